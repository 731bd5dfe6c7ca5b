#pragma once
#include "sgfx/Export.h"
#include "sgfx/Material.h"
#include "sgfx/Texture.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <variant>

namespace sgfx {

class ShaderProgram;

/// OSG-style inheritance flags. A parent's Override beats a child's plain value; a child's
/// Protected value beats the parent's Override.
enum StateFlags : std::uint8_t { Inherit = 0, Override = 1, Protected = 2 };

/// One attribute of a StateSet: unset (inherited), or a value with its StateFlags.
template <class T> struct StateAttr {
    std::optional<T> value;
    std::uint8_t flags = Inherit;
    void set(T v, std::uint8_t f = Inherit) {
        value = std::move(v);
        flags = f;
    }
    void clear() { value.reset(), flags = Inherit; }
    explicit operator bool() const { return value.has_value(); }
    bool operator==(const StateAttr&) const = default;
};

enum class BlendMode : std::uint8_t { Off, Alpha, Premultiplied, Additive, Multiply };
enum class CompareFunc : std::uint8_t {
    Never,
    Less,
    Equal,
    LessEqual,
    Greater,
    NotEqual,
    GreaterEqual,
    Always
};
enum class CullFace : std::uint8_t { None, Back, Front };
enum class RenderBin : std::uint8_t { Opaque, Transparent };

/// Depth test, depth writes and the comparison, as a pass or a StateSet sets them.
struct SGFX_API DepthState {
    bool test = true;
    bool write = true;
    CompareFunc func = CompareFunc::Less;
    bool operator==(const DepthState&) const = default;
};

/// How a blended item is ordered and drawn in the transparent stage (OSG's render bin details,
/// three.js's renderOrder). Items are drawn by ascending `order`, then back to front by the view
/// depth of their bound's centre plus `depthBias`, then in cull order.
struct SGFX_API TransparencyDetails {
    int order = 0;              ///< explicit order: lower is drawn first, whatever the depths
    float depthBias = 0.0f;     ///< metres added to the sort depth (positive: drawn earlier, as if farther)
    bool twoPass = true;        ///< double-sided items (CullFace::None): back faces first, then front faces
    bool sortTriangles = false; ///< re-sort the triangles back to front (self-overlapping meshes)
    float resortAngle = 5.0f;   ///< degrees the view direction may turn before triangles are re-sorted
    bool writeDepth = false;    ///< "depth-writing glass": later items and depth readers see it
    bool operator==(const TransparencyDetails&) const = default;

    /// Throws std::invalid_argument naming the field (non-finite bias, angle outside [0, 180]).
    void validate() const;
};

using UniformValue = std::variant<int, float, glm::vec2, glm::vec3, glm::vec4, glm::mat3, glm::mat4>;

/// The attributes a StateSet may set and a ResolvedState holds, each with its flags.
struct SGFX_API StateAttributes {
    StateAttr<std::shared_ptr<Material>> material;
    StateAttr<std::shared_ptr<ShaderProgram>> program; ///< foreign shader; built-in material when unset
    StateAttr<BlendMode> blend;
    StateAttr<DepthState> depth;
    StateAttr<CullFace> cullFace;
    StateAttr<RenderBin> renderBin;
    StateAttr<TransparencyDetails> transparency;
    /// Named uniforms and sampler textures for foreign shaders (and effect tuning).
    std::map<std::string, StateAttr<UniformValue>, std::less<>> uniforms;
    std::map<std::string, StateAttr<std::shared_ptr<Texture>>, std::less<>> textures;
    /// Same values and flags (resources compared by identity).
    bool operator==(const StateAttributes&) const = default;
};

/// Render state of a node and its subtree (OSG's StateSet): material, textures, blending, depth,
/// culling, render bin, a foreign program. Unset attributes are inherited from above.
class SGFX_API StateSet : public StateAttributes {
public:
    static std::shared_ptr<StateSet> create() { return std::make_shared<StateSet>(); }

    void setUniform(std::string name, UniformValue v, std::uint8_t flags = Inherit) {
        uniforms[std::move(name)].set(std::move(v), flags);
    }
    void setTexture(std::string samplerName, std::shared_ptr<Texture> t, std::uint8_t flags = Inherit) {
        textures[std::move(samplerName)].set(std::move(t), flags);
    }
};

/// The state in force at a point of the graph: every attribute resolved, with its flags kept so
/// deeper StateSets merge correctly.
struct SGFX_API ResolvedState : StateAttributes {
    static ResolvedState defaults();
    ResolvedState merged(const StateSet& child) const;

    const std::shared_ptr<Material>& materialOrNull() const {
        static const std::shared_ptr<Material> none;
        return material.value ? *material.value : none;
    }
    BlendMode blendMode() const { return blend.value.value_or(BlendMode::Off); }
    bool transparent() const;
};

} // namespace sgfx

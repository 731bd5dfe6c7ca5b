#pragma once
#include "sgfx/Effect.h"
#include "sgfx/Export.h"
#include "sgfx/ProgramKey.h"
#include "sgfx/StateSet.h"

#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

namespace sgfx {

namespace gl {
class Program;
}

/// The application's own GLSL 450 program. sgfx feeds it:
///  attributes: location 0 position, 1 normal, 2 tangent, 3 texcoord, 4 colour
///  uniforms:   mat4 sgfx_model, sgfx_normalMatrix (mat3) and the std140 block `SgfxFrame`
///              (declare it with `#include`-free text from docs, or leave it: the wrap adds it)
/// Its fragment `main` is renamed and wrapped so active effects apply to its colour output.
class SGFX_API ShaderProgram {
public:
    static std::shared_ptr<ShaderProgram> create(std::string name, std::string vertexSource,
                                                 std::string fragmentSource) {
        auto p = std::make_shared<ShaderProgram>();
        p->name = std::move(name);
        p->vertexSource = std::move(vertexSource);
        p->fragmentSource = std::move(fragmentSource);
        return p;
    }
    std::string name;
    std::string vertexSource;
    std::string fragmentSource;
};

/// A compile or link failure; what() names the base shader, the snippets and the original line.
class SGFX_API ShaderError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// A linked program with the names of the sources it was composed from (for error messages).
struct SGFX_API ComposedProgram {
    std::string vertex;
    std::string geometry; ///< optional
    std::string fragment; ///< may be empty for a transform-feedback-only program
    /// Transform feedback outputs, captured into one buffer (interleaved) or one buffer each.
    std::vector<std::string> feedbackVaryings;
    bool feedbackInterleaved = true;
    /// Per stage: source-string numbers used in `#line` directives → names
    /// ("blinn_phong.frag", "debug_tint.colorCode").
    std::vector<std::string> vertexSources;
    std::vector<std::string> geometrySources;
    std::vector<std::string> fragmentSources;
    std::string description; ///< "blinn_phong + [debug_tint]"
    /// A compute program: this stage alone (the others empty); its names are vertexSources'.
    std::string compute = {};
};

/// A material shader written once with hook markers (`// @sgfx:NAME` lines). With a geometry
/// stage, the vertex hooks (`vertex_decl`, `vertex`) live in the geometry stage, which is where
/// the world positions are made (particle sprites); the vertex stage then has no hooks.
struct SGFX_API BaseShader {
    std::string name;
    std::string vertexName, vertexSource;
    std::string fragmentName, fragmentSource;
    std::string geometryName = {}, geometrySource = {};
    std::vector<std::string> feedbackVaryings = {};
    bool feedbackInterleaved = true;
};

/// What a built-in material variant contains; each bit becomes a #define (SGFX_BASE_MAP, ...)
/// so a plain material carries no texture fetch, no unused varying and no `discard`. A new bit
/// goes into kAllMaterialFeatures too (it must fit ProgramKey::Features).
enum MaterialFeature : std::uint64_t {
    FeatureBaseMap = 1u << 0,
    FeatureAlphaMap = 1u << 1,
    FeatureNormalMap = 1u << 2,
    FeatureVertexColor = 1u << 3,
    FeatureNormals = 1u << 4,
    FeatureTangents = 1u << 5,
    FeatureTexCoords = 1u << 6,
    FeatureAlphaMask = 1u << 7,
    FeatureBlend = 1u << 8,
    FeatureSpecular = 1u << 9,
    FeatureMetallicRoughness = 1u << 10, ///< ShadingModel::MetallicRoughness
    FeatureVertexLighting = 1u << 11,    ///< Gouraud: lights summed per vertex (Renderer::Options::lighting)
    FeatureWorldPosition = 1u << 16,     ///< interpolate the world position (snippets, point lights, ...)
    FeaturePointLights = 1u << 17,       ///< some light of the view has a position
    /// How the output is blended (with FeatureBlend; none of them = straight alpha), so colour
    /// effects can treat premultiplied, additive and multiplicative output correctly.
    FeatureBlendPremultiplied = 1u << 18,
    FeatureBlendAdditive = 1u << 19,
    FeatureBlendMultiply = 1u << 20,
    FeatureBlendKindMask = FeatureBlendPremultiplied | FeatureBlendAdditive | FeatureBlendMultiply,
    /// G-buffer variant: writes the view-space normal (location 0), linear view depth (1) and
    /// view-space position (2) instead of a colour, keeping cut-outs and normal maps.
    FeatureGBuffer = 1u << 21,
    FeatureMetalRoughMap = 1u << 22, ///< metallic-roughness texture
    FeatureOcclusionMap = 1u << 23,
    FeatureEmissiveMap = 1u << 24,
    FeatureTexCoords1 = 1u << 25,  ///< a second texture coordinate set is interpolated
    FeatureUvTransform = 1u << 26, ///< some map reads set 1 or a transformed set (per-map uniforms)
    FeatureInstanced = 1u << 27,   ///< Geometry::instances: per-instance matrices at locations 6..9
    /// Automatic instance batch (RendererOptions::autoInstancing): the model matrix of instance i
    /// is sgfx_batchModels[sgfx_batchBase + i], a shader storage buffer at kBatchBinding.
    FeatureBatched = 1u << 28,
    FeatureUnlit = 1ull << 29, ///< ShadingModel::Unlit (KHR_materials_unlit)
    /// KHR_materials_clearcoat: the layer and its three maps (each sampled when the material has it).
    FeatureClearcoat = 1ull << 30,
    /// KHR_materials_specular: F0 and F90 of the dielectric part from the extension and its two maps.
    FeatureSpecularExt = 1ull << 31,
    /// Some light of the view has a range, a spot cone or inverse-square falloff: the light
    /// loop evaluates KHR_lights_punctual's attenuation (without it, sgfx 0.1's loop).
    FeatureLightAttenuation = 1ull << 32,
    /// More lights than RendererOptions::maxUnrolledLights: every light comes from a shader
    /// storage buffer, and each fragment shades the lights without a range plus its screen
    /// tile's list of ranged ones (per-vertex lighting: every light). SGFX_LIGHT_COUNT is 0.
    FeatureLightList = 1ull << 33,
    /// KHR_materials_transmission (+ _volume, _ior): the surface samples the copy of the opaque
    /// scene along its refracted ray (SGFX_UNIT_TRANSMISSION); its two maps as the extensions'.
    FeatureTransmission = 1ull << 34,
    /// Geometry::skin: joint indices and weights at locations 10..13, joint matrices in a storage
    /// buffer (kJointsBinding); shaders/pose.glsl skins before the model matrix.
    FeatureSkinned = 1ull << 35,
    /// Geometry::morphTargets: displacements and weights in storage buffers (kMorphBinding,
    /// kMorphWeightsBinding), read by gl_VertexID; applied before skinning.
    FeatureMorphed = 1ull << 36,
    FeaturePoseMask = FeatureSkinned | FeatureMorphed,
    /// RendererOptions::debugConstantShading (profiling only): the material writes its diffuse
    /// colour alone. A view's bit, added at draw time: never in an item's ProgramKey.
    FeatureDebugConstant = 1ull << 40,
    /// Bits 12..15: number of lights (0..8), compiled in so the light loop unrolls.
    FeatureLightCountShift = 12,
    FeatureLightCountMask = 0xfu << 12,
};

/// Every MaterialFeature bit.
inline constexpr FeatureMask kAllMaterialFeatures =
    FeatureBaseMap | FeatureAlphaMap | FeatureNormalMap | FeatureVertexColor | FeatureNormals |
    FeatureTangents | FeatureTexCoords | FeatureAlphaMask | FeatureBlend | FeatureSpecular |
    FeatureMetallicRoughness | FeatureVertexLighting | FeatureLightCountMask | FeatureWorldPosition |
    FeaturePointLights | FeatureBlendKindMask | FeatureGBuffer | FeatureMetalRoughMap | FeatureOcclusionMap |
    FeatureEmissiveMap | FeatureTexCoords1 | FeatureUvTransform | FeatureInstanced | FeatureBatched |
    FeatureUnlit | FeatureClearcoat | FeatureSpecularExt | FeatureLightAttenuation | FeatureLightList |
    FeatureTransmission | FeatureSkinned | FeatureMorphed;
// A program key holds every feature bit (the mask fits only if each bit does).
static_assert(ProgramKey::Features.fits(kAllMaterialFeatures),
              "a MaterialFeature bit is outside ProgramKey::Features");

constexpr unsigned kBatchBinding = 7;      ///< shader storage binding of FeatureBatched's matrices
constexpr unsigned kLightsBinding = 8;     ///< shader storage binding of FeatureLightList's lights
constexpr unsigned kLightTilesBinding = 9; ///< and of its per-tile light lists
constexpr unsigned kJointsBinding = 10;    ///< FeatureSkinned's joint matrices
constexpr unsigned kMorphBinding = 11;     ///< FeatureMorphed's displacements
constexpr unsigned kMorphWeightsBinding = 12; ///< and its weights

class Material;
class Geometry;

/// Builds program variants for (base shader, features, snippets) and caches them.
class SGFX_API ShaderComposer {
public:
    ShaderComposer();
    ~ShaderComposer();

    /// Text only (no GL): testable anywhere.
    static ComposedProgram composeBuiltin(const BaseShader& base,
                                          std::span<const ShaderSnippet* const> snippets,
                                          FeatureMask features = 0);
    static std::string featureDefines(FeatureMask features);
    /// The variant a material needs for a geometry (attributes present, textures, mask, blending).
    static FeatureMask featuresFor(const Material* material, const Geometry& geometry, bool blended,
                                   BlendMode blend = BlendMode::Alpha);
    /// FeatureSkinned and FeatureMorphed for a geometry (built-in materials and foreign shaders).
    static FeatureMask poseFeatures(const Geometry& geometry);
    /// The blend-kind bits alone (the only feature bits a foreign shader's wrap uses).
    static FeatureMask blendFeatures(bool blended, BlendMode blend);
    /// Adds FeatureWorldPosition where the variant or its snippets read the world position.
    static FeatureMask withWorldPosition(FeatureMask features, bool hasSnippets);
    static ComposedProgram composeForeign(const ShaderProgram& program,
                                          std::span<const ShaderSnippet* const> snippets,
                                          FeatureMask features = 0);
    /// Rewrites "S:L(C): msg" / "S(L) : msg" driver lines into "name:line: msg".
    static std::string translateLog(std::string_view log, std::span<const std::string> sourceNames);

    /// The built-in Blinn-Phong material.
    static const BaseShader& blinnPhong();
    /// Vertex stage of full-screen passes (Renderer::drawFullscreen): one triangle from
    /// gl_VertexID, `out vec2 v_uv` in [0, 1]; with SGFX_FULLSCREEN_FAR defined it lies on the far
    /// plane (depth 1), so a depth test EQUAL limits a pass to pixels no geometry covered.
    static std::string_view fullscreenVertex();

    /// Compiles on a miss (GL thread). `foreign` null = built-in material.
    gl::Program& program(const ShaderProgram* foreign, std::span<const ShaderSnippet* const> snippets,
                         FeatureMask features = 0);
    gl::Program& program(const BaseShader& base, std::span<const ShaderSnippet* const> snippets,
                         FeatureMask features = 0);

    std::size_t hits() const { return hits_; }
    std::size_t misses() const { return misses_; }
    std::size_t size() const { return cache_.size(); }
    void clear();

private:
    gl::Program& cached(std::string key, std::span<const ShaderSnippet* const> snippets,
                        const std::function<ComposedProgram()>& compose);
    std::unordered_map<std::string, std::unique_ptr<gl::Program>> cache_;
    std::size_t hits_ = 0, misses_ = 0;
};

} // namespace sgfx

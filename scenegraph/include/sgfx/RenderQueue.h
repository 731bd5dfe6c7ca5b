#pragma once
#include "sgfx/Export.h"
#include "sgfx/Math.h"
#include "sgfx/ProgramKey.h"
#include "sgfx/StateSet.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <deque>
#include <unordered_map>
#include <vector>

namespace sgfx {

class Geometry;
class Drawable;
class Node;
class EffectNode;
class ShaderProgram;
class Camera;
class Light;

/// The effects active above an item, ordered by EffectNode::order(); interned per frame so items
/// share one entry. `signature` is equal for sets whose snippets are equal (same program variant):
/// the ProgramKey::Effects id from RenderQueue::programKeys, 0 = no snippet.
struct SGFX_API EffectSet {
    std::vector<const EffectNode*> effects;
    std::uint32_t signature = 0;
};

/// A light as the frame block carries it: world position (w = 1) or direction (w = 0), colour,
/// and what attenuates it (Light's range, cone and falloff).
struct SGFX_API LightInfo {
    glm::vec4 vector{0, 0, 1, 0}; ///< world: direction towards the light (w=0) or position (w=1)
    glm::vec3 color{1.0f};        ///< colour × intensity
    glm::vec3 spotAxis{0, 0, -1}; ///< world, unit: the direction a spot shines
    float range = 0.0f;           ///< 0: unlimited
    /// Spot cone as KHR_lights_punctual's reference code: a = clamp(cos θ · angleScale +
    /// angleOffset, 0, 1), factor a². Other lights: 0 and 1 (factor 1).
    float angleScale = 0.0f, angleOffset = 1.0f;
    bool inverseSquare = false; ///< LightFalloff::InverseSquare
    const Light* source = nullptr; ///< the node it came from (effects find their light by it)
    /// Anything beyond a plain light of sgfx 0.1 (range, cone, inverse square)?
    bool attenuated() const {
        return range > 0.0f || angleScale != 0.0f || angleOffset != 1.0f || inverseSquare;
    }
};

/// One draw of the frame: what, with which state, effects and matrix, and its sort keys.
struct SGFX_API RenderItem {
    const Geometry* geometry = nullptr; ///< one of these two is set
    const Drawable* drawable = nullptr;
    glm::mat4 model{1.0f};
    const ResolvedState* state = nullptr;
    std::uint32_t effectSet = 0; ///< index into RenderQueue::effectSets
    float depth = 0.0f;          ///< view-space distance of the bound's centre along -Z (transparent
                                 /// items: plus TransparencyDetails::depthBias)
    std::int32_t order = 0;      ///< transparent items: TransparencyDetails::order
    std::int8_t depthBucket = 0; ///< floor(log2(depth)): opaque items sort near-to-far by it first
    std::uint32_t sequence = 0;  ///< cull order, keeps sorting stable
    ProgramKey programKey;       ///< equal keys = one program (ids from the queue's programKeys)
    FeatureMask features = 0;    ///< built-in material variant (MaterialFeature bits)
    /// Which faces this item draws (a double-sided transparent item is queued twice: back faces,
    /// then front faces); AsState = as its state's CullFace says.
    enum class Faces : std::uint8_t { AsState, Back, Front } faces = Faces::AsState;
    /// The model matrix mirrors (negative determinant): the winding that counts as front flips
    /// (glTF 2.0, Meshes: the global transform's determinant defines the winding; OpenGL's
    /// glFrontFace), so culling and two-sided lighting stay right.
    bool mirrored = false;

    RenderItem() = default;
    /// Every field but `order` (0) and `faces` (AsState), so a queue builds items in place.
    RenderItem(const Geometry* g, const Drawable* d, const glm::mat4& m, const ResolvedState* s,
               std::uint32_t effects, float viewDepth, std::int8_t bucket, std::uint32_t seq, ProgramKey key,
               FeatureMask featureBits)
        : geometry(g)
        , drawable(d)
        , model(m)
        , state(s)
        , effectSet(effects)
        , depth(viewDepth)
        , depthBucket(bucket)
        , sequence(seq)
        , programKey(key)
        , features(featureBits)
        , mirrored(isMirroring(m)) {}

    /// det(upper 3x3) < 0.
    static bool isMirroring(const glm::mat4& m) { return glm::determinant(glm::mat3(m)) < 0.0f; }

    const ShaderProgram* program() const;
    const Node& node() const; ///< the geometry or drawable
    BoundingSphere worldBound() const;
};

/// Everything the cull traversal found for one view: items by stage, lights, sub-cameras.
class SGFX_API RenderQueue {
public:
    std::vector<RenderItem> opaque; ///< drawn first; by octave of depth, program, material, mesh, depth
    /// Transmissive items (Material::transmission, blending off): drawn after the opaque items
    /// and the AfterOpaque passes, sampling a copy of what is drawn so far, and before the
    /// Transparent passes and the transparent items. Sorted like `transparent`.
    std::vector<RenderItem> transmissive;
    std::vector<RenderItem> transparent; ///< drawn last; sorted by order, then back to front
    /// Blended items an effect above them draws itself (EffectNode::drawsBlended), e.g. an
    /// order-independent transparency pass; not drawn by the main pass. Cull order.
    std::vector<RenderItem> claimed;
    std::vector<EffectSet> effectSets{EffectSet{}}; ///< [0] = no effect
    std::vector<LightInfo> lights;
    glm::vec3 ambientLight{0.0f};
    std::deque<ResolvedState> states; ///< stable addresses for items' state pointers
    std::vector<Camera*> subCameras;  ///< nested render-to-texture cameras, drawn first
    /// Ids of the items' program keys (foreign programs, drawable base shaders, snippet
    /// signatures): dense for this view and frame, cleared with the queue.
    ProgramKeyTable programKeys;

    void clear();
    void sort();
    std::size_t size() const {
        return opaque.size() + transmissive.size() + transparent.size() + claimed.size();
    }
    std::uint32_t internEffectSet(std::vector<const EffectNode*> effects);
    /// Keeps `state` in `states` and returns its address, or the address of an equal state
    /// already kept this frame: paths that resolve to the same state share one pointer, so
    /// their items batch and draw without a state change (windows of differently coloured
    /// buildings).
    const ResolvedState* internState(ResolvedState&& state);

private:
    std::unordered_multimap<std::size_t, const ResolvedState*> stateIndex_;
    struct SortKey {
        std::uint64_t primary;
        std::uint32_t index;
    };
    std::vector<SortKey> sortKeys_, sortScratchKeys_;
    std::vector<std::uint64_t> programRanks_, materialRanks_, meshRanks_, rankScratch_;
    std::vector<std::uint32_t> meshCounts_;
    void radixSort(std::vector<SortKey>& keys);
    void sortBackToFront(std::vector<RenderItem>& items);
    std::vector<RenderItem> sortScratch_;
};

} // namespace sgfx

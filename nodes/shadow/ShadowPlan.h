#pragma once
// Internal to ShadowNode: one view's sun shadow, planned in setupFrame (no GL) and read by the
// cascade passes and, once they ran, by applyUniforms.
#include <sgfx/RenderQueue.h>
#include <sgfx/nodes/shadow/ShadowNode.h>

#include <glm/glm.hpp>

#include <array>
#include <memory>
#include <vector>

namespace sgfx {

class FrameSetup;

/// One spot light's map.
struct ShadowNode::SpotPlan {
    int light = -1; ///< its index among the view's lights
    glm::mat4 view{1.0f}, projection{1.0f};
    glm::mat4 matrix{1.0f}; ///< world to atlas (divide by w)
    glm::vec4 tileRect{0.0f}, position{0.0f}, axis{0.0f};
    glm::vec4 params{0.0f}; ///< near, far, texel per metre of depth
    RenderQueue queue;      ///< what the cull from the spot found
    std::vector<RenderItem> casters;
};

/// Cascades fitted to the camera, their tiles in the atlas, the matrices, and each map's casters;
/// the spots' maps after them.
struct ShadowNode::Plan {
    ShadowFrameInfo info;
    glm::ivec2 atlasSize{1};
    std::vector<glm::ivec4> tiles{glm::ivec4(0, 0, 1, 1)};
    glm::mat4 lightView{1.0f}; ///< V_L (a rotation)
    std::vector<glm::mat4> projections;
    /// Light space (V_L·P) to atlas per cascade: xy·scale (xy) + offset (zw); and to the map's
    /// depth, the same for every cascade: z·x + y.
    std::array<glm::vec4, shadow::kMaxCascades> cascadeMaps{};
    glm::vec2 depthMap{1.0f, 0.0f};
    std::array<glm::vec4, shadow::kMaxCascades> tileRects{};
    glm::mat3 rotation{1.0f};
    glm::vec4 splits{0.0f}, bandStart{0.0f}, texels{0.0f};
    glm::vec4 light{0.0f};   ///< xyz towards the sun, w: 1 / depth range
    RenderQueue casterQueue; ///< what the cull from the light found (owns the casters' states)
    std::vector<std::vector<RenderItem>> casters; ///< per cascade
    std::vector<SpotPlan> spots;
};

/// The plan the passes last ran, for applyUniforms and lastFrame (one view at a time: a nested
/// view finishes before its parent's setupFrame).
struct ShadowNode::Shared {
    std::shared_ptr<const Plan> current;
};

namespace shadow {
/// Plans `node`'s maps for the view being set up: the sun's cascades when the sun is among the
/// view's lights and gives light, a map per such spot; nothing (a 1×1 atlas no pass draws) else.
std::shared_ptr<ShadowNode::Plan> planShadows(const FrameSetup& f, const ShadowNode& node);
} // namespace shadow

} // namespace sgfx

#pragma once
// Conservative occlusion culling's CPU half (RendererOptions::occlusionCulling; no GL here): the
// max-depth pyramid of a read-back depth buffer, the screen rectangle and nearest depth of a world
// bound, the occlusion test, and the per-view memory of what was visible. Two-phase hierarchical Z
// after Haar and Aaltonen, "GPU-driven rendering pipelines" (SIGGRAPH 2015), done on the CPU.
#include "sgfx/Math.h"
#include "sgfx/RenderQueue.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <memory>
#include <span>
#include <unordered_set>
#include <vector>

namespace sgfx::render {

/// Window depths ([0, 1], GL's default depth range), level 0 at full size, bottom row first (as
/// glReadPixels returns them); level k+1 holds the maximum of 2×2 texels of level k (ceil sizes).
class DepthPyramid {
public:
    /// From `depth` (width × height values). Throws std::invalid_argument on a size mismatch.
    void build(std::span<const float> depth, int width, int height);
    int levels() const { return int(levels_.size()); }
    int width(int level) const { return levels_[std::size_t(level)].width; }
    int height(int level) const { return levels_[std::size_t(level)].height; }
    float at(int level, int x, int y) const {
        const Level& l = levels_[std::size_t(level)];
        return l.depth[std::size_t(y) * std::size_t(l.width) + std::size_t(x)];
    }
    /// The largest depth over pixels [x0, x1] × [y0, y1] of level 0 (inclusive, inside the
    /// image), read from the coarsest level where the rectangle covers at most 2 × 2 texels.
    float maxOver(int x0, int y0, int x1, int y1) const;

private:
    struct Level {
        int width = 0, height = 0;
        std::vector<float> depth;
    };
    std::vector<Level> levels_;
};

/// A world bound on the screen: the pixels its fragments can cover and their nearest depth.
struct ScreenRect {
    bool mayBeVisible = true; ///< a corner behind the near plane (or outside the view): never culled
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0; ///< inclusive pixels, clamped to the image
    float nearDepth = 0.0f;             ///< the smallest window depth of the 8 corners
};

/// The axis-aligned cube around `world` (8 corners) through `viewProjection` into a width × height
/// image, widened by a pixel on each side (rasterisation covers pixel centres inside the hull).
ScreenRect screenRect(const glm::mat4& viewProjection, const BoundingSphere& world, int width, int height);

/// The margin by which a bound must lie behind the pyramid to be culled: a few units in the last
/// place of depths near 1, above the rasteriser's depth interpolation error.
constexpr float kOcclusionDepthMargin = 1.0f / (1 << 21);

/// Culled iff the bound's nearest depth lies behind the largest depth over its rectangle. With
/// `unsafeMinDepth` the rectangle's smallest depth is used instead (a deliberately wrong test that
/// drops partly visible items; RendererOptions::OcclusionCulling::DebugUnsafeMinDepth).
bool occluded(const DepthPyramid& pyramid, const ScreenRect& rect, std::span<const float> level0 = {},
              bool unsafeMinDepth = false);

/// Identifies an item across frames: its geometry or drawable, model matrix and faces.
std::uint64_t occlusionKey(const RenderItem& item);

/// Per view (camera): the items seen last frame, drawn first as this frame's occluders, and the
/// scratch the split keeps for its capacity.
struct OcclusionState {
    std::weak_ptr<const Node> owner;
    std::unordered_set<std::uint64_t> visible, next;
    std::vector<RenderItem> first, rest;
    std::vector<std::uint64_t> firstKeys, restKeys;
    std::vector<float> depth;
    DepthPyramid pyramid;
};

} // namespace sgfx::render

namespace sgfx::render {

/// Whether every opaque item's depth writes only ever lower the depth (test on, Less, LessEqual or
/// Equal, or writes off), so a subset of them leaves a depth everywhere >= the final one.
bool depthIsMonotone(std::span<const RenderItem> opaque);

/// Whether an item may be culled: a geometry (drawables draw what they like) depth-tested with
/// Less or LessEqual.
bool occlusionCandidate(const RenderItem& item);

} // namespace sgfx::render

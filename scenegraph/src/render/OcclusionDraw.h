#pragma once
// The opaque items drawn with conservative occlusion culling (RendererOptions::occlusionCulling).
#include "render/Occlusion.h"
#include "sgfx/Renderer.h"

#include <cstddef>
#include <span>
#include <vector>

namespace sgfx::render {

struct OcclusionResult {
    std::size_t tested = 0, culled = 0;
};

/// Draws `opaque` (in this order within each phase) into the bound single-sample `draw` target:
/// last frame's visible items, then, after reading the depth back, the others not hidden behind
/// it (culled ones appended to `culledOut`). `viewProjection`: the matrix the items are drawn with.
OcclusionResult drawOpaqueTwoPhase(Renderer& r, const gl::RenderTarget& draw,
                                   std::span<const RenderItem> opaque, const glm::mat4& viewProjection,
                                   OcclusionState& state, bool unsafeMinDepth,
                                   std::vector<RenderItem>* culledOut);

} // namespace sgfx::render

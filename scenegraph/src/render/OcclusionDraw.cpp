// Conservative occlusion culling's GL half (RendererOptions::occlusionCulling): the opaque items
// in two phases with a depth read-back between them (docs/performance.md, "Occlusion culling").
#include "render/OcclusionDraw.h"

#include "sgfx/gl/Objects.h"

#include <sgfx_glad/gl.h>

namespace sgfx::render {

OcclusionResult drawOpaqueTwoPhase(Renderer& r, const gl::RenderTarget& draw,
                                   std::span<const RenderItem> opaque, const glm::mat4& viewProjection,
                                   OcclusionState& state, bool unsafeMinDepth,
                                   std::vector<RenderItem>* culledOut) {
    OcclusionResult result;
    // Phase 1: what was seen last frame, drawn first as this frame's occluders. Which items these
    // are only decides the order; the test below never trusts last frame.
    state.first.clear();
    state.rest.clear();
    for (const RenderItem& it : opaque)
        (state.visible.count(occlusionKey(it)) ? state.first : state.rest).push_back(it);
    state.next.clear();
    if (state.first.empty()) { // nothing to test against (the first frame): every item drawn
        r.drawItems(opaque);
        for (const RenderItem& it : opaque)
            state.next.insert(occlusionKey(it));
        std::swap(state.visible, state.next);
        return result;
    }
    r.drawItems(state.first);
    // Phase 2: the depth of a subset of this frame's items, everywhere >= the final depth, as a
    // max pyramid. GL: a direct read of the depth texture (DSA, no binding to restore); it waits
    // for the rasteriser, the price of the test.
    const std::size_t n = std::size_t(draw.width) * std::size_t(draw.height);
    state.depth.resize(n);
    glGetTextureImage(draw.depth.get(), 0, GL_DEPTH_COMPONENT, GL_FLOAT, GLsizei(n * sizeof(float)),
                      state.depth.data());
    state.pyramid.build(state.depth, draw.width, draw.height);
    const auto hidden = [&](const RenderItem& it) {
        return occlusionCandidate(it) &&
               occluded(state.pyramid, screenRect(viewProjection, it.worldBound(), draw.width, draw.height),
                        state.depth, unsafeMinDepth);
    };
    // The occluders that are now hidden behind the others are not drawn first next frame.
    for (const RenderItem& it : state.first)
        if (!hidden(it)) state.next.insert(occlusionKey(it));
    std::size_t kept = 0;
    for (const RenderItem& it : state.rest) {
        result.tested += occlusionCandidate(it) ? 1 : 0;
        if (hidden(it)) {
            ++result.culled;
            if (culledOut) culledOut->push_back(it);
            continue;
        }
        state.next.insert(occlusionKey(it));
        state.rest[kept++] = it;
    }
    state.rest.resize(kept);
    // Phase 3: the survivors.
    r.drawItems(state.rest);
    std::swap(state.visible, state.next);
    return result;
}

} // namespace sgfx::render

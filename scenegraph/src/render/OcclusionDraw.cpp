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
    state.firstKeys.clear();
    state.restKeys.clear();
    for (const RenderItem& it : opaque) {
        const std::uint64_t key = occlusionKey(it);
        const bool seen = state.visible.count(key) != 0;
        (seen ? state.first : state.rest).push_back(it);
        (seen ? state.firstKeys : state.restKeys).push_back(key);
    }
    state.next.clear();
    if (state.first.empty()) { // nothing to test against (the first frame): every item drawn
        r.drawItems(opaque);
        state.next.insert(state.restKeys.begin(), state.restKeys.end());
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
    for (std::size_t i = 0; i < state.first.size(); ++i)
        if (!hidden(state.first[i])) state.next.insert(state.firstKeys[i]);
    std::size_t kept = 0;
    for (std::size_t i = 0; i < state.rest.size(); ++i) {
        const RenderItem& it = state.rest[i];
        result.tested += occlusionCandidate(it) ? 1 : 0;
        if (hidden(it)) {
            ++result.culled;
            if (culledOut) culledOut->push_back(it);
            continue;
        }
        state.next.insert(state.restKeys[i]);
        if (kept != i) state.rest[kept] = it;
        ++kept;
    }
    state.rest.resize(kept);
    // Phase 3: the survivors.
    r.drawItems(state.rest);
    std::swap(state.visible, state.next);
    return result;
}

} // namespace sgfx::render

#pragma once
// The renderer's redundant-state filter (private to the renderer): the program, blend, cull and
// depth state and the texture units (texture and sampler object) it last set, so an unchanged
// value costs no GL call. Every real change is counted as a state change (FrameStats::stateChanges).
#include "render/TextureUnits.h"
#include "sgfx/StateSet.h"

#include <glm/glm.hpp>

#include <array>
#include <cstddef>
#include <utility>
#include <vector>

namespace sgfx::gl {

class StateCache {
public:
    static constexpr std::size_t kUnits = render::kHandedOutUnits; ///< units the renderer hands out
    /// Units tracked: the renderer's and a drawable's own (buffer textures, volume data).
    static constexpr std::size_t kTrackedUnits = render::kTrackedUnits;

    /// Where real changes are counted (the renderer's FrameStats::stateChanges).
    explicit StateCache(std::size_t& stateChanges)
        : stateChanges_(&stateChanges) {}

    /// glUseProgram unless `program` is current; true when it changed (counted).
    bool useProgram(unsigned program);
    /// Binds `texture` to `unit`, read through sampler object `sampler`; 0 (the default) reads it
    /// with the texture's own sampling state, so a sampler object left on the unit (a comparison
    /// sampler) is unbound. Texture and sampler each cost a GL call only when they change.
    void bindTexture(unsigned unit, unsigned texture, unsigned sampler = 0);
    /// Only `unit`'s sampler object (0: none), glBindSampler when it changes (counted).
    void bindSampler(unsigned unit, unsigned sampler);
    void setBlend(BlendMode mode);
    /// Culls `face`, with the clockwise winding as the front one when `mirrored` (an item whose
    /// model matrix has a negative determinant). The winding is set even without culling: it
    /// decides gl_FrontFacing, which two-sided lighting reads.
    void setCull(CullFace face, bool mirrored = false);
    /// Only the winding (the cull face stays): clockwise front faces when `mirrored`.
    void setFrontFace(bool mirrored);
    /// Whether the winding last set is the mirrored (clockwise) one.
    bool mirroredWinding() const { return clockwiseFront_ == 1; }
    void setDepth(const DepthState& depth);
    /// Draws into `fbo` over (0, 0, size); sRGB encoding on write for sRGB targets.
    void bindFramebuffer(unsigned fbo, glm::ivec2 size, bool srgb = true);
    unsigned framebuffer() const { return framebuffer_; }
    glm::ivec2 viewport() const { return viewport_; }
    void setColourMask(bool on);
    /// glBlendFunci per attachment (source, destination factors as GL enums); the next setBlend
    /// sets every attachment again.
    void setBlendPerAttachment(const std::vector<std::pair<unsigned, unsigned>>& factors);
    /// A viewport of part of the bound framebuffer (x, y, w, h); the next bindFramebuffer sets the
    /// whole target again, whichever framebuffer it binds.
    void setViewport(const glm::ivec4& rect);
    /// Scissor test on `rect` (x, y, w, h), or off when `on` is false.
    void setScissor(bool on, const glm::ivec4& rect = glm::ivec4(0));
    /// Draws into `fbo` over (0, 0, size) with blending off, keeping the sRGB setting (a drawable's
    /// own off-screen step); endOffscreen() returns to the framebuffer, viewport and blending that
    /// were current (a blend mode or per-attachment factors alike). Not nested.
    void beginOffscreen(unsigned fbo, glm::ivec2 size);
    void endOffscreen();
    /// The depth state was set behind the cache (glDepthMask before a clear).
    void forgetDepth() { depthKnown_ = false; }
    /// Forgets everything: GL state was changed behind the cache (a pass, another library). The
    /// units' sampler objects become unknown: the next texture or sampler bind first unbinds the
    /// sampler objects of every tracked unit (one glBindSamplers).
    void invalidate();

private:
    unsigned program_ = 0;
    int blend_ = -1;
    int cull_ = -1;
    int clockwiseFront_ = -1;
    DepthState depth_{};
    bool depthKnown_ = false;
    std::array<unsigned, kTrackedUnits> units_{};
    std::array<unsigned, kTrackedUnits> samplers_{}; // sampler objects, valid while samplersKnown_
    bool samplersKnown_ = false;                     // false: whatever was bound behind the cache
    unsigned framebuffer_ = ~0u;
    glm::ivec2 viewport_{-1};
    int srgb_ = -1, colourMask_ = -1, scissor_ = -1;
    glm::ivec4 scissorRect_{0};
    struct Offscreen {
        unsigned framebuffer = ~0u;
        glm::ivec4 viewport{0}; // x, y, w, h
        bool known = false;     // framebuffer and viewport were the cache's (else queried)
        bool blend = false;     // blending was on
        int blendState = -1;    // the cache's blend_ when the target began
    } offscreen_;
    std::size_t* stateChanges_;
};

} // namespace sgfx::gl

#pragma once
// Per-camera anti-aliasing state and steps of Renderer::renderView (private to the renderer).
#include "sgfx/Camera.h"
#include "sgfx/gl/Objects.h"

#include <glm/glm.hpp>

#include <memory>
#include <string>
#include <vector>

namespace sgfx {
class Renderer;
}

namespace sgfx::aa {

struct ViewState {
    std::weak_ptr<Node> owner;
    AntiAliasing settings;
    int samples = 1; // MSAA samples in use (clamped)
    gl::RenderTarget msaa, ssaa;
    gl::TextureObject copy; // the finished image, read by FXAA and TAA
    int copyWidth = 0, copyHeight = 0;
    unsigned copyFormat = 0;
    gl::FramebufferObject fbo;
    gl::TextureObject luma; // FXAA: perceptual luma, R16F
    gl::FramebufferObject lumaFbo;
    int lumaWidth = 0, lumaHeight = 0;
    gl::TextureObject stencil; // FXAA: the edge pixels
    int stencilWidth = 0, stencilHeight = 0;
    gl::TextureObject smaaEdges, smaaWeights; // SMAA: RG8 edges (bilinear), RGBA16F weights
    gl::FramebufferObject smaaEdgesFbo, smaaWeightsFbo;
    gl::TextureObject smaaArea, smaaSearch, smaaDiagonal; // SMAA's look-up textures (sgfx/SmaaTextures.h)
    int smaaWidth = 0, smaaHeight = 0;
    gl::TextureObject history[2]; // TAA and SMAA T2x, linear RGBA16F
    int historyWidth = 0, historyHeight = 0, historyIndex = 0;
    glm::mat4 jitter{1.0f};
    glm::mat4 viewProjection{1.0f}, previousViewProjection{1.0f}; // without jitter
    glm::mat4 previousView{1.0f};
    std::uint64_t epoch = ~0ull;
    std::uint32_t frames = 0; // TAA frames accumulated since the last reset
    std::uint32_t sequence = 0;
    bool warned = false; // the MSAA clamp was reported for these settings
};

// Chooses the draw target's sample count, clamps MSAA to the driver's limit (with a warning)
// and computes TAA's jitter for this frame; `viewProjection` is without jitter. The jitter follows
// `frameNumber` when it is set (1, 2, ...: every channel of a frame, on every cluster rank, jitters
// alike), else a count of the view's own frames.
void begin(ViewState& s, const Camera& camera, const glm::mat4& viewProjection, int width, int height,
           std::uint64_t frameNumber, std::vector<std::string>& warnings);
// Where the view is drawn: the multisample or supersampled target, or `target` itself.
gl::RenderTarget& drawTarget(ViewState& s, gl::RenderTarget& target);
// Multisample resolve or supersample downsample of colour and depth into `to`.
void resolve(Renderer& r, ViewState& s, gl::RenderTarget& from, gl::RenderTarget& to);
// FXAA, SMAA or TAA on the finished single-sample image.
void finish(Renderer& r, ViewState& s, gl::RenderTarget& target);

// The i-th element (1-based) of the Halton sequence in `base`.
float halton(std::uint32_t index, std::uint32_t base);

} // namespace sgfx::aa

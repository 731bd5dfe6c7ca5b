#include "AntiAliasing.h"

#include "EmbeddedShaders.h"
#include "sgfx/Renderer.h"
#include "sgfx/SmaaTextures.h"

#include <glm/gtc/matrix_transform.hpp>
#include <sgfx_glad/gl.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <string>

namespace sgfx::aa {

namespace {

BaseShader fullscreenBase(const char* name, const char* fragment) {
    return BaseShader{name, "blit.vert", std::string(shaders::embedded("blit.vert")), fragment,
                      std::string(shaders::embedded(fragment))};
}

gl::Program& fullscreenProgram(Renderer& r, const BaseShader& base, const ShaderSnippet* defines = nullptr) {
    if (defines) return r.composer().program(base, std::array{defines}, 0);
    return r.composer().program(base, {}, 0);
}

// The full-screen programs of anti-aliasing, their base shaders built once (thread-safe).
enum class Stage {
    Downsample,
    Resolve,
    FxaaLuma,
    FxaaEdges,
    Fxaa,
    TaaResolve,
    SmaaEdgesLuma, // the three edge detectors in SmaaEdge's order
    SmaaEdgesColour,
    SmaaEdgesDepth,
    SmaaWeights,
    SmaaBlend
};
const BaseShader& base(Stage stage) {
    static const std::array<BaseShader, 11> bases = {
        fullscreenBase("aa_downsample", "aa_downsample.frag"),
        fullscreenBase("aa_resolve", "aa_resolve.frag"),
        fullscreenBase("fxaa_luma", "fxaa_luma.frag"),
        fullscreenBase("fxaa_edges", "fxaa_edges.frag"),
        fullscreenBase("fxaa", "fxaa.frag"),
        fullscreenBase("taa_resolve", "taa_resolve.frag"),
        fullscreenBase("smaa_edges_luma", "smaa_edges_luma.frag"),
        fullscreenBase("smaa_edges_colour", "smaa_edges_colour.frag"),
        fullscreenBase("smaa_edges_depth", "smaa_edges_depth.frag"),
        fullscreenBase("smaa_weights", "smaa_weights.frag"),
        fullscreenBase("smaa_blend", "smaa_blend.frag")};
    return bases[std::size_t(stage)];
}

void ensureCopy(ViewState& s, const gl::RenderTarget& target) {
    if (s.copy.get() && s.copyWidth == target.width && s.copyHeight == target.height &&
        s.copyFormat == target.colorFormat)
        return;
    s.copy = gl::createTexture2D(target.colorFormat, target.width, target.height, GL_LINEAR);
    s.copyWidth = target.width;
    s.copyHeight = target.height;
    s.copyFormat = target.colorFormat;
}

// The finished image into `copy`, and `fbo` drawing into the target's colour (plus `extra`).
void prepareFullscreen(ViewState& s, const gl::RenderTarget& target, GLuint extra = 0) {
    ensureCopy(s, target);
    glCopyImageSubData(target.color.get(), GL_TEXTURE_2D, 0, 0, 0, 0, s.copy.get(), GL_TEXTURE_2D, 0, 0, 0, 0,
                       target.width, target.height, 1);
    if (!s.fbo) s.fbo = gl::createFramebuffer();
    glNamedFramebufferTexture(s.fbo.get(), GL_COLOR_ATTACHMENT0, target.color.get(), 0);
    glNamedFramebufferTexture(s.fbo.get(), GL_COLOR_ATTACHMENT1, extra, 0);
    const GLenum buffers[] = {GL_COLOR_ATTACHMENT0, GLenum(extra ? GL_COLOR_ATTACHMENT1 : GL_NONE)};
    glNamedFramebufferDrawBuffers(s.fbo.get(), 2, buffers);
    glBindFramebuffer(GL_FRAMEBUFFER, s.fbo.get());
    glViewport(0, 0, target.width, target.height);
    glEnable(GL_FRAMEBUFFER_SRGB);
}

} // namespace

float halton(std::uint32_t index, std::uint32_t base) {
    float f = 1.0f, r = 0.0f;
    for (; index > 0; index /= base) {
        f /= float(base);
        r += f * float(index % base);
    }
    return r;
}

void begin(ViewState& s, const Camera& camera, const glm::mat4& viewProjection, int width, int height,
           std::uint64_t frameNumber, std::vector<std::string>& warnings) {
    const AntiAliasing& a = camera.antiAliasing();
    if (!(a == s.settings)) s.frames = 0, s.warned = false;
    s.settings = a;
    s.samples = 1;
    if (a.mode == AntiAliasing::Mode::Msaa && a.samples > 1) {
        GLint maxSamples = 1;
        glGetIntegerv(GL_MAX_SAMPLES, &maxSamples);
        s.samples = std::min(a.samples, std::max(1, int(maxSamples)));
        if (s.samples != a.samples) {
            char buf[160];
            std::snprintf(buf, sizeof buf,
                          "sgfx: MSAA: %d samples asked, the driver allows %d (GL_MAX_SAMPLES): using %d",
                          a.samples, int(maxSamples), s.samples);
            if (!s.warned) warnings.emplace_back(buf);
            s.warned = true;
        }
    }
    s.jitter = glm::mat4(1.0f);
    s.previousViewProjection = s.viewProjection;
    s.viewProjection = viewProjection;
    if (a.mode != AntiAliasing::Mode::Taa && a.mode != AntiAliasing::Mode::SmaaT2x) return;
    // A camera cut (or a jump no history can follow) starts the accumulation again.
    const glm::mat4 view = camera.viewMatrix;
    const glm::vec3 eye = glm::vec3(glm::inverse(view)[3]),
                    lastEye = glm::vec3(glm::inverse(s.previousView)[3]);
    const glm::vec3 forward = -glm::vec3(glm::transpose(view)[2]),
                    lastForward = -glm::vec3(glm::transpose(s.previousView)[2]);
    const bool cut = s.epoch != camera.historyEpoch() || glm::length(eye - lastEye) > 2.0f ||
                     glm::dot(forward, lastForward) < std::cos(glm::radians(15.0f));
    if (cut) s.frames = 0;
    s.epoch = camera.historyEpoch();
    s.previousView = view;
    // Halton(2, 3) points within the pixel, 16 of them in turn: the image moves by minus the
    // offset, so each pixel samples the scene at (h₂, h₃) from its lower left corner. SMAA T2x:
    // two points a quarter pixel from the centre on a diagonal, in turn (Jimenez et al. 2012, sec. 6).
    const std::uint64_t n = frameNumber > 0 ? frameNumber - 1 : s.sequence++;
    const auto i = std::uint32_t(n % 16 + 1);
    const glm::vec2 offset = a.mode == AntiAliasing::Mode::SmaaT2x
                                 ? (i % 2 ? glm::vec2(0.25f, -0.25f) : glm::vec2(-0.25f, 0.25f))
                                 : glm::vec2(halton(i, 2) - 0.5f, halton(i, 3) - 0.5f);
    s.jitter = glm::translate(
        glm::mat4(1.0f), glm::vec3(-2.0f * offset.x / float(width), -2.0f * offset.y / float(height), 0.0f));
}

gl::RenderTarget& drawTarget(ViewState& s, gl::RenderTarget& target) {
    const AntiAliasing& a = s.settings;
    // Targets the current mode does not use are released (a mode switch frees its memory).
    if (a.mode != AntiAliasing::Mode::Msaa) s.msaa = {};
    if (a.mode != AntiAliasing::Mode::Ssaa) s.ssaa = {};
    const bool smaa = a.mode == AntiAliasing::Mode::Smaa || a.mode == AntiAliasing::Mode::SmaaT2x;
    if (a.mode != AntiAliasing::Mode::Fxaa && a.mode != AntiAliasing::Mode::Taa && !smaa)
        s.copy = {}, s.fbo = {};
    if (a.mode != AntiAliasing::Mode::Fxaa) {
        s.luma = {}, s.lumaFbo = {};
        s.lumaWidth = s.lumaHeight = 0;
    }
    if (a.mode != AntiAliasing::Mode::Fxaa && !smaa) s.stencil = {}, s.stencilWidth = s.stencilHeight = 0;
    if (!smaa) {
        s.smaaEdges = {}, s.smaaWeights = {}, s.smaaEdgesFbo = {}, s.smaaWeightsFbo = {};
        s.smaaArea = {}, s.smaaSearch = {}, s.smaaDiagonal = {};
        s.smaaWidth = s.smaaHeight = 0;
    }
    if (a.mode != AntiAliasing::Mode::Taa && a.mode != AntiAliasing::Mode::SmaaT2x) {
        s.history[0] = {}, s.history[1] = {};
        s.historyWidth = s.historyHeight = 0;
    }
    if (a.mode == AntiAliasing::Mode::Msaa && s.samples > 1) {
        s.msaa.resize(target.width, target.height, target.colorFormat, s.samples);
        return s.msaa;
    }
    if (a.mode == AntiAliasing::Mode::Ssaa && a.factor > 1) {
        GLint maxSize = 0;
        glGetIntegerv(GL_MAX_TEXTURE_SIZE, &maxSize);
        if (long(target.width) * a.factor > maxSize || long(target.height) * a.factor > maxSize)
            throw std::invalid_argument("sgfx: SSAA " + std::to_string(a.factor) + "x of " +
                                        std::to_string(target.width) + "x" + std::to_string(target.height) +
                                        " needs " + std::to_string(target.width * a.factor) + "x" +
                                        std::to_string(target.height * a.factor) +
                                        ", beyond the driver's texture limit " + std::to_string(maxSize));
        // Colour and 32-bit depth per sample; refuse what would not fit a sensible budget.
        const int colourBytes = target.colorFormat == GL_RGBA32F   ? 16
                                : target.colorFormat == GL_RGBA16F ? 8
                                                                   : 4;
        const double mib =
            double(target.width) * a.factor * target.height * a.factor * (colourBytes + 4) / 1048576.0;
        if (mib > 2048.0)
            throw std::invalid_argument("sgfx: SSAA " + std::to_string(a.factor) + "x of " +
                                        std::to_string(target.width) + "x" + std::to_string(target.height) +
                                        " needs " + std::to_string(int(mib)) +
                                        " MiB of targets, over the 2048 MiB limit");
        s.ssaa.resize(target.width * a.factor, target.height * a.factor, target.colorFormat);
        return s.ssaa;
    }
    return target;
}

void resolve(Renderer& r, ViewState& s, gl::RenderTarget& from, gl::RenderTarget& to) {
    // Depth: one sample per pixel, for the post passes that read it. Colour: the mean of the
    // samples (MSAA) or of the factor×factor block (SSAA), in linear colour.
    glBlitNamedFramebuffer(from.fbo.get(), to.fbo.get(), 0, 0, from.width, from.height, 0, 0, to.width,
                           to.height, GL_DEPTH_BUFFER_BIT, GL_NEAREST);
    const bool ms = from.samples > 1;
    gl::Program& program =
        ms ? fullscreenProgram(r, base(Stage::Resolve)) : fullscreenProgram(r, base(Stage::Downsample));
    glBindFramebuffer(GL_FRAMEBUFFER, to.fbo.get());
    glViewport(0, 0, to.width, to.height);
    glEnable(GL_FRAMEBUFFER_SRGB);
    r.resetStateCache();
    r.setBlend(BlendMode::Off);
    r.bindTexture(0, from.color.get());
    glUseProgram(program.get());
    if (ms)
        program.set("sgfx_aaSampleCount", from.samples);
    else
        program.set("sgfx_aaFactor", s.settings.factor);
    r.drawFullscreen(program);
    r.bindTexture(0, 0);
    r.resetStateCache();
}

namespace {

// FXAA's and SMAA's edge passes write 1 into the stencil wherever they leave a fragment (they
// discard the rest); the passes after them shade the marked pixels only, until the stencil test is
// disabled (a software rasterizer skips stencil-failed fragments before shading).
void markStencilWhereDrawn() {
    glEnable(GL_STENCIL_TEST);
    glStencilFunc(GL_ALWAYS, 1, 0xff);
    glStencilOp(GL_KEEP, GL_KEEP, GL_REPLACE);
    glStencilMask(0xff);
}
void drawOnlyWhereMarked() {
    glStencilFunc(GL_EQUAL, 1, 0xff);
    glStencilOp(GL_KEEP, GL_KEEP, GL_KEEP);
}

void fxaa(Renderer& r, ViewState& s, gl::RenderTarget& target) {
    const AntiAliasing& a = s.settings;
    // Luma first (one channel for the edge search), then the filter from the image's copy.
    if (!s.luma || s.lumaWidth != target.width || s.lumaHeight != target.height) {
        s.luma = gl::createTexture2D(GL_R16F, target.width, target.height, GL_LINEAR);
        s.lumaFbo = gl::createFramebuffer();
        glNamedFramebufferTexture(s.lumaFbo.get(), GL_COLOR_ATTACHMENT0, s.luma.get(), 0);
        s.lumaWidth = target.width;
        s.lumaHeight = target.height;
    }
    r.resetStateCache();
    r.setBlend(BlendMode::Off);
    glBindFramebuffer(GL_FRAMEBUFFER, s.lumaFbo.get());
    glViewport(0, 0, target.width, target.height);
    r.bindTexture(0, target.color.get());
    r.drawFullscreen(fullscreenProgram(r, base(Stage::FxaaLuma)));
    r.bindTexture(0, 0);
    prepareFullscreen(s, target);
    // Edge pixels into the stencil, so the filter below is shaded there only (a software
    // rasterizer skips stencil-failed fragments before shading).
    if (!s.stencil || s.stencilWidth != target.width || s.stencilHeight != target.height) {
        s.stencil = gl::createTexture2D(GL_STENCIL_INDEX8, target.width, target.height);
        s.stencilWidth = target.width;
        s.stencilHeight = target.height;
    }
    glNamedFramebufferTexture(s.fbo.get(), GL_STENCIL_ATTACHMENT, s.stencil.get(), 0);
    const GLint zero = 0;
    glClearNamedFramebufferiv(s.fbo.get(), GL_STENCIL, 0, &zero);
    auto stepsDefine = [](const char* name, int steps) {
        ShaderSnippet d;
        d.name = name;
        d.defines = "#define SGFX_FXAA_STEPS " + std::to_string(steps);
        return d;
    };
    static const ShaderSnippet steps[] = {stepsDefine("fxaa_low", 5), stepsDefine("fxaa_medium", 8),
                                          stepsDefine("fxaa_high", 12)};
    const std::size_t q = std::size_t(a.fxaaQuality);
    gl::Program& program = fullscreenProgram(r, base(Stage::Fxaa), &steps[q]);
    // Edge threshold, minimum threshold and sub-pixel amount of FXAA 3.11's presets.
    static const glm::vec3 presets[] = {
        {0.25f, 0.0833f, 0.5f}, {0.166f, 0.0625f, 0.75f}, {0.125f, 0.0312f, 1.0f}};
    r.bindTexture(0, s.copy.get());
    r.bindTexture(1, s.luma.get());
    gl::Program& edges = fullscreenProgram(r, base(Stage::FxaaEdges));
    glUseProgram(edges.get());
    edges.set("sgfx_fxaa", presets[q]);
    markStencilWhereDrawn();
    glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    r.drawFullscreen(edges);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    drawOnlyWhereMarked();
    glUseProgram(program.get());
    program.set("sgfx_fxaa", presets[q]);
    r.drawFullscreen(program);
    glDisable(GL_STENCIL_TEST);
    glNamedFramebufferTexture(s.fbo.get(), GL_STENCIL_ATTACHMENT, 0, 0);
    r.bindTexture(0, 0);
    r.bindTexture(1, 0);
    r.resetStateCache();
}

// The TAA resolve: this frame weighted `alpha` against the reprojected history. The history
// keeps the result (TAA) or this frame alone (`keepCurrent`, SMAA T2x: the mean of two frames).
void temporalResolve(Renderer& r, ViewState& s, gl::RenderTarget& target, float alpha, bool keepCurrent) {
    if (!s.history[0] || s.historyWidth != target.width || s.historyHeight != target.height) {
        for (auto& h : s.history)
            h = gl::createTexture2D(GL_RGBA16F, target.width, target.height, GL_LINEAR);
        s.historyWidth = target.width;
        s.historyHeight = target.height;
        s.frames = 0;
    }
    const int read = s.historyIndex, write = 1 - s.historyIndex;
    prepareFullscreen(s, target, s.history[write].get());
    gl::Program& program = fullscreenProgram(r, base(Stage::TaaResolve));
    r.resetStateCache();
    r.setBlend(BlendMode::Off);
    r.bindTexture(0, s.copy.get());
    r.bindTexture(1, target.depth.get());
    r.bindTexture(2, s.history[read].get());
    glUseProgram(program.get());
    program.set("sgfx_taaAlpha", alpha);
    program.set("sgfx_taaKeepCurrent", int(keepCurrent));
    program.set("sgfx_taaReprojection", s.previousViewProjection * glm::inverse(s.viewProjection));
    r.drawFullscreen(program);
    for (unsigned u = 0; u < 3; ++u)
        r.bindTexture(u, 0);
    r.resetStateCache();
    glNamedFramebufferTexture(s.fbo.get(), GL_COLOR_ATTACHMENT1, 0, 0);
    s.historyIndex = write;
    ++s.frames;
}

// SMAA's targets at the view's size and its look-up textures (made once per view).
void smaaTargets(ViewState& s, const gl::RenderTarget& target) {
    if (!s.smaaArea) {
        s.smaaArea = gl::createTexture2D(GL_RG32F, smaa::kAreaSize, smaa::kAreaSize);
        glTextureSubImage2D(s.smaaArea.get(), 0, 0, 0, smaa::kAreaSize, smaa::kAreaSize, GL_RG, GL_FLOAT,
                            smaa::areaTexture().data());
        s.smaaSearch = gl::createTexture2D(GL_R32F, smaa::kSearchWidth, smaa::kSearchHeight);
        glTextureSubImage2D(s.smaaSearch.get(), 0, 0, 0, smaa::kSearchWidth, smaa::kSearchHeight, GL_RED,
                            GL_FLOAT, smaa::searchTexture().data());
        s.smaaDiagonal = gl::createTexture2D(GL_RG32F, smaa::kDiagonalAreaSize, smaa::kDiagonalAreaSize);
        glTextureSubImage2D(s.smaaDiagonal.get(), 0, 0, 0, smaa::kDiagonalAreaSize, smaa::kDiagonalAreaSize,
                            GL_RG, GL_FLOAT, smaa::diagonalAreaTexture().data());
    }
    if (s.smaaEdges && s.smaaWidth == target.width && s.smaaHeight == target.height) return;
    s.smaaEdges = gl::createTexture2D(GL_RG8, target.width, target.height, GL_LINEAR);
    s.smaaWeights = gl::createTexture2D(GL_RGBA16F, target.width, target.height);
    s.stencil = gl::createTexture2D(GL_STENCIL_INDEX8, target.width, target.height);
    s.stencilWidth = s.smaaWidth = target.width;
    s.stencilHeight = s.smaaHeight = target.height;
    s.smaaEdgesFbo = gl::createFramebuffer(s.smaaEdges);
    s.smaaWeightsFbo = gl::createFramebuffer(s.smaaWeights);
    for (const gl::FramebufferObject* f : {&s.smaaEdgesFbo, &s.smaaWeightsFbo})
        glNamedFramebufferTexture(f->get(), GL_STENCIL_ATTACHMENT, s.stencil.get(), 0);
}

// SMAA 1x (Jimenez et al. 2012): edges (marking the stencil), blending weights on the marked
// pixels only, then neighbourhood blending of the whole image.
void smaa1x(Renderer& r, ViewState& s, gl::RenderTarget& target) {
    const AntiAliasing& a = s.settings;
    // The reference's presets: edge threshold, search steps (two pixels a step), corner
    // detection (25 % rounding on high and ultra), diagonal search steps (high and ultra).
    static constexpr float thresholds[] = {0.15f, 0.1f, 0.1f, 0.05f};
    static constexpr int diagonal[] = {0, 0, 8, 16};
    static constexpr int steps[] = {4, 8, 16, 32};
    static constexpr float corner[] = {0.0f, 0.0f, 0.75f, 0.75f};
    const std::size_t preset = std::size_t(a.smaaPreset);
    smaaTargets(s, target);
    r.resetStateCache();
    r.setBlend(BlendMode::Off);
    const GLfloat zero[4] = {0, 0, 0, 0};
    const GLint noStencil = 0;
    glClearNamedFramebufferfv(s.smaaEdgesFbo.get(), GL_COLOR, 0, zero);
    glClearNamedFramebufferiv(s.smaaEdgesFbo.get(), GL_STENCIL, 0, &noStencil);
    glClearNamedFramebufferfv(s.smaaWeightsFbo.get(), GL_COLOR, 0, zero);
    glBindFramebuffer(GL_FRAMEBUFFER, s.smaaEdgesFbo.get());
    glViewport(0, 0, target.width, target.height);
    r.bindTexture(0, target.color.get());
    r.bindTexture(1, target.depth.get());
    gl::Program& edges = fullscreenProgram(r, base(Stage(int(Stage::SmaaEdgesLuma) + int(a.smaaEdge))));
    glUseProgram(edges.get());
    edges.set("sgfx_smaaThreshold", thresholds[preset]);
    markStencilWhereDrawn();
    r.drawFullscreen(edges);
    glBindFramebuffer(GL_FRAMEBUFFER, s.smaaWeightsFbo.get());
    drawOnlyWhereMarked();
    r.bindTexture(0, s.smaaEdges.get());
    r.bindTexture(1, s.smaaArea.get());
    r.bindTexture(2, s.smaaSearch.get());
    r.bindTexture(3, s.smaaDiagonal.get());
    gl::Program& weights = fullscreenProgram(r, base(Stage::SmaaWeights));
    glUseProgram(weights.get());
    weights.set("sgfx_smaaSteps", steps[preset]);
    weights.set("sgfx_smaaCorner", corner[preset]);
    weights.set("sgfx_smaaDiagSteps", a.smaaDiagonalSteps < 0 ? diagonal[preset] : a.smaaDiagonalSteps);
    r.drawFullscreen(weights);
    glDisable(GL_STENCIL_TEST);
    prepareFullscreen(s, target);
    r.bindTexture(0, s.copy.get());
    r.bindTexture(1, s.smaaWeights.get());
    r.bindTexture(2, 0);
    r.bindTexture(3, 0);
    r.drawFullscreen(fullscreenProgram(r, base(Stage::SmaaBlend)));
    r.bindTexture(0, 0);
    r.bindTexture(1, 0);
    r.resetStateCache();
}

} // namespace

void finish(Renderer& r, ViewState& s, gl::RenderTarget& target) {
    const AntiAliasing& a = s.settings;
    switch (a.mode) {
    case AntiAliasing::Mode::Fxaa:
        fxaa(r, s, target);
        break;
    case AntiAliasing::Mode::Taa:
        // Accumulate evenly until the history holds 1/(1 − feedback) frames, then blend.
        temporalResolve(r, s, target, std::max(1.0f / float(s.frames + 1), 1.0f - a.taaFeedback), false);
        break;
    case AntiAliasing::Mode::Smaa:
        smaa1x(r, s, target);
        break;
    case AntiAliasing::Mode::SmaaT2x:
        // SMAA 1x on this jittered frame, then the mean with the previous one (sec. 6).
        smaa1x(r, s, target);
        temporalResolve(r, s, target, s.frames == 0 ? 1.0f : 0.5f, true);
        break;
    default:
        break;
    }
}

} // namespace sgfx::aa

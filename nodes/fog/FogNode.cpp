#include "fog/FogNode.h"
#include "fog/FogMath.h"

#include "ParameterChecks.h"
#include "TargetCache.h"

#include <sgfx/gl/Objects.h>

#include <glad/gl.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace sgfx {

namespace {

using nodes::number;

[[noreturn]] void refuse(const std::string& what) {
    nodes::refuse("FogParameters", what);
}

void checkRange(const char* name, float v, double lo, double hi) {
    nodes::checkRange("FogParameters", name, v, lo, hi);
}

std::string text(std::string_view file) {
    return nodes::shaderText(file);
}

const std::string& unitDefine() {
    static const std::string d = "#define SGFX_FOG_DEPTH_UNIT " + std::to_string(kEffectTextureUnit);
    return d;
}

ShaderSnippet snippetOf(std::string name, std::string defines, std::string fragmentDecl,
                        std::string colorCode = {}) {
    ShaderSnippet s;
    s.name = std::move(name);
    s.defines = std::move(defines);
    s.fragmentDecl = std::move(fragmentDecl);
    s.colorCode = std::move(colorCode);
    return s;
}

// The full-screen vertex stage with a define after its #version line.
std::string fullscreenVertexWith(std::string_view define) {
    return nodes::afterVersion(std::string(ShaderComposer::fullscreenVertex()), std::string(define) + "\n");
}

} // namespace

FogParameters FogParameters::solid() {
    FogParameters p;
    p.density = 1e-4f;
    p.falloff = 1e-4f;
    return p;
}

FogParameters FogParameters::ground() {
    FogParameters p;
    p.density = 1e-3f;
    p.falloff = 4.5e-3f;
    return p;
}

void FogParameters::validate() const {
    checkRange("density", density, 0.0, 1e6);
    checkRange("falloff", falloff, 0.0, 1e3);
    for (int i = 0; i < 3; ++i)
        checkRange(("color[" + std::to_string(i) + "]").c_str(), color[i], 0.0, 1e6);
    checkRange("referenceHeight", referenceHeight, -1e10, 1e10);
    for (int i = 0; i < 3; ++i)
        checkRange(("up[" + std::to_string(i) + "]").c_str(), up[i], -1e10, 1e10);
    if (glm::length(up) < 1e-6f) refuse("up has zero length; it must give a direction");
    checkRange("maxOpacity", maxOpacity, 0.0, 1.0);
    if (std::uint8_t(response) > std::uint8_t(FogResponse::Exponential))
        refuse("response has an invalid value " + std::to_string(int(response)));
    if (std::uint8_t(sky) > std::uint8_t(FogSky::Distance))
        refuse("sky has an invalid value " + std::to_string(int(sky)));
    if (!std::isfinite(skyDistance) || skyDistance <= 0.0f || skyDistance > 1e10f)
        refuse("skyDistance = " + number(skyDistance) + " must be in (0, 1e10] metres");
}

// Seed §2's T_depth: depth of every item of the view (opaque and transparent), into a texture
// the materials read at kEffectTextureUnit. One per view, shared by nested split-fog nodes.
class FogNode::DepthPrePass : public RenderPass {
public:
    std::string_view name() const override { return "fog depth pre-pass"; }
    PassStage stage() const override { return PassStage::PrePass; }
    void execute(Renderer& r) override {
        const gl::RenderTarget& view = r.currentTarget();
        Target& t = targetFor(view.width, view.height, r.frame().frameNumber);
        r.bindTexture(kEffectTextureUnit, 0); // not sampled while it is being written
        glBindFramebuffer(GL_FRAMEBUFFER, t.fbo.get());
        glViewport(0, 0, t.width, t.height);
        glDepthMask(GL_TRUE);
        glClearDepth(1.0);
        glClear(GL_DEPTH_BUFFER_BIT);
        gl::Program& depthOnly = r.depthOnlyProgram();
        r.drawItems(r.queue().opaque, &depthOnly, DrawMode::DepthOnly);
        r.drawItems(r.queue().transparent, &depthOnly, DrawMode::DepthOnly);
        r.drawItems(r.queue().claimed, &depthOnly, DrawMode::DepthOnly);
        r.bindTexture(kEffectTextureUnit, t.depth.get());
    }

private:
    struct Target {
        gl::FramebufferObject fbo;
        gl::TextureObject depth;
        int width = 0, height = 0;
        std::uint64_t lastUse = 0;
    };

    // One target per view size, so a render-to-texture view and the main view do not reallocate
    // each other's every frame; the least recently used of more than four goes.
    Target& targetFor(int width, int height, std::uint64_t frame) {
        return targets_.get(
            frame, [&](const Target& t) { return t.width == width && t.height == height; },
            [&](Target& t) { init(t, width, height); });
    }

    static void init(Target& t, int width, int height) {
        t.fbo = gl::createFramebuffer();
        t.depth = gl::createTexture2D(GL_DEPTH_COMPONENT32F, width, height);
        glNamedFramebufferTexture(t.fbo.get(), GL_DEPTH_ATTACHMENT, t.depth.get(), 0);
        glNamedFramebufferDrawBuffer(t.fbo.get(), GL_NONE);
        glNamedFramebufferReadBuffer(t.fbo.get(), GL_NONE);
        if (glCheckNamedFramebufferStatus(t.fbo.get(), GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
            throw std::runtime_error("sgfx: fog depth pre-pass: framebuffer incomplete at " +
                                     std::to_string(width) + "x" + std::to_string(height));
        t.width = width; // only a complete target is ever matched
        t.height = height;
    }

public:
    void releaseGLObjects() { targets_.clear(); }

private:
    nodes::TargetCache<Target> targets_;
};

// Seed §1's post-process (every pixel) or the forward modes' sky (uncovered pixels only).
class FogNode::FullscreenPass : public RenderPass {
public:
    explicit FullscreenPass(bool post)
        : post_(post) {}
    std::string_view name() const override { return post_ ? "fog post-process" : "fog sky"; }
    PassStage stage() const override { return post_ ? PassStage::Post : PassStage::AfterOpaque; }
    FogParameters parameters;

    void execute(Renderer& r) override {
        const gl::RenderTarget& view = r.currentTarget();
        gl::Program& program = r.composer().program(base(), std::array{&decl()}, 0);
        if (post_) {
            // Sampling the depth texture while it is attached to the draw framebuffer is a
            // feedback loop: draw into a framebuffer that has the colour texture alone.
            if (!fbo_) fbo_ = gl::createFramebuffer();
            glNamedFramebufferTexture(fbo_.get(), GL_COLOR_ATTACHMENT0, view.color.get(), 0);
            glBindFramebuffer(GL_FRAMEBUFFER, fbo_.get());
            r.bindTexture(kEffectTextureUnit, view.depth.get());
        } else {
            glBindFramebuffer(GL_FRAMEBUFFER, view.fbo.get());
        }
        glViewport(0, 0, view.width, view.height);
        glEnable(GL_FRAMEBUFFER_SRGB);
        r.setBlend(BlendMode::Alpha);
        glUseProgram(program.get());
        setUniforms(program, parameters, r.frame().eye);
        r.drawFullscreen(program, post_
                                      ? DepthState{.test = false, .write = false, .func = CompareFunc::Always}
                                      : DepthState{.test = true, .write = false, .func = CompareFunc::Equal});
        if (post_) r.bindTexture(kEffectTextureUnit, 0);
    }
    void releaseGLObjects() { fbo_.reset(); }

private:
    const BaseShader& base() const {
        static const BaseShader sky{"fog_sky", "blit.vert",
                                    fullscreenVertexWith("#define SGFX_FULLSCREEN_FAR"),
                                    "fog_fullscreen.frag", text("fog_fullscreen.frag")};
        static const BaseShader post{"fog_post", "blit.vert", std::string(ShaderComposer::fullscreenVertex()),
                                     "fog_fullscreen.frag", text("fog_fullscreen.frag")};
        return post_ ? post : sky;
    }
    const ShaderSnippet& decl() const {
        static const ShaderSnippet sky =
            snippetOf("fog_fullscreen", unitDefine(), text("fog_optical_depth.glsl"));
        static const ShaderSnippet post = snippetOf(
            "fog_fullscreen_post", unitDefine() + "\n#define SGFX_FOG_POST", text("fog_optical_depth.glsl"));
        return post_ ? post : sky;
    }
    bool post_;
    gl::FramebufferObject fbo_;
};

std::shared_ptr<FogNode> FogNode::create(const FogParameters& parameters, FogMode mode) {
    auto n = std::make_shared<FogNode>();
    n->setParameters(parameters);
    n->setMode(mode);
    return n;
}

FogNode::FogNode()
    : depthPass_(std::make_shared<DepthPrePass>())
    , skyPass_(std::make_shared<FullscreenPass>(false))
    , postPass_(std::make_shared<FullscreenPass>(true)) {
    // Fog covers the sky too: it must be planned when nothing under it is in view.
    setCullingActive(false);
}

FogNode::~FogNode() = default;

void FogNode::releaseGLObjects() {
    depthPass_->releaseGLObjects();
    skyPass_->releaseGLObjects();
    postPass_->releaseGLObjects();
}

void FogNode::setParameters(const FogParameters& p) {
    p.validate();
    parameters_ = p;
    parameters_.up = glm::normalize(p.up);
}

void FogNode::setMode(FogMode m) {
    if (std::uint8_t(m) > std::uint8_t(FogMode::PostProcess))
        throw std::invalid_argument("sgfx: FogNode::setMode: invalid mode value " + std::to_string(int(m)));
    mode_ = m;
}

const ShaderSnippet& FogNode::snippet() const {
    static const ShaderSnippet forward =
        snippetOf("fog", "", text("fog_optical_depth.glsl"), text("fog_forward.glsl"));
    static const ShaderSnippet split =
        snippetOf("fog_split", unitDefine(), text("fog_optical_depth.glsl") + text("fog_split_decl.glsl"),
                  text("fog_split.glsl"));
    static const ShaderSnippet post = snippetOf("fog_post", "", ""); // the pass does it all
    switch (mode_) {
    case FogMode::ForwardSplit:
        return split;
    case FogMode::PostProcess:
        return post;
    case FogMode::Forward:
        break;
    }
    return forward;
}

void FogNode::planFrame(FramePlan& plan) const {
    // Cull visits outer nodes first: the outermost fog owns the view-wide passes.
    if (mode_ == FogMode::PostProcess) {
        if (plan.has(postPass_->name())) return;
        postPass_->parameters = parameters_;
        plan.add(postPass_);
        return;
    }
    if (mode_ == FogMode::ForwardSplit && !plan.has(depthPass_->name())) plan.add(depthPass_);
    if (parameters_.sky != FogSky::Off && !plan.has(skyPass_->name())) {
        skyPass_->parameters = parameters_;
        plan.add(skyPass_);
    }
}

void FogNode::applyUniforms(gl::Program& program, const DrawContext& context) const {
    if (mode_ != FogMode::PostProcess) setUniforms(program, parameters_, context.frame.eye);
}

void FogNode::setUniforms(gl::Program& program, const FogParameters& p, const glm::vec3& eye) {
    const float eyeHeight = fog::heightOf(eye, p.up, p.referenceHeight);
    program.set("sgfx_fogEye", glm::vec2(eyeHeight, fog::densityFactor(p.falloff, eyeHeight)));
    program.set("sgfx_fogDensity", p.density);
    program.set("sgfx_fogFalloff", p.falloff);
    program.set("sgfx_fogColor", p.color);
    program.set("sgfx_fogPlane", glm::vec4(p.up, p.referenceHeight));
    const float sky = p.sky == FogSky::Off ? 0.0f : p.sky == FogSky::FarPlane ? -1.0f : p.skyDistance;
    program.set("sgfx_fogShape",
                glm::vec4(p.response == FogResponse::Exponential ? 1.0f : 0.0f, p.maxOpacity, sky, 0.0f));
}

} // namespace sgfx

#include "ao/AmbientOcclusionNode.h"

#include "ParameterChecks.h"
#include "TargetCache.h"

#include <sgfx/gl/Objects.h>

#include <glad/gl.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <stdexcept>
#include <string>

namespace sgfx {

namespace {

constexpr unsigned kMapUnit = kEffectTextureUnit + 1; // 13: read by the materials in the main pass

using nodes::number;

std::string text(std::string_view file) {
    return nodes::shaderText(file);
}

[[noreturn]] void refuse(const std::string& what) {
    nodes::refuse("AmbientOcclusionParameters", what);
}

void checkRange(const char* name, float v, double lo, double hi, bool openLow = false) {
    nodes::checkRange("AmbientOcclusionParameters", name, v, lo, hi, openLow);
}

// A full-screen base shader whose fragment stage may include ao_view_position.glsl.
BaseShader fullscreen(std::string name, std::string_view fragmentFile) {
    std::string frag = text(fragmentFile);
    const std::string marker = "#include_ao_view_position";
    if (const auto at = frag.find(marker); at != std::string::npos)
        frag.replace(at, marker.size(), text("ao_view_position.glsl"));
    return BaseShader{std::move(name), "blit.vert", std::string(ShaderComposer::fullscreenVertex()),
                      std::string(fragmentFile), std::move(frag)};
}

ShaderSnippet definesOnly(std::string name, std::string defines) {
    ShaderSnippet s;
    s.name = std::move(name);
    s.defines = std::move(defines);
    return s;
}

void checkComplete(GLuint fbo, const char* what, int w, int h) {
    if (glCheckNamedFramebufferStatus(fbo, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        throw std::runtime_error(std::string("sgfx: ambient occlusion: ") + what +
                                 " framebuffer incomplete at " + std::to_string(w) + "x" + std::to_string(h));
}

} // namespace

// ------------------------------------------------------------------------------ parameters

AmbientOcclusionParameters AmbientOcclusionParameters::paper() {
    AmbientOcclusionParameters p;
    p.kernel = AoKernel::PaperHalfCube;
    p.compare = AoCompare::StoredDepth;
    p.rangeCheck = false;
    p.blur = AoBlur::Box;
    p.gbuffer = AoGBuffer::PaperPositions;
    return p;
}

void AmbientOcclusionParameters::validate() const {
    if (samples < 8 || samples > 64) refuse("samples = " + std::to_string(samples) + " is outside [8, 64]");
    checkRange("radius", radius, 0.0, 1e4, true);
    checkRange("bias", bias, 0.0, 1e3);
    checkRange("intensity", intensity, 0.0, 100.0);
    checkRange("power", power, 0.01, 100.0);
    if (blurSize < 1 || blurSize > 15 || blurSize % 2 == 0)
        refuse("blurSize = " + std::to_string(blurSize) + " must be odd, in [1, 15]");
    if (std::uint8_t(kernel) > std::uint8_t(AoKernel::PaperHalfCube))
        refuse("kernel has an invalid value " + std::to_string(int(kernel)));
    if (std::uint8_t(compare) > std::uint8_t(AoCompare::StoredDepth))
        refuse("compare has an invalid value " + std::to_string(int(compare)));
    if (std::uint8_t(blur) > std::uint8_t(AoBlur::Box))
        refuse("blur has an invalid value " + std::to_string(int(blur)));
    if (std::uint8_t(gbuffer) > std::uint8_t(AoGBuffer::PaperPositions))
        refuse("gbuffer has an invalid value " + std::to_string(int(gbuffer)));
    if (std::uint8_t(debugView) > std::uint8_t(AoDebugView::Blurred))
        refuse("debugView has an invalid value " + std::to_string(int(debugView)));
}

std::vector<glm::vec3> ao::kernel(AoKernel kind, int samples, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> rnd(0.0f, 1.0f);
    std::vector<glm::vec3> k;
    k.reserve(std::size_t(samples));
    for (int i = 0; i < samples; ++i) {
        // Seed §2: S = (2r − 1, 2r − 1, r).
        glm::vec3 s(2.0f * rnd(rng) - 1.0f, 2.0f * rnd(rng) - 1.0f, rnd(rng));
        if (kind == AoKernel::Hemisphere) {
            // Directions off the tangent plane; lengths spread evenly over [0.1, 1]: inside the
            // unit hemisphere, and denser towards the centre than a uniform fill of its volume
            // (44 % within R/2 against 12.5 %), so near occluders count most. The common
            // lerp(0.1, 1, t²)·rand crowds 80 % of the samples within R/4, where δ hides them.
            s.z = std::max(s.z, 0.1f);
            s = glm::normalize(s) * (0.1f + 0.9f * (float(i) + 0.5f) / float(samples));
        }
        k.push_back(s);
    }
    return k;
}

std::vector<glm::vec2> ao::rotationNoise(std::uint32_t seed) {
    std::mt19937 rng(seed ^ 0x9e3779b9u);
    std::uniform_real_distribution<float> rnd(0.0f, 1.0f);
    std::vector<glm::vec2> n(16);
    for (glm::vec2& v : n)
        v = glm::vec2(2.0f * rnd(rng) - 1.0f, 2.0f * rnd(rng) - 1.0f); // V_r, z = 0
    return n;
}

// ------------------------------------------------------------------------------ passes

// What the three passes share: per-view-size targets, the kernel and the noise texture.
struct AmbientOcclusionNode::Shared {
    AmbientOcclusionParameters parameters;

    struct Targets {
        int width = 0, height = 0, mapWidth = 0, mapHeight = 0;
        bool positions = false;
        std::uint64_t lastUse = 0;
        gl::FramebufferObject gbuffer, raw, half, blurred; // half: after the blur's x pass
        gl::TextureObject normal, depth, position, zbuffer, rawMap, halfMap, blurredMap;
    };
    nodes::TargetCache<Targets> targets;
    Targets* current = nullptr; // the view being drawn (set by the G-buffer pass)
    gl::TextureObject noise;
    std::uint32_t noiseSeed = 0;
    std::vector<glm::vec3> kernel;
    AoKernel kernelKind{};
    int kernelSamples = 0;
    std::uint32_t kernelSeed = 0;

    Targets& targetsFor(int w, int h, std::uint64_t frame) {
        const bool half = parameters.halfResolution;
        const bool positions = parameters.gbuffer == AoGBuffer::PaperPositions;
        const int mw = half ? (w + 1) / 2 : w, mh = half ? (h + 1) / 2 : h;
        return targets.get(
            frame,
            [&](const Targets& t) {
                return t.width == w && t.height == h && t.mapWidth == mw && t.mapHeight == mh &&
                       t.positions == positions;
            },
            [&](Targets& t) { init(t, w, h, mw, mh, positions); });
    }

    static void init(Targets& t, int w, int h, int mw, int mh, bool positions) {
        t.normal = gl::createTexture2D(GL_RGBA16F, w, h);
        t.depth = gl::createTexture2D(GL_R32F, w, h);
        t.zbuffer = gl::createTexture2D(GL_DEPTH_COMPONENT32F, w, h);
        t.gbuffer = gl::createFramebuffer();
        glNamedFramebufferTexture(t.gbuffer.get(), GL_COLOR_ATTACHMENT0, t.normal.get(), 0);
        glNamedFramebufferTexture(t.gbuffer.get(), GL_COLOR_ATTACHMENT1, t.depth.get(), 0);
        glNamedFramebufferTexture(t.gbuffer.get(), GL_DEPTH_ATTACHMENT, t.zbuffer.get(), 0);
        GLenum buffers[] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_NONE};
        if (positions) {
            t.position = gl::createTexture2D(GL_RGBA16F, w, h);
            glNamedFramebufferTexture(t.gbuffer.get(), GL_COLOR_ATTACHMENT2, t.position.get(), 0);
            buffers[2] = GL_COLOR_ATTACHMENT2;
        }
        glNamedFramebufferDrawBuffers(t.gbuffer.get(), 3, buffers);
        checkComplete(t.gbuffer.get(), "G-buffer", w, h);
        auto mapTarget = [&](gl::FramebufferObject& fbo, gl::TextureObject& map) {
            map = gl::createTexture2D(GL_RG32F, mw, mh);
            fbo = gl::createFramebuffer();
            glNamedFramebufferTexture(fbo.get(), GL_COLOR_ATTACHMENT0, map.get(), 0);
            checkComplete(fbo.get(), "occlusion map", mw, mh);
        };
        mapTarget(t.raw, t.rawMap);
        mapTarget(t.half, t.halfMap);
        mapTarget(t.blurred, t.blurredMap);
        // Only a complete set is ever matched.
        t.width = w, t.height = h, t.mapWidth = mw, t.mapHeight = mh, t.positions = positions;
    }

    void release() {
        targets.clear();
        current = nullptr;
        noise.reset();
    }

    GLuint noiseTexture() {
        if (!noise || noiseSeed != parameters.seed) {
            const std::vector<glm::vec2> n = ao::rotationNoise(parameters.seed);
            noise = gl::createTexture2D(GL_RG32F, 4, 4);
            glTextureSubImage2D(noise.get(), 0, 0, 0, 4, 4, GL_RG, GL_FLOAT, n.data());
            noiseSeed = parameters.seed;
        }
        return noise.get();
    }

    const std::vector<glm::vec3>& kernelFor() {
        const AmbientOcclusionParameters& p = parameters;
        if (kernel.empty() || kernelKind != p.kernel || kernelSamples != p.samples || kernelSeed != p.seed) {
            kernel = ao::kernel(p.kernel, p.samples, p.seed);
            kernelKind = p.kernel, kernelSamples = p.samples, kernelSeed = p.seed;
        }
        return kernel;
    }
};

// Seed §1: view-space normals and depth (or positions) of every opaque item of the view.
class AmbientOcclusionNode::GBufferPass : public RenderPass {
public:
    explicit GBufferPass(std::shared_ptr<Shared> s)
        : shared_(std::move(s)) {}
    std::string_view name() const override { return "ao g-buffer"; }
    PassStage stage() const override { return PassStage::PrePass; }
    void execute(Renderer& r) override {
        const gl::RenderTarget& view = r.currentTarget();
        Shared::Targets& t = shared_->targetsFor(view.width, view.height, r.frame().frameNumber);
        shared_->current = &t;
        r.bindTexture(kMapUnit, 0);
        glBindFramebuffer(GL_FRAMEBUFFER, t.gbuffer.get());
        glViewport(0, 0, t.width, t.height);
        glDisable(GL_FRAMEBUFFER_SRGB);
        const float zero[4] = {0, 0, 0, 0};
        for (int i = 0; i < (t.positions ? 3 : 2); ++i)
            glClearNamedFramebufferfv(t.gbuffer.get(), GL_COLOR, i, zero);
        const float far = 1.0f;
        glDepthMask(GL_TRUE);
        glClearNamedFramebufferfv(t.gbuffer.get(), GL_DEPTH, 0, &far);
        r.resetStateCache();
        r.drawItems(r.queue().opaque, &r.gbufferProgram(), DrawMode::GBuffer);
    }

private:
    std::shared_ptr<Shared> shared_;
};

// Seed §2: the occlusion map.
class AmbientOcclusionNode::OcclusionPass : public RenderPass {
public:
    explicit OcclusionPass(std::shared_ptr<Shared> s)
        : shared_(std::move(s)) {}
    std::string_view name() const override { return "ao occlusion"; }
    PassStage stage() const override { return PassStage::PrePass; }
    void execute(Renderer& r) override {
        Shared::Targets* t = shared_->current;
        if (!t) return;
        const AmbientOcclusionParameters& p = shared_->parameters;
        static const BaseShader base = fullscreen("ao_occlusion", "ao_occlusion.frag");
        static const ShaderSnippet depth = definesOnly("ao_depth", "");
        static const ShaderSnippet positions = definesOnly("ao_positions", "#define SGFX_AO_POSITIONS");
        gl::Program& program = r.composer().program(base, std::array{t->positions ? &positions : &depth}, 0);
        glBindFramebuffer(GL_FRAMEBUFFER, t->raw.get());
        glViewport(0, 0, t->mapWidth, t->mapHeight);
        glDisable(GL_FRAMEBUFFER_SRGB);
        r.setBlend(BlendMode::Off);
        r.bindTexture(0, t->normal.get());
        r.bindTexture(1, t->depth.get());
        r.bindTexture(2, t->positions ? t->position.get() : 0);
        r.bindTexture(3, shared_->noiseTexture());
        glUseProgram(program.get());
        const std::vector<glm::vec3>& k = shared_->kernelFor();
        glProgramUniform3fv(program.get(), program.location("sgfx_aoKernel[0]"), GLsizei(k.size()), &k[0].x);
        program.set("sgfx_aoSamples", p.samples);
        program.set("sgfx_aoShape", glm::vec4(p.radius, p.bias, p.rangeCheck ? 1.0f : 0.0f,
                                              p.compare == AoCompare::TangentPlane ? 1.0f : 0.0f));
        const bool paperLike = p.compare == AoCompare::StoredDepth && !p.rangeCheck;
        program.set("sgfx_aoShape2",
                    glm::vec4(p.halfResolution ? 2.0f : 1.0f, paperLike ? 0.0f : 1.0f, 0, 0));
        r.drawFullscreen(program);
    }

private:
    std::shared_ptr<Shared> shared_;
};

// Seed §3: the blur, then the map goes to the materials' unit.
class AmbientOcclusionNode::BlurPass : public RenderPass {
public:
    explicit BlurPass(std::shared_ptr<Shared> s)
        : shared_(std::move(s)) {}
    std::string_view name() const override { return "ao blur"; }
    PassStage stage() const override { return PassStage::PrePass; }
    void execute(Renderer& r) override {
        Shared::Targets* t = shared_->current;
        if (!t) return;
        const AmbientOcclusionParameters& p = shared_->parameters;
        if (p.blurSize > 1) {
            static const BaseShader base = fullscreen("ao_blur", "ao_blur.frag");
            static const ShaderSnippet bilateral = definesOnly("ao_bilateral", "");
            static const ShaderSnippet box = definesOnly("ao_box", "#define SGFX_AO_BOX");
            gl::Program& program =
                r.composer().program(base, std::array{p.blur == AoBlur::Box ? &box : &bilateral}, 0);
            glViewport(0, 0, t->mapWidth, t->mapHeight);
            glDisable(GL_FRAMEBUFFER_SRGB);
            r.setBlend(BlendMode::Off);
            glUseProgram(program.get());
            // Separable: along x into `half`, then along y into `blurred`.
            for (int pass = 0; pass < 2; ++pass) {
                glBindFramebuffer(GL_FRAMEBUFFER, pass == 0 ? t->half.get() : t->blurred.get());
                r.bindTexture(0, pass == 0 ? t->rawMap.get() : t->halfMap.get());
                program.set("sgfx_aoBlur", glm::vec4(float(p.blurSize), p.radius, pass == 0 ? 1.0f : 0.0f,
                                                     pass == 0 ? 0.0f : 1.0f));
                r.drawFullscreen(program);
            }
        }
        r.bindTexture(kMapUnit, p.blurSize > 1 ? t->blurredMap.get() : t->rawMap.get());
    }

private:
    std::shared_ptr<Shared> shared_;
};

// The map over the view, opaque grey (seed figures 5 and 7).
class AmbientOcclusionNode::DebugPass : public RenderPass {
public:
    explicit DebugPass(std::shared_ptr<Shared> s)
        : shared_(std::move(s)) {}
    std::string_view name() const override { return "ao debug view"; }
    PassStage stage() const override { return PassStage::Post; }
    void execute(Renderer& r) override {
        Shared::Targets* t = shared_->current;
        if (!t) return;
        static const BaseShader base = fullscreen("ao_debug", "ao_debug.frag");
        gl::Program& program = r.composer().program(base, {}, 0);
        const bool raw =
            shared_->parameters.debugView == AoDebugView::Raw || shared_->parameters.blurSize == 1;
        r.setBlend(BlendMode::Off);
        r.bindTexture(0, raw ? t->rawMap.get() : t->blurredMap.get());
        r.drawFullscreen(program);
    }

private:
    std::shared_ptr<Shared> shared_;
};

// ------------------------------------------------------------------------------ node

std::shared_ptr<AmbientOcclusionNode>
AmbientOcclusionNode::create(const AmbientOcclusionParameters& parameters) {
    auto n = std::make_shared<AmbientOcclusionNode>();
    n->setParameters(parameters);
    return n;
}

AmbientOcclusionNode::AmbientOcclusionNode()
    : shared_(std::make_shared<Shared>())
    , gbufferPass_(std::make_shared<GBufferPass>(shared_))
    , occlusionPass_(std::make_shared<OcclusionPass>(shared_))
    , blurPass_(std::make_shared<BlurPass>(shared_))
    , debugPass_(std::make_shared<DebugPass>(shared_)) {}

AmbientOcclusionNode::~AmbientOcclusionNode() = default;

void AmbientOcclusionNode::releaseGLObjects() {
    shared_->release();
}

void AmbientOcclusionNode::setParameters(const AmbientOcclusionParameters& p) {
    p.validate();
    parameters_ = p;
}

const ShaderSnippet& AmbientOcclusionNode::snippet() const {
    static const ShaderSnippet s = [] {
        ShaderSnippet sn;
        sn.name = "ambient_occlusion";
        sn.defines = "#define SGFX_AMBIENT_OCCLUSION 1\n#define SGFX_AO_UNIT " + std::to_string(kMapUnit);
        sn.fragmentDecl = text("ao_apply.glsl");
        sn.ambientCode = text("ao_ambient.glsl");
        return sn;
    }();
    return s;
}

void AmbientOcclusionNode::planFrame(FramePlan& plan) const {
    // The outermost node in view computes the map for the whole view.
    if (plan.has(gbufferPass_->name())) return;
    shared_->parameters = parameters_;
    shared_->current = nullptr;
    plan.add(gbufferPass_);
    plan.add(occlusionPass_);
    plan.add(blurPass_);
    if (parameters_.debugView != AoDebugView::Off) plan.add(debugPass_);
}

void AmbientOcclusionNode::applyUniforms(gl::Program& program, const DrawContext&) const {
    program.set("sgfx_aoApply", glm::vec2(parameters_.intensity, parameters_.power));
}

} // namespace sgfx

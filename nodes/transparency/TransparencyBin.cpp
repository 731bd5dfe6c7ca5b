#include "transparency/TransparencyBin.h"

#include "ParameterChecks.h"

#include <sgfx/Geometry.h>
#include <sgfx/StateSet.h>
#include <sgfx/gl/Objects.h>

#include <glad/gl.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

namespace sgfx {

namespace {

constexpr unsigned kAccumUnit = kEffectTextureUnit + 2; // units 14, 15: this pass's own
constexpr unsigned kRevealUnit = kEffectTextureUnit + 3;

std::string text(std::string_view file) {
    return nodes::shaderText(file);
}

ShaderSnippet oitSnippet() {
    ShaderSnippet s;
    s.name = "transparency_oit";
    s.fragmentDecl = text("oit_weight.glsl");
    s.colorCode = text("oit_accumulate.glsl");
    return s;
}

int equationOf(OitWeight w) {
    switch (w) {
    case OitWeight::Depth7:
        return 7;
    case OitWeight::Depth8:
        return 8;
    case OitWeight::Depth9:
        return 9;
    case OitWeight::WindowDepth10:
        return 10;
    case OitWeight::Constant:
        break;
    }
    return 0;
}

// Pixels the items' bounding spheres may cover: the accumulation and the composite are
// scissored to them (a software rasterizer pays for every pixel of a full-screen pass).
glm::ivec4 screenBounds(std::span<const RenderItem> items, const FrameData& frame) {
    glm::vec2 lo(0.0f), hi(0.0f);
    bool any = false;
    const bool perspective = frame.projection[2][3] != 0.0f;
    const float nearZ = frame.projection[3][2] / (frame.projection[2][2] - 1.0f); // the near distance
    for (const RenderItem& it : items) {
        const BoundingSphere s = it.worldBound();
        if (!s.valid()) continue;
        const glm::vec3 c = glm::vec3(frame.view * glm::vec4(s.center, 1.0f));
        if (perspective && (!(nearZ > 0.0f) || -c.z - s.radius <= nearZ))
            return {0, 0, frame.width, frame.height}; // reaches the camera: everything
        for (int k = 0; k < 8; ++k) {
            const glm::vec3 corner = c + s.radius * glm::vec3(k & 1 ? 1 : -1, k & 2 ? 1 : -1, k & 4 ? 1 : -1);
            const glm::vec4 clip = frame.projection * glm::vec4(corner, 1.0f);
            const glm::vec2 ndc = glm::vec2(clip) / clip.w;
            lo = any ? glm::min(lo, ndc) : ndc;
            hi = any ? glm::max(hi, ndc) : ndc;
            any = true;
        }
    }
    if (!any || !std::isfinite(lo.x + lo.y + hi.x + hi.y))
        return {0, 0, any ? frame.width : 0, any ? frame.height : 0};
    lo = glm::clamp(lo, -1.0f, 1.0f);
    hi = glm::clamp(hi, -1.0f, 1.0f);
    const int x0 = std::max(0, int(std::floor((lo.x * 0.5f + 0.5f) * float(frame.width))) - 1);
    const int y0 = std::max(0, int(std::floor((lo.y * 0.5f + 0.5f) * float(frame.height))) - 1);
    const int x1 = std::min(frame.width, int(std::ceil((hi.x * 0.5f + 0.5f) * float(frame.width))) + 1);
    const int y1 = std::min(frame.height, int(std::ceil((hi.y * 0.5f + 0.5f) * float(frame.height))) + 1);
    return {x0, y0, std::max(0, x1 - x0), std::max(0, y1 - y0)};
}

} // namespace

void OitParameters::validate() const {
    if (std::uint8_t(weight) > std::uint8_t(OitWeight::WindowDepth10))
        nodes::refuse("OitParameters", "weight has an invalid value " + std::to_string(int(weight)));
    nodes::checkRange("OitParameters", "depthScale", depthScale, 0.0, 1e9, true);
}

// Accumulates every claimed item of the view into (Σ C·w, Σ α·w) and Π(1 − α), against the
// opaque depth, then composites them over the view in one full-screen pass.
class TransparencyBin::OitPass : public RenderPass {
public:
    std::string_view name() const override { return "transparency OIT"; }
    PassStage stage() const override { return PassStage::Transparent; }
    bool revealage8Bit = false;

    void execute(Renderer& r) override {
        const auto& items = r.queue().claimed;
        if (items.empty()) return;
        const gl::RenderTarget& view = r.currentTarget();
        allocate(view);
        const glm::ivec4 rect = screenBounds(items, r.frame());
        if (rect.z <= 0 || rect.w <= 0) return;

        r.bindTexture(kAccumUnit, 0); // not sampled while being written
        r.bindTexture(kRevealUnit, 0);
        glBindFramebuffer(GL_FRAMEBUFFER, fbo_.get());
        glViewport(0, 0, view.width, view.height);
        glDisable(GL_FRAMEBUFFER_SRGB);
        const float zero[4] = {0, 0, 0, 0}, one[4] = {1, 1, 1, 1};
        // Whole-target clears: llvmpipe clears whole tiles at once, a scissored clear pixel by
        // pixel (5x slower at 720p).
        glClearNamedFramebufferfv(fbo_.get(), GL_COLOR, 0, zero);
        glClearNamedFramebufferfv(fbo_.get(), GL_COLOR, 1, one);
        glEnable(GL_SCISSOR_TEST);
        glScissor(rect.x, rect.y, rect.z, rect.w);
        glEnable(GL_BLEND);
        glBlendEquation(GL_FUNC_ADD);
        glBlendFunci(0, GL_ONE, GL_ONE);
        glBlendFunci(1, GL_ZERO, GL_ONE_MINUS_SRC_COLOR);
        glEnable(GL_DEPTH_TEST); // against the opaque depth, never written
        glDepthFunc(GL_LESS);
        glDepthMask(GL_FALSE);
        r.resetStateCache();
        r.drawItems(items, nullptr, DrawMode::PassBlend);

        glBindFramebuffer(GL_FRAMEBUFFER, view.fbo.get());
        glEnable(GL_FRAMEBUFFER_SRGB);
        r.resetStateCache(); // blend functions per target changed behind the cache
        r.setBlend(BlendMode::Alpha);
        r.bindTexture(kAccumUnit, accum_.get());
        r.bindTexture(kRevealUnit, reveal_.get());
        r.drawFullscreen(compositeProgram(r, samples_ > 1));
        r.bindTexture(kAccumUnit, 0);
        r.bindTexture(kRevealUnit, 0);
        glDisable(GL_SCISSOR_TEST);
    }

    void releaseGLObjects() {
        fbo_.reset();
        accum_.reset();
        reveal_.reset();
        depth_ = 0;
    }

private:
    void allocate(const gl::RenderTarget& view) {
        const GLenum revealFormat = revealage8Bit ? GL_R8 : GL_R16F;
        if (!fbo_ || width_ != view.width || height_ != view.height || revealFormat_ != revealFormat ||
            samples_ != view.samples) {
            // A multisampled view (MSAA) gets multisampled sums, composited per sample.
            const bool ms = view.samples > 1;
            fbo_ = gl::createFramebuffer();
            if (ms) {
                accum_ = gl::createTexture(GL_TEXTURE_2D_MULTISAMPLE);
                reveal_ = gl::createTexture(GL_TEXTURE_2D_MULTISAMPLE);
                glTextureStorage2DMultisample(accum_.get(), view.samples, GL_RGBA16F, view.width, view.height,
                                              GL_TRUE);
                glTextureStorage2DMultisample(reveal_.get(), view.samples, revealFormat, view.width,
                                              view.height, GL_TRUE);
            } else {
                accum_ = gl::createTexture2D(GL_RGBA16F, view.width, view.height);
                reveal_ = gl::createTexture2D(revealFormat, view.width, view.height);
            }
            samples_ = view.samples;
            glNamedFramebufferTexture(fbo_.get(), GL_COLOR_ATTACHMENT0, accum_.get(), 0);
            glNamedFramebufferTexture(fbo_.get(), GL_COLOR_ATTACHMENT1, reveal_.get(), 0);
            const GLenum buffers[] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
            glNamedFramebufferDrawBuffers(fbo_.get(), 2, buffers);
            width_ = view.width;
            height_ = view.height;
            revealFormat_ = revealFormat;
            depth_ = 0;
        }
        // The view's own depth (it may be a render-to-texture camera's, or reallocated).
        if (depth_ != view.depth.get()) {
            glNamedFramebufferTexture(fbo_.get(), GL_DEPTH_ATTACHMENT, view.depth.get(), 0);
            depth_ = view.depth.get();
        }
        if (glCheckNamedFramebufferStatus(fbo_.get(), GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
            throw std::runtime_error("sgfx: transparency OIT: framebuffer incomplete at " +
                                     std::to_string(view.width) + "x" + std::to_string(view.height));
    }

    static gl::Program& compositeProgram(Renderer& r, bool multisample) {
        static const BaseShader base{"oit_composite", "blit.vert",
                                     std::string(ShaderComposer::fullscreenVertex()), "oit_composite.frag",
                                     text("oit_composite.frag")};
        static const ShaderSnippet units = [] {
            ShaderSnippet s;
            s.name = "oit_units";
            s.defines = "#define SGFX_OIT_ACCUM_UNIT " + std::to_string(kAccumUnit) +
                        "\n#define SGFX_OIT_REVEAL_UNIT " + std::to_string(kRevealUnit);
            return s;
        }();
        static const ShaderSnippet ms = [] {
            ShaderSnippet s = units;
            s.name = "oit_units_ms";
            s.defines += "\n#define SGFX_OIT_MULTISAMPLE";
            return s;
        }();
        return r.composer().program(base, std::array{multisample ? &ms : &units}, 0);
    }

    gl::FramebufferObject fbo_;
    gl::TextureObject accum_, reveal_;
    int width_ = 0, height_ = 0;
    GLenum revealFormat_ = 0;
    int samples_ = 1;
    GLuint depth_ = 0;
};

std::shared_ptr<TransparencyBin> TransparencyBin::create(TransparencyMode mode) {
    auto n = std::make_shared<TransparencyBin>();
    n->setMode(mode);
    return n;
}

TransparencyBin::TransparencyBin()
    : oitPass_(std::make_shared<OitPass>()) {
    StateSet& s = getOrCreateStateSet();
    s.renderBin.set(RenderBin::Transparent);
    s.blend.set(BlendMode::Alpha);
}

TransparencyBin::~TransparencyBin() = default;

void TransparencyBin::releaseGLObjects() {
    oitPass_->releaseGLObjects();
}

void TransparencyBin::setMode(TransparencyMode m) {
    if (std::uint8_t(m) > std::uint8_t(TransparencyMode::WeightedBlended))
        throw std::invalid_argument("sgfx: TransparencyBin::setMode: invalid mode value " +
                                    std::to_string(int(m)));
    mode_ = m;
}

void TransparencyBin::setOitParameters(const OitParameters& p) {
    p.validate();
    oit_ = p;
}

void TransparencyBin::setDetails(const TransparencyDetails& d) {
    d.validate();
    getOrCreateStateSet().transparency.set(d);
}

const ShaderSnippet& TransparencyBin::snippet() const {
    static const ShaderSnippet sorted = [] {
        ShaderSnippet s;
        s.name = "transparency_sorted"; // no code: the core's sorted stage does the work
        return s;
    }();
    static const ShaderSnippet oit = oitSnippet();
    return mode_ == TransparencyMode::WeightedBlended ? oit : sorted;
}

bool TransparencyBin::drawsBlended(BlendMode mode) const {
    return mode_ == TransparencyMode::WeightedBlended &&
           (mode == BlendMode::Alpha || mode == BlendMode::Premultiplied);
}

void TransparencyBin::planFrame(FramePlan& plan) const {
    // One accumulation per view for every weighted blended bin in it: their items blend
    // order-independently with each other too. The outermost bin's pass does it.
    if (mode_ != TransparencyMode::WeightedBlended || plan.has(oitPass_->name())) return;
    oitPass_->revealage8Bit = oit_.revealage8Bit;
    plan.add(oitPass_);
}

void TransparencyBin::applyUniforms(gl::Program& program, const DrawContext&) const {
    if (mode_ == TransparencyMode::WeightedBlended)
        program.set("sgfx_oitWeight", glm::vec2(float(equationOf(oit_.weight)), oit_.depthScale));
}

} // namespace sgfx

#include <sgfx/nodes/transparency/TransparencyBin.h>

#include "ParameterChecks.h"

#include <sgfx/FrameSetup.h>
#include <sgfx/Geometry.h>
#include <sgfx/PassCommands.h>
#include <sgfx/StateSet.h>
#include <sgfx/gl/Objects.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

namespace sgfx {

namespace {

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

namespace {

const BaseShader& compositeBase() {
    static const BaseShader base{"oit_composite", "blit.vert",
                                 std::string(ShaderComposer::fullscreenVertex()), "oit_composite.frag",
                                 text("oit_composite.frag")};
    return base;
}

const ShaderSnippet& compositeVariant(bool multisample) {
    static const ShaderSnippet single = [] {
        ShaderSnippet s;
        s.name = "oit_single";
        return s;
    }();
    static const ShaderSnippet ms = [] {
        ShaderSnippet s;
        s.name = "oit_multisample";
        s.defines = "#define SGFX_OIT_MULTISAMPLE";
        return s;
    }();
    return multisample ? ms : single;
}

} // namespace

// Accumulates every claimed item of the view into (Σ C·w, Σ α·w) and Π(1 − α), against the
// opaque depth (McGuire & Bavoil 2013), in the screen rectangle the items cover.
void TransparencyBin::addAccumulatePass(FrameSetup& f) const {
    struct Data {
        ResourceId accum, reveal, depth;
    };
    const int samples = f.view().samples; // a multisampled view gets multisampled sums
    f.addPass<Data>(
        "transparency OIT: accumulate", PassPhase::Transparent,
        [samples, r8 = oit_.revealage8Bit](PassBuilder& b, Data& d) {
            d.accum =
                b.colour(b.create("oit.accum", {.format = format::Rgba16F, .samples = samples}), 0, false);
            d.reveal = b.colour(
                b.create("oit.reveal", {.format = r8 ? format::R8 : format::R16F, .samples = samples}), 1,
                false);
            d.depth =
                b.depthTest(b.get(resources::DrawDepth)); // opaque and transmissive depth, never written
            // Transmissive materials in the bin read the copy of the opaque scene, and every item
            // what its effects sample (a shadow map).
            if (b.has(resources::TransmissionColour)) b.sample(resources::TransmissionColour);
            b.sampleMaterials(b.queue().claimed);
            b.publish("oit.accum", d.accum);
            b.publish("oit.reveal", d.reveal);
        },
        [](PassCommands& c, const Data& d) {
            const auto& items = c.queue().claimed;
            c.target({d.accum, d.reveal}, d.depth);
            // Whole-target clears: llvmpipe clears whole tiles at once, a scissored clear pixel by
            // pixel (5x slower at 720p).
            c.clearColour(glm::vec4(0.0f), 0);
            c.clearColour(glm::vec4(1.0f), 1);
            const glm::ivec4 rect = screenBounds(items, c.frame());
            if (rect.z <= 0 || rect.w <= 0) return;
            c.scissor(rect);
            using F = AttachmentBlend::Factor;
            c.blendAttachments({{F::One, F::One}, {F::Zero, F::OneMinusSrcColour}});
            c.depthState({.test = true, .write = false, .func = CompareFunc::Less});
            c.drawQueue(items, DrawMode::PassBlend);
        });
}

// The weighted average over the view with coverage 1 − Π(1 − α), in one full-screen pass.
void TransparencyBin::addCompositePass(FrameSetup& f) const {
    struct Data {
        ResourceId accum, reveal, colour;
    };
    f.addPass<Data>(
        "transparency OIT: composite", PassPhase::Transparent,
        [](PassBuilder& b, Data& d) {
            d.accum = b.sample(b.get("oit.accum"), "sgfx_oitAccum");
            d.reveal = b.sample(b.get("oit.reveal"), "sgfx_oitReveal");
            d.colour = b.write(resources::DrawColour);
        },
        [](PassCommands& c, const Data& d) {
            const glm::ivec4 rect = screenBounds(c.queue().claimed, c.frame());
            if (rect.z <= 0 || rect.w <= 0) return;
            gl::Program& program =
                c.program(compositeBase(), std::array{&compositeVariant(c.samples(d.accum) > 1)});
            c.target({d.colour});
            c.scissor(rect);
            c.bind(program, "sgfx_oitAccum", d.accum);
            c.bind(program, "sgfx_oitReveal", d.reveal);
            c.fullscreen(program, {.blend = BlendMode::Alpha});
        });
}

std::shared_ptr<TransparencyBin> TransparencyBin::create(TransparencyMode mode) {
    auto n = std::make_shared<TransparencyBin>();
    n->setMode(mode);
    return n;
}

TransparencyBin::TransparencyBin() {
    StateSet& s = getOrCreateStateSet();
    s.renderBin.set(RenderBin::Transparent);
    s.blend.set(BlendMode::Alpha);
}

TransparencyBin::~TransparencyBin() = default;

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

void TransparencyBin::setupFrame(FrameSetup& f) const {
    // One accumulation per view for every weighted blended bin in it: their items blend
    // order-independently with each other too. The outermost bin's passes do it.
    if (mode_ != TransparencyMode::WeightedBlended || f.queue().claimed.empty() ||
        !f.once("transparency OIT"))
        return;
    addAccumulatePass(f);
    addCompositePass(f);
}

void TransparencyBin::applyUniforms(gl::Program& program, const DrawContext&) const {
    if (mode_ == TransparencyMode::WeightedBlended)
        program.set("sgfx_oitWeight", glm::vec2(float(equationOf(oit_.weight)), oit_.depthScale));
}

} // namespace sgfx

#include <sgfx/nodes/fog/FogMath.h>
#include <sgfx/nodes/fog/FogNode.h>

#include "ParameterChecks.h"

#include <sgfx/FrameSetup.h>
#include <sgfx/PassCommands.h>
#include <sgfx/Renderer.h>
#include <sgfx/gl/Objects.h>

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

namespace {

const BaseShader& fullscreenBase(bool post) {
    static const BaseShader sky{"fog_sky", "blit.vert", fullscreenVertexWith("#define SGFX_FULLSCREEN_FAR"),
                                "fog_fullscreen.frag", text("fog_fullscreen.frag")};
    static const BaseShader postBase{"fog_post", "blit.vert", std::string(ShaderComposer::fullscreenVertex()),
                                     "fog_fullscreen.frag", text("fog_fullscreen.frag")};
    return post ? postBase : sky;
}

const ShaderSnippet& fullscreenDecl(bool post) {
    static const ShaderSnippet sky = snippetOf("fog_fullscreen", "", text("fog_optical_depth.glsl"));
    static const ShaderSnippet postDecl =
        snippetOf("fog_fullscreen_post", "#define SGFX_FOG_POST", text("fog_optical_depth.glsl"));
    return post ? postDecl : sky;
}

// The resource the split materials sample: the depth of the nearest surface of every item.
constexpr std::string_view kNearestDepth = "fog.nearestDepth";

} // namespace

// Seed §1's post-process: every pixel, from the resolved view depth, onto the view colour.
void FogNode::addPostPass(FrameSetup& f) const {
    struct Data {
        ResourceId depth, colour;
    };
    f.addPass<Data>(
        "fog post-process", PassPhase::AfterResolve,
        [](PassBuilder& b, Data& d) {
            d.depth = b.sample(b.get(resources::ViewDepth), "sgfx_fogSceneDepth");
            d.colour = b.write(resources::ViewColour); // a colour-only target: no depth feedback loop
        },
        [p = parameters_](PassCommands& c, const Data& d) {
            gl::Program& program = c.program(fullscreenBase(true), std::array{&fullscreenDecl(true)});
            c.target({d.colour});
            c.bind(program, "sgfx_fogSceneDepth", d.depth);
            setUniforms(program, p, c.frame().eye);
            c.fullscreen(program, {.blend = BlendMode::Alpha});
        });
}

// Forward mode, deferred opaque: seed §1 on the draw target after the opaque items, before the
// transmission copy (glass sees fogged opaque, as when the materials fogged it) and before the
// blended items, which fog themselves. Pixels at depth 1 take the sky rule of the sky pass, which
// this replaces; with `sky` false (another fog owns the sky) they are left alone.
void FogNode::addOpaquePass(FrameSetup& f, bool sky) const {
    struct Data {
        ResourceId depth, colour;
    };
    FogParameters p = parameters_;
    if (!sky) p.sky = FogSky::Off;
    f.addPass<Data>(
        "fog opaque", PassPhase::AfterOpaque,
        [](PassBuilder& b, Data& d) {
            d.depth = b.sample(b.get(resources::DrawDepth), "sgfx_fogSceneDepth");
            d.colour = b.write(resources::DrawColour); // a colour-only target: no depth feedback loop
        },
        [p](PassCommands& c, const Data& d) {
            gl::Program& program = c.program(fullscreenBase(true), std::array{&fullscreenDecl(true)});
            c.target({d.colour});
            c.bind(program, "sgfx_fogSceneDepth", d.depth);
            setUniforms(program, p, c.frame().eye);
            c.fullscreen(program, {.blend = BlendMode::Alpha});
        });
}

// Deferring is exact when the pass reaches every opaque fragment the materials would have fogged
// and nothing would have changed the colour after the fog: every opaque item is below this node,
// no effect after it in their sets has colour code, and the depth holds one sample a pixel. Only
// the opaque items' sets count: blended and transmissive items keep the forward fog (an OIT bin
// after the fog on the glass does not stop the opaque pass).
bool FogNode::canDefer(const RenderQueue& q, int samples) const {
    if (mode_ != FogMode::Forward || !deferOpaque_ || samples > 1) return false;
    std::vector<bool> used(q.effectSets.size(), false);
    for (const RenderItem& item : q.opaque) {
        if (item.effectSet >= used.size()) return false; // no effect set: not below this node
        used[item.effectSet] = true;
    }
    for (std::size_t i = 0; i < used.size(); ++i) {
        if (!used[i]) continue;
        const std::vector<const EffectNode*>& set = q.effectSets[i].effects;
        const auto self = std::find(set.begin(), set.end(), this);
        if (self == set.end() || std::any_of(std::next(self), set.end(), [](const EffectNode* e) {
                return !e->snippet().colorCode.empty();
            }))
            return false;
    }
    return true;
}

// The forward modes' sky: pixels still at the far plane after the opaque items.
void FogNode::addSkyPass(FrameSetup& f) const {
    struct Data {
        ResourceId colour, depth;
    };
    f.addPass<Data>(
        "fog sky", PassPhase::AfterOpaque,
        [](PassBuilder& b, Data& d) {
            d.depth = b.depthTest(b.get(resources::DrawDepth));
            d.colour = b.write(resources::DrawColour);
        },
        [p = parameters_](PassCommands& c, const Data& d) {
            gl::Program& program = c.program(fullscreenBase(false), std::array{&fullscreenDecl(false)});
            c.target({d.colour}, d.depth);
            setUniforms(program, p, c.frame().eye);
            c.fullscreen(program, {.blend = BlendMode::Alpha,
                                   .depth = {.test = true, .write = false, .func = CompareFunc::Equal}});
        });
}

// Seed §2's T_depth is the nearest surface of every item, blended and transmissive ones included
// (glass is fogged on [O, Pn]): the shared opaque scene depth, plus the other items' depth drawn
// over a copy of it when there are any.
void FogNode::addNearestDepth(FrameSetup& f) const {
    f.requestSceneDepth({.when = PassPhase::BeforeMain});
    const RenderQueue& q = f.queue();
    if (q.transparent.empty() && q.claimed.empty() && q.transmissive.empty()) {
        f.addPass("fog: nearest depth", PassPhase::BeforeMain,
                  [](PassBuilder& b) { b.publish(std::string(kNearestDepth), b.get(resources::SceneDepth)); },
                  {});
        return;
    }
    struct Data {
        ResourceId from, to;
    };
    f.addPass<Data>(
        "fog: blended depth", PassPhase::BeforeMain,
        [](PassBuilder& b, Data& d) {
            d.from = b.sample(b.get(resources::SceneDepth), "copy");
            d.to = b.depth(b.create(std::string(kNearestDepth), {.format = format::Depth32F}), false);
            b.publish(std::string(kNearestDepth), d.to);
        },
        [](PassCommands& c, const Data& d) {
            c.copyDepth(d.from, d.to);
            c.target({}, d.to);
            c.drawQueue(c.queue().transmissive, DrawMode::DepthOnly);
            c.drawQueue(c.queue().transparent, DrawMode::DepthOnly);
            c.drawQueue(c.queue().claimed, DrawMode::DepthOnly);
        });
}

std::shared_ptr<FogNode> FogNode::create(const FogParameters& parameters, FogMode mode) {
    auto n = std::make_shared<FogNode>();
    n->setParameters(parameters);
    n->setMode(mode);
    return n;
}

FogNode::FogNode() {
    // Fog covers the sky too: it must be planned when nothing under it is in view.
    setCullingActive(false);
}

FogNode::~FogNode() = default;

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
    static const ShaderSnippet forward = [] {
        ShaderSnippet sn = snippetOf("fog", "", text("fog_optical_depth.glsl"), text("fog_forward.glsl"));
        sn.transmittedCode = text("fog_forward_transmitted.glsl");
        return sn;
    }();
    static const ShaderSnippet split = [] {
        ShaderSnippet sn =
            snippetOf("fog_split", "", text("fog_optical_depth.glsl") + text("fog_split_decl.glsl"),
                      text("fog_split.glsl"));
        sn.samplers = {{"sgfx_fogNearestDepth", std::string(kNearestDepth)}};
        return sn;
    }();
    // Deferred opaque: the "fog opaque" pass fogs opaque and masked variants, which compile no fog.
    static const ShaderSnippet blended = [] {
        ShaderSnippet sn = snippetOf("fog_blended", "", text("fog_optical_depth.glsl"),
                                     "// blended and transmissive variants only\n"
                                     "#if defined(SGFX_BLEND) || defined(SGFX_TRANSMISSION)\n" +
                                         text("fog_forward.glsl") + "\n#endif");
        sn.transmittedCode = text("fog_forward_transmitted.glsl");
        return sn;
    }();
    static const ShaderSnippet post = snippetOf("fog_post", "", ""); // the pass does it all
    switch (mode_) {
    case FogMode::ForwardSplit:
        return split;
    case FogMode::PostProcess:
        return post;
    case FogMode::Forward:
        break;
    }
    return deferred_ ? blended : forward;
}

void FogNode::setupFrame(FrameSetup& f) const {
    // Cull visits outer nodes first: the outermost fog owns the view-wide passes.
    if (mode_ == FogMode::PostProcess) {
        if (f.once("fog post-process")) addPostPass(f);
        return;
    }
    const bool deferred = canDefer(f.queue(), f.view().samples); // compile() records the same choice
    if (mode_ == FogMode::ForwardSplit && f.once("fog: nearest depth")) addNearestDepth(f);
    const bool sky = parameters_.sky != FogSky::Off && f.once("fog sky");
    if (deferred)
        addOpaquePass(f, sky);
    else if (sky && !paintSkyWithClear(f))
        addSkyPass(f);
}

// The sky pass's result as the main pass's clear colour where that is exact (setClearSky): the
// pixels at the far plane after the opaque items then hold the camera's clear colour c, and the
// pass would blend (fog colour, k) over it: rgb = mix(c, fog, k), alpha = k + c.a·(1 − k).
// Exact needs: the view clears colour and depth (a pixel at depth 1 holds c), every opaque item
// is a plain geometry (a drawable may set its own depth state in its draw) drawn unblended with
// the default depth state (nothing colours a pixel it leaves at the far plane), no pass of this
// phase before the fog's, and colours in [0, 1] (a normalised target clamps the blend's inputs
// and the clear's result, which differ outside it).
bool FogNode::paintSkyWithClear(FrameSetup& f) const {
    const ViewInfo& v = f.view();
    const FogParameters& p = parameters_;
    if (!clearSky_ || !v.clearsColour || !v.clearsDepth || p.sky != FogSky::Distance) return false;
    for (const FrameSetup::DeclaredPass& pass : f.passes())
        if (pass.phase == PassPhase::AfterOpaque) return false;
    for (const RenderItem& it : f.queue().opaque) {
        if (it.drawable || !it.state || it.state->blendMode() != BlendMode::Off) return false;
        const DepthState d = it.state->depth.value.value_or(DepthState{});
        if (!d.test || !d.write || d.func != CompareFunc::Less) return false;
    }
    const glm::dvec4 c(v.clearColour), fogColour(glm::dvec3(p.color), 1.0);
    for (int i = 0; i < 4; ++i)
        if (!(c[i] >= 0.0 && c[i] <= 1.0 && fogColour[i] >= 0.0 && fogColour[i] <= 1.0)) return false;
    const glm::dmat4 viewMatrix(v.view);
    const glm::dvec3 eye(glm::inverse(viewMatrix)[3]);
    const glm::dvec3 up(p.up);
    // Two pixels' margin: anti-aliasing's jitter moves the rays by under one.
    const double extent = 1.0 + 4.0 / std::max(1, std::min(v.drawSize.x, v.drawSize.y));
    const glm::dvec2 elevation =
        fog::elevationRange(glm::inverse(glm::dmat4(v.projection) * viewMatrix), eye, up, extent);
    const double eyeHeight = fog::heightOf(eye, up, double(p.referenceHeight));
    const auto response =
        p.response == FogResponse::Linear ? fog::Response::Linear : fog::Response::Exponential;
    const glm::dvec2 k = fog::skyAmountRange(p.density, p.falloff, eyeHeight, elevation, p.skyDistance,
                                             response, p.maxOpacity);
    double step = 0.0; // the most a unit of k moves a channel
    for (int i = 0; i < 4; ++i)
        step = std::max(step, std::abs(fogColour[i] - c[i]));
    if (!((k.y - k.x) * step <= 1e-4)) return false;
    const double kSky = 0.5 * (k.x + k.y);
    f.setClearColour(glm::vec4(glm::vec3(glm::mix(glm::dvec3(c), glm::dvec3(p.color), kSky)),
                               float(kSky + c.a * (1.0 - kSky))));
    return true;
}

// The view's queue and draw target are the ones setupFrame saw: the choice is the same.
void FogNode::compile(Renderer& renderer) const {
    deferred_ = canDefer(renderer.queue(), renderer.currentTarget().samples);
}

void FogNode::applyUniforms(gl::Program& program, const DrawContext& context) const {
    if (mode_ == FogMode::PostProcess) return;
    if (deferred_ && program.location("sgfx_fogDensity") < 0) return; // an opaque variant: no fog code
    setUniforms(program, parameters_, context.frame.eye);
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

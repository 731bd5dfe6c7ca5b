#include <sgfx/nodes/ao/AmbientOcclusionNode.h>

#include "ParameterChecks.h"

#include <sgfx/FrameSetup.h>
#include <sgfx/PassCommands.h>
#include <sgfx/gl/Objects.h>

#include <sgfx_glad/gl.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <stdexcept>
#include <string>

namespace sgfx {

namespace {

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
    if (std::uint8_t(normals) > std::uint8_t(AoNormals::FromDepth))
        refuse("normals has an invalid value " + std::to_string(int(normals)));
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

constexpr int kTemporalSamples = 8; // taps per frame of the temporal occlusion

// What the three passes share: per-view-size targets, the kernel and the noise texture.
// GPU objects and CPU caches the passes keep between frames; touched only while they execute.
struct AmbientOcclusionNode::Shared {
    gl::TextureObject noise;
    std::uint32_t noiseSeed = 0;
    std::vector<glm::vec3> kernel;
    AoKernel kernelKind{};
    int kernelSamples = 0;
    std::uint32_t kernelSeed = 0;

    // Temporal history (AmbientOcclusionParameters::temporal): two (k, depth, age) textures in
    // turn, read one and write the other; and what they were made under.
    std::array<gl::TextureObject, 2> history;
    int current = 0;
    bool historyValid = false;
    glm::ivec2 historySize{0};
    glm::mat4 previousView{1.0f}, previousProjection{1.0f};
    AmbientOcclusionParameters historyParameters;
    std::vector<glm::vec3> frameKernel;

    void release() {
        noise.reset();
        history = {};
        historyValid = false;
    }

    // Whether last frame's history may be blended into this one; (re)makes the textures.
    bool keepHistory(const AmbientOcclusionParameters& p, glm::ivec2 size, const glm::mat4& view) {
        const auto& h = historyParameters;
        const bool same = historyValid && size == historySize && h.seed == p.seed && h.radius == p.radius &&
                          h.bias == p.bias && h.kernel == p.kernel && h.compare == p.compare &&
                          h.rangeCheck == p.rangeCheck && h.normals == p.normals && h.gbuffer == p.gbuffer;
        // A camera cut, or a jump no history can follow (TAA's rule): eye > 2 m, turn > 15°.
        const glm::vec3 eye = glm::vec3(glm::inverse(view)[3]),
                        lastEye = glm::vec3(glm::inverse(previousView)[3]);
        const glm::vec3 forward = glm::vec3(glm::transpose(view)[2]),
                        lastForward = glm::vec3(glm::transpose(previousView)[2]);
        const bool cut = glm::length(eye - lastEye) > 2.0f ||
                         glm::dot(forward, lastForward) < std::cos(glm::radians(15.0f));
        if (!history[0] || size != historySize)
            for (gl::TextureObject& t : history)
                t = gl::createTexture2D(GL_RGBA32F, size.x, size.y);
        historySize = size, historyParameters = p, historyValid = true;
        return same && !cut;
    }

    // Frame f's taps: set f mod 8 of the interleaved 8·m kernel, so 8 frames use all of it.
    const std::vector<glm::vec3>& kernelForFrame(const AmbientOcclusionParameters& p, std::uint64_t frame) {
        AmbientOcclusionParameters all = p;
        all.samples = 8 * kTemporalSamples;
        const std::vector<glm::vec3>& k = kernelFor(all);
        frameKernel.clear();
        for (std::size_t i = frame % 8; i < k.size(); i += 8)
            frameKernel.push_back(k[i]);
        return frameKernel;
    }

    // The seed's §2 rotation vectors V_r, a 4×4 texture the occlusion pass tiles over the view.
    GLuint noiseTexture(std::uint32_t seed) {
        if (!noise || noiseSeed != seed) {
            const std::vector<glm::vec2> n = ao::rotationNoise(seed);
            noise = gl::createTexture2D(GL_RG32F, 4, 4);
            // GL: node-owned data (the noise texels); no texture upload command
            glTextureSubImage2D(noise.get(), 0, 0, 0, 4, 4, GL_RG, GL_FLOAT, n.data());
            noiseSeed = seed;
        }
        return noise.get();
    }

    const std::vector<glm::vec3>& kernelFor(const AmbientOcclusionParameters& p) {
        if (kernel.empty() || kernelKind != p.kernel || kernelSamples != p.samples || kernelSeed != p.seed) {
            kernel = ao::kernel(p.kernel, p.samples, p.seed);
            kernelKind = p.kernel, kernelSamples = p.samples, kernelSeed = p.seed;
        }
        return kernel;
    }
};

namespace {

constexpr std::string_view kRaw = "ao.raw"; // the occlusion before the blur
constexpr std::string_view kMap = "ao.map"; // what the materials read: (k, linear depth)

constexpr std::string_view kNormal = "ao.normal"; // FromDepth: normals rebuilt at map size
constexpr std::string_view kDepth = "ao.depth";   // FromDepth: linear depth at map size

bool half(const AmbientOcclusionParameters& p) {
    return p.halfResolution || p.temporal;
}

TextureDesc mapDesc(const AmbientOcclusionParameters& p, unsigned fmt = format::Rg32F) {
    return {.format = fmt, .size = half(p) ? SizeRule::half(SizeRule::Round::Up) : SizeRule::draw()};
}

} // namespace

// AoNormals::FromDepth: normals and linear depth at map size rebuilt from the scene depth pre-pass.
void AmbientOcclusionNode::addNormalsPass(FrameSetup& f) const {
    struct Data {
        ResourceId depth, normal, linear;
    };
    f.addPass<Data>(
        "ao normals", PassPhase::BeforeMain,
        [p = parameters_](PassBuilder& b, Data& d) {
            d.depth = b.sample(b.get(resources::SceneDepth), "sgfx_aoSceneDepth");
            d.normal = b.colour(b.create(std::string(kNormal), mapDesc(p, format::Rgba16F)), 0, false);
            d.linear = b.colour(b.create(std::string(kDepth), mapDesc(p, format::R32F)), 1, false);
            b.publish(std::string(kNormal), d.normal);
            b.publish(std::string(kDepth), d.linear);
        },
        [p = parameters_](PassCommands& c, const Data& d) {
            static const BaseShader base = fullscreen("ao_normals", "ao_normals.frag");
            gl::Program& program = c.program(base);
            c.target({d.normal, d.linear});
            c.bind(program, "sgfx_aoSceneDepth", d.depth);
            program.set("sgfx_aoScale", half(p) ? 2 : 1);
            c.fullscreen(program);
        });
}

// Seed §2: the occlusion map, from the scene's G-buffer (§1: view-space normals and depth, or
// positions), or from normals and depth rebuilt from the depth pre-pass.
void AmbientOcclusionNode::addOcclusionPass(FrameSetup& f) const {
    struct Data {
        ResourceId normals, depth, positions, raw;
    };
    const bool fromDepth = parameters_.normals == AoNormals::FromDepth;
    const glm::ivec2 drawSize = f.view().drawSize;
    const std::uint64_t frame = f.view().frameNumber;
    f.addPass<Data>(
        "ao occlusion", PassPhase::BeforeMain,
        [p = parameters_, fromDepth](PassBuilder& b, Data& d) {
            d.normals = b.sample(b.get(fromDepth ? kNormal : resources::SceneNormals), "sgfx_aoGNormal");
            d.depth = b.sample(b.get(fromDepth ? kDepth : resources::SceneLinearDepth), "sgfx_aoGDepth");
            if (p.gbuffer == AoGBuffer::PaperPositions && !fromDepth)
                d.positions = b.sample(b.get(resources::ScenePositions), "sgfx_aoGPosition");
            d.raw = b.colour(b.create(std::string(kRaw), mapDesc(p)), 0, false);
            b.publish(std::string(kRaw), d.raw);
            if (p.blurSize <= 1 && !p.temporal) b.publish(std::string(kMap), d.raw);
        },
        [p = parameters_, shared = shared_, fromDepth, drawSize, frame](PassCommands& c, const Data& d) {
            static const BaseShader base = fullscreen("ao_occlusion", "ao_occlusion.frag");
            static const ShaderSnippet depth = definesOnly("ao_depth", "");
            static const ShaderSnippet positions = definesOnly("ao_positions", "#define SGFX_AO_POSITIONS");
            gl::Program& program = c.program(base, std::array{d.positions.valid() ? &positions : &depth});
            c.target({d.raw});
            c.bind(program, "sgfx_aoGNormal", d.normals);
            c.bind(program, "sgfx_aoGDepth", d.depth);
            if (d.positions.valid()) c.bind(program, "sgfx_aoGPosition", d.positions);
            c.bindTexture(program, "sgfx_aoNoise", shared->noiseTexture(p.seed));
            const std::vector<glm::vec3>& k =
                p.temporal ? shared->kernelForFrame(p, frame) : shared->kernelFor(p);
            for (std::size_t i = 0; i < k.size(); ++i)
                program.set("sgfx_aoKernel[" + std::to_string(i) + "]", k[i]);
            program.set("sgfx_aoSamples", int(k.size()));
            program.set("sgfx_aoShape", glm::vec4(p.radius, p.bias, p.rangeCheck ? 1.0f : 0.0f,
                                                  p.compare == AoCompare::TangentPlane ? 1.0f : 0.0f));
            const bool paperLike = p.compare == AoCompare::StoredDepth && !p.rangeCheck;
            const float scale = half(p) ? 2.0f : 1.0f;
            program.set("sgfx_aoShape2", glm::vec4(scale, paperLike ? 0.0f : 1.0f, 0, 0));
            program.set("sgfx_aoGrid", glm::vec4(glm::vec2(drawSize), fromDepth ? scale : 1.0f, 0.0f));
            c.fullscreen(program);
        });
}

// Temporal: this frame's taps blended into the reprojected history, into the map the materials
// read (at half size: they upsample it by depth).
void AmbientOcclusionNode::addAccumulatePass(FrameSetup& f) const {
    struct Data {
        ResourceId raw, map;
    };
    const ViewInfo& v = f.view();
    f.addPass<Data>(
        "ao accumulate", PassPhase::BeforeMain,
        [p = parameters_](PassBuilder& b, Data& d) {
            d.raw = b.sample(b.get(kRaw), "sgfx_aoRaw");
            d.map = b.colour(b.create(std::string(kMap), mapDesc(p)), 0, false);
            b.publish(std::string(kMap), d.map);
        },
        [p = parameters_, shared = shared_, drawSize = v.drawSize, view = v.view,
         projection = v.projection](PassCommands& c, const Data& d) {
            static const BaseShader base = fullscreen("ao_accumulate", "ao_accumulate.frag");
            Shared& s = *shared;
            const bool keep = s.keepHistory(p, c.size(d.map), view);
            gl::Program& program = c.program(base);
            c.target({d.map});
            c.bind(program, "sgfx_aoRaw", d.raw);
            c.bindTexture(program, "sgfx_aoHistory", s.history[std::size_t(s.current)].get());
            // GL: a node-owned history written as an image (the frame graph's targets last one
            // frame); the barrier makes last frame's image writes visible to this frame's fetches.
            glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
            glBindImageTexture(0, s.history[std::size_t(1 - s.current)].get(), 0, GL_FALSE, 0, GL_WRITE_ONLY,
                               GL_RGBA32F);
            program.set("sgfx_aoHistoryOut", 0);
            program.set("sgfx_aoReproject", s.previousView * glm::inverse(view));
            program.set("sgfx_aoPreviousProjection", s.previousProjection);
            program.set("sgfx_aoTemporal", glm::vec4(glm::vec2(drawSize), 2.0f, keep ? 0.0f : 1.0f));
            c.fullscreen(program);
            s.current = 1 - s.current;
            s.previousView = view, s.previousProjection = projection;
        });
}

// Seed §3: the blur, separable: along x, then along y into the map the materials read.
void AmbientOcclusionNode::addBlurPasses(FrameSetup& f) const {
    struct Data {
        ResourceId from, to;
    };
    for (int axis = 0; axis < 2; ++axis)
        f.addPass<Data>(
            axis == 0 ? "ao blur x" : "ao blur y", PassPhase::BeforeMain,
            [p = parameters_, axis](PassBuilder& b, Data& d) {
                d.from = b.sample(b.get(axis == 0 ? kRaw : "ao.half"), "sgfx_aoRaw");
                const std::string out(axis == 0 ? "ao.half" : kMap);
                d.to = b.colour(b.create(out, mapDesc(p)), 0, false);
                b.publish(out, d.to);
            },
            [p = parameters_, axis](PassCommands& c, const Data& d) {
                static const BaseShader base = fullscreen("ao_blur", "ao_blur.frag");
                static const ShaderSnippet bilateral = definesOnly("ao_bilateral", "");
                static const ShaderSnippet box = definesOnly("ao_box", "#define SGFX_AO_BOX");
                gl::Program& program = c.program(base, std::array{p.blur == AoBlur::Box ? &box : &bilateral});
                c.target({d.to});
                c.bind(program, "sgfx_aoRaw", d.from);
                program.set("sgfx_aoBlur", glm::vec4(float(p.blurSize), p.radius, axis == 0 ? 1.0f : 0.0f,
                                                     axis == 0 ? 0.0f : 1.0f));
                c.fullscreen(program);
            });
}

// The map over the view, opaque grey (seed figures 5 and 7).
void AmbientOcclusionNode::addDebugPass(FrameSetup& f) const {
    struct Data {
        ResourceId map, colour;
    };
    const bool raw =
        parameters_.debugView == AoDebugView::Raw || (parameters_.blurSize == 1 && !parameters_.temporal);
    f.addPass<Data>(
        "ao debug view", PassPhase::AfterResolve,
        [raw](PassBuilder& b, Data& d) {
            d.map = b.sample(b.get(raw ? kRaw : kMap), "sgfx_aoShown");
            d.colour = b.write(resources::ViewColour);
        },
        [](PassCommands& c, const Data& d) {
            static const BaseShader base = fullscreen("ao_debug", "ao_debug.frag");
            gl::Program& program = c.program(base);
            c.target({d.colour});
            c.bind(program, "sgfx_aoShown", d.map);
            c.fullscreen(program);
        });
}

// ------------------------------------------------------------------------------ node

std::shared_ptr<AmbientOcclusionNode>
AmbientOcclusionNode::create(const AmbientOcclusionParameters& parameters) {
    auto n = std::make_shared<AmbientOcclusionNode>();
    n->setParameters(parameters);
    return n;
}

AmbientOcclusionNode::AmbientOcclusionNode()
    : shared_(std::make_shared<Shared>()) {}

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
        sn.defines = "#define SGFX_AMBIENT_OCCLUSION 1";
        sn.samplers = {{"sgfx_aoMap", std::string(kMap)}};
        sn.fragmentDecl = text("ao_apply.glsl");
        sn.ambientCode = text("ao_ambient.glsl");
        return sn;
    }();
    return s;
}

void AmbientOcclusionNode::setupFrame(FrameSetup& f) const {
    // The outermost node in view computes the map for the whole view.
    if (!f.once("ambient occlusion")) return;
    const bool gbuffer = parameters_.normals == AoNormals::GBuffer;
    f.requestSceneDepth({.normals = gbuffer,
                         .linearDepth = gbuffer,
                         .positions = gbuffer && parameters_.gbuffer == AoGBuffer::PaperPositions,
                         .when = PassPhase::BeforeMain});
    if (!gbuffer) addNormalsPass(f);
    addOcclusionPass(f);
    if (parameters_.temporal)
        addAccumulatePass(f);
    else if (parameters_.blurSize > 1)
        addBlurPasses(f);
    if (parameters_.debugView != AoDebugView::Off) addDebugPass(f);
}

void AmbientOcclusionNode::compile(Renderer&) const {
    shared_->noiseTexture(parameters_.seed); // the rotation noise, before the occlusion pass reads it
}

void AmbientOcclusionNode::applyUniforms(gl::Program& program, const DrawContext&) const {
    program.set("sgfx_aoApply", glm::vec2(parameters_.intensity, parameters_.power));
}

} // namespace sgfx

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
// GPU objects and CPU caches the passes keep between frames; touched only while they execute.
struct AmbientOcclusionNode::Shared {
    gl::TextureObject noise;
    std::uint32_t noiseSeed = 0;
    std::vector<glm::vec3> kernel;
    AoKernel kernelKind{};
    int kernelSamples = 0;
    std::uint32_t kernelSeed = 0;

    void release() { noise.reset(); }

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

TextureDesc mapDesc(const AmbientOcclusionParameters& p) {
    return {.format = format::Rg32F,
            .size = p.halfResolution ? SizeRule::half(SizeRule::Round::Up) : SizeRule::draw()};
}

} // namespace

// Seed §2: the occlusion map, from the scene's G-buffer (§1: view-space normals and depth, or
// positions).
void AmbientOcclusionNode::addOcclusionPass(FrameSetup& f) const {
    struct Data {
        ResourceId normals, depth, positions, raw;
    };
    f.addPass<Data>(
        "ao occlusion", PassPhase::BeforeMain,
        [p = parameters_](PassBuilder& b, Data& d) {
            d.normals = b.sample(b.get(resources::SceneNormals), "sgfx_aoGNormal");
            d.depth = b.sample(b.get(resources::SceneLinearDepth), "sgfx_aoGDepth");
            if (p.gbuffer == AoGBuffer::PaperPositions)
                d.positions = b.sample(b.get(resources::ScenePositions), "sgfx_aoGPosition");
            d.raw = b.colour(b.create(std::string(kRaw), mapDesc(p)), 0, false);
            b.publish(std::string(kRaw), d.raw);
            if (p.blurSize <= 1) b.publish(std::string(kMap), d.raw);
        },
        [p = parameters_, shared = shared_](PassCommands& c, const Data& d) {
            static const BaseShader base = fullscreen("ao_occlusion", "ao_occlusion.frag");
            static const ShaderSnippet depth = definesOnly("ao_depth", "");
            static const ShaderSnippet positions = definesOnly("ao_positions", "#define SGFX_AO_POSITIONS");
            gl::Program& program = c.program(base, std::array{d.positions.valid() ? &positions : &depth});
            c.target({d.raw});
            c.bind(program, "sgfx_aoGNormal", d.normals);
            c.bind(program, "sgfx_aoGDepth", d.depth);
            if (d.positions.valid()) c.bind(program, "sgfx_aoGPosition", d.positions);
            c.bindTexture(program, "sgfx_aoNoise", shared->noiseTexture(p.seed));
            const std::vector<glm::vec3>& k = shared->kernelFor(p);
            for (std::size_t i = 0; i < k.size(); ++i)
                program.set("sgfx_aoKernel[" + std::to_string(i) + "]", k[i]);
            program.set("sgfx_aoSamples", p.samples);
            program.set("sgfx_aoShape", glm::vec4(p.radius, p.bias, p.rangeCheck ? 1.0f : 0.0f,
                                                  p.compare == AoCompare::TangentPlane ? 1.0f : 0.0f));
            const bool paperLike = p.compare == AoCompare::StoredDepth && !p.rangeCheck;
            program.set("sgfx_aoShape2",
                        glm::vec4(p.halfResolution ? 2.0f : 1.0f, paperLike ? 0.0f : 1.0f, 0, 0));
            c.fullscreen(program);
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
    const bool raw = parameters_.debugView == AoDebugView::Raw || parameters_.blurSize == 1;
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
    f.requestSceneDepth({.normals = true,
                         .linearDepth = true,
                         .positions = parameters_.gbuffer == AoGBuffer::PaperPositions,
                         .when = PassPhase::BeforeMain});
    addOcclusionPass(f);
    if (parameters_.blurSize > 1) addBlurPasses(f);
    if (parameters_.debugView != AoDebugView::Off) addDebugPass(f);
}

void AmbientOcclusionNode::compile(Renderer&) const {
    shared_->noiseTexture(parameters_.seed); // the rotation noise, before the occlusion pass reads it
}

void AmbientOcclusionNode::applyUniforms(gl::Program& program, const DrawContext&) const {
    program.set("sgfx_aoApply", glm::vec2(parameters_.intensity, parameters_.power));
}

} // namespace sgfx

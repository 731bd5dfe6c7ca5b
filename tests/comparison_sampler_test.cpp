// Depth-comparison sampling (SnippetSampler::comparison, PassCommands::bindComparison), the way a
// shadow map is read (OSMesa): one depth resource read in the same draw through the renderer's
// comparison sampler object (sampler2DShadow, GL_LEQUAL, linear 2×2 percentage-closer filter) and
// plainly with the texture's own nearest state; no sampler object is left on a unit that a later
// pass or material reads plainly; the sampler object is counted and dies with the renderer.
#include "TestUtil.h"

#include <sgfx/Effect.h>
#include <sgfx/FrameSetup.h>
#include <sgfx/Group.h>
#include <sgfx/PassCommands.h>
#include <sgfx/Shapes.h>
#include <sgfx/gl/Objects.h>

#include <sgfx_glad/gl.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <memory>
#include <string>

using namespace sgfx;
using namespace sgfx::test;

namespace {

constexpr int kSize = 64;
constexpr int kCaseWidth = kSize / 4; // four test cases side by side, 16 px each

// The depth map the tests read: 8×2 texels, the left four columns 0.25 and the right four 0.5
// (exact in D32F). Texel centres are at u = (i + 0.5) / 8.
constexpr float kLeftDepth = 0.25f, kRightDepth = 0.5f;
constexpr const char* kMap = "test.shadow";

// The cases, one per quarter of the view: (u, reference) at v = 0.5.
//   0: u = 0.75 (texels 5 and 6 only: 0.5), ref 0.25 < 0.5   -> LEQUAL passes: 1
//   1: u = 0.75,                            ref 0.75 > 0.5   -> fails: 0
//   2: u = 0.75,                            ref 0.5 == 0.5   -> passes: 1
//   3: u = 0.4875 (8u - 0.5 = 3.4: texel 3 (0.25) weighted 0.6, texel 4 (0.5) 0.4), ref 0.375:
//      fails on texel 3, passes on texel 4 -> bilinear PCF 0.4
// The plain reads: nearest at u = 0.75 -> 0.5, at u = 0.4875 -> texel 3, 0.25.
constexpr double kBoundaryU = 0.4875;
const std::array<double, 4> kExpectedComparison = {1.0, 0.0, 1.0, 0.4};
const char* const kCasesGlsl = "const vec2 sgfx_testCases[4] = vec2[4](vec2(0.75, 0.25), vec2(0.75, 0.75),\n"
                               "    vec2(0.75, 0.5), vec2(0.4875, 0.375));\n";

// Filtering precision: GL leaves the sub-texel precision of linear filtering to the
// implementation (llvmpipe: 8 bits); a 2×2 comparison filter weights its four results bilinearly.
constexpr double kFilterTolerance = 1.0 / 128.0;

// Writes the depth map: a clear to 0.5, then the left half (scissored) to 0.25.
void declareDepthMap(FrameSetup& f) {
    struct Data {
        ResourceId map;
    };
    f.addPass<Data>(
        "test depth map", PassPhase::BeforeMain,
        [](PassBuilder& b, Data& d) {
            d.map = b.depth(b.create(kMap, {.format = format::Depth32F, .size = SizeRule::fixedSize(8, 2)}),
                            false);
            b.publish(kMap, d.map);
        },
        [](PassCommands& c, const Data& d) {
            c.target({}, d.map);
            c.clearDepth(kRightDepth);
            c.scissor({0, 0, 4, 2});
            c.clearDepth(kLeftDepth);
        });
}

BaseShader fullscreenShader(std::string name, std::string fragment) {
    return BaseShader{name, "blit.vert", std::string(ShaderComposer::fullscreenVertex()), name + ".frag",
                      std::move(fragment)};
}

// Two full-screen passes before the main pass: "test compare" reads the map through
// bindComparison on its first unit and plainly on its second into a 4×1 target (one texel per
// case: comparison, plain at 0.75, plain at the boundary); "test plain" then reads the map plainly
// on the first unit, where the comparison sampler was, into a 1×1 target.
void declareCommandPasses(FrameSetup& f) {
    struct Data {
        ResourceId map, out;
    };
    f.addPass<Data>(
        "test compare", PassPhase::BeforeMain,
        [](PassBuilder& b, Data& d) {
            d.map = b.sample(b.get(kMap), "sgfx_testShadow");
            d.out = b.colour(
                b.create("test.compared", {.format = format::Rgba32F, .size = SizeRule::fixedSize(4, 1)}), 0,
                false);
            b.publish("test.compared", d.out);
        },
        [](PassCommands& c, const Data& d) {
            static const BaseShader base = fullscreenShader(
                "test_compare", std::string("#version 450 core\n"
                                            "layout(location = 0) out vec4 outColour;\n"
                                            "uniform sampler2DShadow sgfx_testShadow;\n"
                                            "uniform sampler2D sgfx_testDepth;\n") +
                                    kCasesGlsl +
                                    "void main() {\n"
                                    "    vec2 c = sgfx_testCases[int(gl_FragCoord.x)];\n"
                                    "    outColour = vec4(texture(sgfx_testShadow, vec3(c.x, 0.5, c.y)),\n"
                                    "        texture(sgfx_testDepth, vec2(0.75, 0.5)).r,\n"
                                    "        texture(sgfx_testDepth, vec2(0.4875, 0.5)).r, 1.0);\n"
                                    "}\n");
            gl::Program& program = c.program(base);
            c.target({d.out});
            c.bindComparison(program, "sgfx_testShadow", d.map);
            c.bind(program, "sgfx_testDepth", d.map);
            c.fullscreen(program);
        });
    f.addPass<Data>(
        "test plain", PassPhase::BeforeMain,
        [](PassBuilder& b, Data& d) {
            d.map = b.sample(b.get(kMap), "sgfx_testPlain");
            d.out = b.colour(
                b.create("test.plain", {.format = format::Rgba32F, .size = SizeRule::fixedSize(1, 1)}), 0,
                false);
            b.publish("test.plain", d.out);
        },
        [](PassCommands& c, const Data& d) {
            static const BaseShader base = fullscreenShader(
                "test_plain", "#version 450 core\n"
                              "layout(location = 0) out vec4 outColour;\n"
                              "uniform sampler2D sgfx_testPlain;\n"
                              "void main() {\n"
                              "    outColour = vec4(texture(sgfx_testPlain, vec2(0.4875, 0.5)).r,\n"
                              "        texture(sgfx_testPlain, vec2(0.75, 0.5)).r, 0.0, 1.0);\n"
                              "}\n");
            gl::Program& program = c.program(base);
            c.target({d.out});
            c.bind(program, "sgfx_testPlain", d.map);
            c.fullscreen(program);
        });
}

// What the probe's material snippet does.
enum class Probe {
    // the map through a comparison sampler and plainly in one draw: (comparison, plain at 0.75,
    // plain at the boundary) per case
    Comparison,
    // the map plainly only, on the unit the comparison sampler had: (plain at the boundary, plain
    // at 0.75, 0)
    Plain,
    // what the two command passes wrote: the left half of each case shows test.compared's texel
    // of the case, the right half test.plain
    Commands,
};

ShaderSnippet probeSnippet(Probe probe) {
    ShaderSnippet sn;
    sn.fragmentDecl = kCasesGlsl;
    switch (probe) {
    case Probe::Comparison:
        sn.name = "test_probe_comparison";
        sn.fragmentDecl += "uniform sampler2DShadow sgfx_testShadow;\nuniform sampler2D sgfx_testDepth;\n";
        sn.colorCode = "vec2 testCase = sgfx_testCases[clamp(int(gl_FragCoord.x) / 16, 0, 3)];\n"
                       "sgfx_color = vec4(texture(sgfx_testShadow, vec3(testCase.x, 0.5, testCase.y)),\n"
                       "    texture(sgfx_testDepth, vec2(0.75, 0.5)).r,\n"
                       "    texture(sgfx_testDepth, vec2(0.4875, 0.5)).r, 1.0);\n";
        // The comparison first, so it has the first frame-resource unit (the Plain probe's next frame).
        sn.samplers = {{.uniform = "sgfx_testShadow", .resource = kMap, .comparison = true},
                       {.uniform = "sgfx_testDepth", .resource = kMap}};
        break;
    case Probe::Plain:
        sn.name = "test_probe_plain";
        sn.fragmentDecl += "uniform sampler2D sgfx_testPlain;\n";
        sn.colorCode = "sgfx_color = vec4(texture(sgfx_testPlain, vec2(0.4875, 0.5)).r,\n"
                       "    texture(sgfx_testPlain, vec2(0.75, 0.5)).r, 0.0, 1.0);\n";
        sn.samplers = {{.uniform = "sgfx_testPlain", .resource = kMap}};
        break;
    case Probe::Commands:
        sn.name = "test_probe_commands";
        sn.fragmentDecl += "uniform sampler2D sgfx_testCompared;\nuniform sampler2D sgfx_testPlainPass;\n";
        sn.colorCode = "int testCase = clamp(int(gl_FragCoord.x) / 16, 0, 3);\n"
                       "sgfx_color = int(gl_FragCoord.x) % 16 < 8\n"
                       "    ? vec4(texelFetch(sgfx_testCompared, ivec2(testCase, 0), 0).rgb, 1.0)\n"
                       "    : vec4(texelFetch(sgfx_testPlainPass, ivec2(0), 0).rgb, 1.0);\n";
        sn.samplers = {{.uniform = "sgfx_testCompared", .resource = "test.compared"},
                       {.uniform = "sgfx_testPlainPass", .resource = "test.plain"}};
        break;
    }
    return sn;
}

class ProbeEffect : public EffectNode {
public:
    explicit ProbeEffect(Probe probe)
        : probe_(probe)
        , snippet_(probeSnippet(probe)) {}
    std::string_view kind() const override { return "comparison probe"; }
    const ShaderSnippet& snippet() const override { return snippet_; }
    void setupFrame(FrameSetup& f) const override {
        declareDepthMap(f);
        if (probe_ == Probe::Commands) declareCommandPasses(f);
    }

private:
    Probe probe_;
    ShaderSnippet snippet_;
};

// A probe over a quad that fills the view; float colour, so the pixels are the values the
// snippet wrote.
std::shared_ptr<Node> probeScene(Probe probe) {
    auto effect = std::make_shared<ProbeEffect>(probe);
    effect->addChild(shapes::quad(4, 4));
    return effect;
}

std::unique_ptr<Viewer> probeViewer() {
    auto v = orthoTopViewer(kSize, 1.0f);
    v->renderer().options().colorTarget = RendererOptions::ColorTarget::Rgba32F;
    return v;
}

glm::dvec3 pixel(const FloatImage& img, int x) {
    const float* p = &img.rgba[(std::size_t(kSize / 2) * std::size_t(kSize) + std::size_t(x)) * 4];
    return {p[0], p[1], p[2]};
}

// Texture units, of all the renderer tracks, that have a sampler object bound.
int unitsWithASampler() {
    GLint units = 0;
    glGetIntegerv(GL_MAX_COMBINED_TEXTURE_IMAGE_UNITS, &units);
    int bound = 0;
    for (int u = 0; u < std::min(units, 48); ++u) {
        glActiveTexture(GLenum(GL_TEXTURE0 + u));
        GLint sampler = 0;
        glGetIntegerv(GL_SAMPLER_BINDING, &sampler);
        bound += sampler != 0;
    }
    glActiveTexture(GL_TEXTURE0);
    return bound;
}

void expectComparisonProbe(const FloatImage& img) {
    for (int c = 0; c < 4; ++c) {
        const glm::dvec3 p = pixel(img, c * kCaseWidth + kCaseWidth / 2);
        if (c < 3)
            EXPECT_EQ(p.r, kExpectedComparison[std::size_t(c)]) << "comparison, case " << c;
        else
            EXPECT_NEAR(p.r, kExpectedComparison[3], kFilterTolerance) << "2×2 comparison filter";
        EXPECT_EQ(p.g, kRightDepth) << "plain read in the same draw, case " << c;
        EXPECT_EQ(p.b, kLeftDepth) << "plain read at the boundary is nearest, case " << c;
    }
}

} // namespace

TEST(ComparisonSampler, ASnippetReadsOneDepthResourceWithAndWithoutComparisonInOneDraw) {
    auto v = probeViewer();
    v->setSceneData(probeScene(Probe::Comparison));
    v->frame(0.0);
    expectNoGlErrors(*v);
    expectComparisonProbe(v->renderer().readPixelsLinear());
    EXPECT_GE(unitsWithASampler(), 1) << "the comparison sampler is on its unit after the draw";
    EXPECT_EQ(gl::liveObjects()[gl::Kind::Sampler], 1);

    // The next frame, another effect reads the same map plainly on the same unit (the first
    // frame-resource unit): no sampler object is left there, so it reads the nearest texels.
    v->setSceneData(probeScene(Probe::Plain));
    v->frame(0.1);
    expectNoGlErrors(*v);
    const FloatImage plain = v->renderer().readPixelsLinear();
    for (int x : {kSize / 4, kSize / 2, 3 * kSize / 4}) {
        const glm::dvec3 p = pixel(plain, x);
        EXPECT_EQ(p.r, kLeftDepth) << "plain, nearest read at the boundary, x " << x;
        EXPECT_EQ(p.g, kRightDepth) << "plain read, x " << x;
    }
    EXPECT_EQ(unitsWithASampler(), 0) << "a plain bind unbinds the unit's sampler object";

    // And back: the comparison is bound again after the plain frame.
    v->setSceneData(probeScene(Probe::Comparison));
    v->frame(0.2);
    expectNoGlErrors(*v);
    expectComparisonProbe(v->renderer().readPixelsLinear());
}

TEST(ComparisonSampler, PassCommandsBindComparisonAndALaterPassReadsTheUnitPlainly) {
    auto v = probeViewer();
    v->setSceneData(probeScene(Probe::Commands));
    for (int frame = 0; frame < 2; ++frame) {
        v->frame(0.1 * frame);
        expectNoGlErrors(*v);
        const FloatImage img = v->renderer().readPixelsLinear();
        for (int c = 0; c < 4; ++c) {
            const glm::dvec3 compared = pixel(img, c * kCaseWidth + 4);
            if (c < 3)
                EXPECT_EQ(compared.r, kExpectedComparison[std::size_t(c)]) << "comparison, case " << c;
            else
                EXPECT_NEAR(compared.r, kExpectedComparison[3], kFilterTolerance) << "2×2 comparison filter";
            EXPECT_EQ(compared.g, kRightDepth) << "plain read beside the comparison, case " << c;
            EXPECT_EQ(compared.b, kLeftDepth) << "plain nearest read beside the comparison, case " << c;
            // The next pass binds the map plainly on the unit that had the comparison sampler.
            const glm::dvec3 plain = pixel(img, c * kCaseWidth + 12);
            EXPECT_EQ(plain.r, kLeftDepth) << "later pass, nearest read at the boundary";
            EXPECT_EQ(plain.g, kRightDepth) << "later pass, plain read";
        }
    }
}

TEST(ComparisonSampler, ASamplerObjectBoundBehindTheRenderersBackIsUnboundByThePlainBinds) {
    auto v = probeViewer();
    v->setSceneData(probeScene(Probe::Plain));
    v->frame(0.0);
    expectNoGlErrors(*v);
    {
        // Another library binds a comparison sampler on every unit between two frames; the
        // renderer's state cache cannot know (each view's frame starts by forgetting its state).
        const gl::SamplerObject foreign = gl::createComparisonSampler();
        for (GLuint u = 0; u < 48; ++u)
            glBindSampler(u, foreign.get());
        ASSERT_EQ(unitsWithASampler(), 48);
        v->frame(0.1);
        expectNoGlErrors(*v);
        EXPECT_EQ(unitsWithASampler(), 0) << "the first plain bind after the forgetting unbinds them all";
        const FloatImage plain = v->renderer().readPixelsLinear();
        const glm::dvec3 p = pixel(plain, kSize / 2);
        EXPECT_EQ(p.r, kLeftDepth) << "plain, nearest read at the boundary";
        EXPECT_EQ(p.g, kRightDepth) << "plain read";
    }
    EXPECT_EQ(gl::liveObjects()[gl::Kind::Sampler], 0) << "the plain frames made no sampler object";
}

TEST(ComparisonSampler, TheSamplerObjectIsMadeAtFirstUseAndDiesWithTheRenderer) {
    ASSERT_EQ(gl::liveObjects().total(), 0);
    {
        auto v = probeViewer();
        v->setSceneData(probeScene(Probe::Plain));
        v->frame(0.0);
        expectNoGlErrors(*v);
        EXPECT_EQ(gl::liveObjects()[gl::Kind::Sampler], 0) << "no comparison read yet: no sampler object";
        v->setSceneData(probeScene(Probe::Comparison));
        v->frame(0.1);
        v->frame(0.2);
        expectNoGlErrors(*v);
        EXPECT_EQ(gl::liveObjects()[gl::Kind::Sampler], 1) << "one comparison sampler, made once";
    }
    EXPECT_EQ(gl::liveObjects()[gl::Kind::Sampler], 0);
    EXPECT_EQ(gl::liveObjects().total(), 0);
}

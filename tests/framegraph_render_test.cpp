// The frame graph in real frames (OSMesa): one scene depth shared by the effects, passes culled when
// nothing reads what they make, the renderer's pool reusing its textures, and the graph's picture.
#include "TestUtil.h"

#include <sgfx/FrameSetup.h>
#include <sgfx/Geometry.h>
#include <sgfx/Group.h>
#include <sgfx/Shapes.h>
#include <sgfx/nodes/ao/AmbientOcclusionNode.h>
#include <sgfx/nodes/fog/FogNode.h>
#include <sgfx/nodes/particles/ParticleSystemNode.h>
#include <sgfx/nodes/transparency/TransparencyBin.h>
#include <sgfx/nodes/volume/VolumeNode.h>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include <cstdio>
#include <regex>
#include <utility>
#include <vector>

using namespace sgfx;
using namespace sgfx::test;

namespace {

constexpr int kSize = 64;

std::shared_ptr<Node> panel(float size, float distance, glm::vec3 colour, float alpha = 1.0f) {
    auto m = Material::create();
    m->ambient = glm::vec3(0);
    m->diffuse = glm::vec4(0, 0, 0, alpha);
    m->emissive = colour;
    auto t = Transform::create(glm::rotate(glm::translate(glm::mat4(1.0f), {0, distance, 3}),
                                           glm::radians(90.0f), glm::vec3(1, 0, 0)));
    auto q = shapes::quad(size, size);
    auto& ss = q->getOrCreateStateSet();
    ss.material.set(m);
    if (alpha < 1.0f) {
        ss.blend.set(BlendMode::Alpha);
        ss.cullFace.set(CullFace::None);
    }
    t->addChild(q);
    return t;
}

std::unique_ptr<Viewer> viewer() {
    auto v = Viewer::createHeadless(kSize, kSize);
    v->camera()->setPerspective(60.0f, 0.5f, 500.0f);
    v->camera()->setLookAt({0, 0, 3}, {0, 10, 3}, {0, 0, 1});
    v->camera()->computeNearFar = false;
    return v;
}

std::shared_ptr<FogNode> splitFog() {
    FogParameters p = FogParameters::ground();
    p.sky = FogSky::Off;
    return FogNode::create(p, FogMode::ForwardSplit);
}

// The DOT node id whose label starts with `label`, and whether it is drawn dashed (culled).
struct DotNode {
    std::string id;
    bool dashed = false;
};
std::vector<DotNode> dotNodes(const std::string& dot, const std::string& label) {
    std::vector<DotNode> out;
    const std::regex node("(\\w+) \\[shape=\\w+, label=\"([^\"]*)\"([^\\n]*)\\];");
    for (auto it = std::sregex_iterator(dot.begin(), dot.end(), node); it != std::sregex_iterator(); ++it) {
        const std::string text = (*it)[2];
        if (text.rfind(label + "\\n", 0) == 0)
            out.push_back({(*it)[1], (*it)[3].str().find("dashed") != std::string::npos});
    }
    return out;
}

std::size_t edgesInto(const std::string& dot, const std::string& id) {
    std::size_t n = 0;
    for (std::size_t at = dot.find("-> " + id + " "); at != std::string::npos;
         at = dot.find("-> " + id + " ", at + 1))
        ++n;
    return n;
}

bool hasEdge(const std::string& dot, const std::string& from, const std::string& to) {
    return dot.find(from + " -> " + to + " ") != std::string::npos;
}

// A soft smoke system (premultiplied, softness 1 m) at `at`.
std::shared_ptr<Node> softSmoke(glm::vec3 at) {
    auto t = Transform::create(glm::translate(glm::mat4(1.0f), at));
    auto smoke = ParticleSystemNode::smoke(0.5f, 50);
    EXPECT_GT(smoke->settings().softness, 0.0f);
    t->addChild(smoke);
    return t;
}

} // namespace

TEST(FrameGraphRender, SplitFogDrawsTheGeometryTwiceAndOneSceneDepthFeedsIt) {
    auto v = viewer();
    auto fog = splitFog();
    fog->addChild(panel(400, 80, {0.9f, 0.3f, 0.1f}));
    fog->addChild(panel(10, 10, {0.1f, 0.6f, 0.3f}, 0.5f)); // glass: the fog's nearest depth has it too
    v->setSceneData(fog);
    v->frame();
    expectNoGlErrors(*v);
    EXPECT_EQ(v->renderer().stats().geometryPasses, 2u) << "the scene depth pre-pass and the main pass";
    const std::string& dot = v->renderer().lastFrameGraphDot();
    const auto depth = dotNodes(dot, "scene.depth");
    ASSERT_EQ(depth.size(), 1u) << dot;
    EXPECT_EQ(edgesInto(dot, depth[0].id), 1u) << "one writer of scene.depth\n" << dot;
    ASSERT_EQ(dotNodes(dot, "fog: blended depth").size(), 1u) << dot;
    EXPECT_FALSE(dotNodes(dot, "fog: blended depth")[0].dashed) << dot;
    EXPECT_EQ(dot.find("fog depth pre-pass"), std::string::npos) << "the fog makes no depth of its own";
}

TEST(FrameGraphRender, TheSceneDepthIsCulledWhenNothingDrawnSamplesIt) {
    auto v = viewer();
    auto root = Group::create();
    auto fog = splitFog();                             // planned: fog nodes are never culled
    fog->addChild(panel(10, -20, {0.9f, 0.3f, 0.1f})); // behind the camera: nothing fogged is drawn
    root->addChild(fog);
    root->addChild(panel(400, 80, {0.2f, 0.2f, 0.8f})); // drawn, without fog
    v->setSceneData(root);
    v->frame();
    expectNoGlErrors(*v);
    const std::string& dot = v->renderer().lastFrameGraphDot();
    const auto pass = dotNodes(dot, "scene depth");
    ASSERT_EQ(pass.size(), 1u) << dot;
    EXPECT_TRUE(pass[0].dashed) << "culled: no drawn item samples the fog's depth\n" << dot;
    EXPECT_EQ(v->renderer().stats().geometryPasses, 1u);
    EXPECT_EQ(v->renderer().renderTargetBytes(), 0u) << "a culled pass's target is never made";
    // The same scene with the fogged panel in view: now the depth is made and read.
    fog->addChild(panel(10, 20, {0.9f, 0.3f, 0.1f}));
    v->frame();
    EXPECT_EQ(v->renderer().stats().geometryPasses, 2u);
    EXPECT_FALSE(dotNodes(v->renderer().lastFrameGraphDot(), "scene depth")[0].dashed);
    EXPECT_EQ(v->renderer().renderTargetBytes(), std::size_t(kSize) * kSize * 4)
        << "one D32F at the view's size";
}

TEST(FrameGraphRender, ThePoolKeepsItsTexturesAcrossFramesAndReleasesThemWhenUnused) {
    auto v = viewer();
    auto fog = splitFog();
    fog->addChild(panel(400, 80, {0.9f, 0.3f, 0.1f}));
    fog->addChild(panel(10, 10, {0.1f, 0.6f, 0.3f}, 0.5f));
    v->setSceneData(fog);
    v->frame();
    // scene.depth and fog.nearestDepth: both D32F, alive at once (the copy reads one into the other).
    const std::size_t held = v->renderer().renderTargetBytes();
    EXPECT_EQ(held, 2u * kSize * kSize * 4);
    for (int i = 0; i < 10; ++i) {
        v->frame();
        EXPECT_EQ(v->renderer().renderTargetBytes(), held) << "frame " << i;
    }
    // Without the fog nobody asks for the textures: the pool lets them go after a few frames.
    auto plain = Group::create();
    plain->addChild(panel(400, 80, {0.9f, 0.3f, 0.1f}));
    v->setSceneData(plain);
    for (int i = 0; i < 5; ++i)
        v->frame();
    EXPECT_EQ(v->renderer().renderTargetBytes(), 0u);
    expectNoGlErrors(*v);
}

TEST(FrameGraphRender, TheGraphPictureNamesEveryViewPassAndGpuTime) {
    auto v = viewer();
    v->renderer().options().timePasses = true;
    FogParameters p = FogParameters::ground();
    auto fog = FogNode::create(p, FogMode::PostProcess);
    fog->addChild(panel(400, 80, {0.9f, 0.3f, 0.1f}));
    v->setSceneData(fog);
    v->frame();
    expectNoGlErrors(*v);
    const std::string& dot = v->renderer().lastFrameGraphDot();
    EXPECT_EQ(dot.rfind("digraph frame {", 0), 0u) << dot;
    EXPECT_EQ(std::count(dot.begin(), dot.end(), '{'), std::count(dot.begin(), dot.end(), '}'));
    for (const char* pass : {"main: opaque", "main: transparent", "fog post-process"}) {
        const auto nodes = dotNodes(dot, pass);
        ASSERT_EQ(nodes.size(), 1u) << pass << "\n" << dot;
        EXPECT_TRUE(std::regex_search(dot, std::regex(std::string(pass) + "\\\\n[0-9]+\\.[0-9]{3} ms")))
            << pass;
    }
    EXPECT_FALSE(dotNodes(dot, "draw.colour").empty()) << dot;
}

TEST(FrameGraphRender, ARenderToTextureViewIsAClusterOfItsOwnWithItsOwnSceneDepth) {
    auto v = viewer();
    auto rtt = Camera::create();
    rtt->name = "mirror";
    rtt->setViewport(0, 0, 32, 32);
    rtt->setPerspective(60.0f, 0.5f, 500.0f);
    rtt->setLookAt({0, 0, 3}, {0, 10, 3});
    rtt->renderTarget = Texture::create(nullptr);
    auto fogInside = splitFog();
    fogInside->addChild(panel(400, 80, {0.9f, 0.3f, 0.1f}));
    rtt->addChild(fogInside);
    auto root = Group::create();
    root->addChild(rtt);
    auto fog = splitFog();
    fog->addChild(panel(400, 80, {0.2f, 0.3f, 0.9f}));
    root->addChild(fog);
    v->setSceneData(root);
    v->frame();
    expectNoGlErrors(*v);
    const std::string& dot = v->renderer().lastFrameGraphDot();
    EXPECT_NE(dot.find("subgraph \"cluster_mirror\""), std::string::npos) << dot;
    EXPECT_EQ(std::count(dot.begin(), dot.end(), '{'), 3) << "the frame, the mirror and the main view\n"
                                                          << dot;
    const auto depths = dotNodes(dot, "scene.depth");
    ASSERT_EQ(depths.size(), 2u) << dot;
    EXPECT_NE(dot.find("scene.depth\\nD32F 32x32"), std::string::npos) << "the mirror's own size\n" << dot;
    EXPECT_NE(dot.find("scene.depth\\nD32F 64x64"), std::string::npos) << dot;
    EXPECT_EQ(v->renderer().stats().geometryPasses, 4u) << "a pre-pass and a main pass per view";
}

namespace {

// A fifth effect that reads two frame resources alongside fog, ambient occlusion, OIT and soft
// particles: the scene's depth and the occlusion map. Its surfaces show what it read: red = the
// map's linear depth / 64, green = the stored window depth.
class ProbeEffect : public EffectNode {
public:
    std::string_view kind() const override { return "probe"; }
    int order() const override { return 900; }
    const ShaderSnippet& snippet() const override {
        static const ShaderSnippet s = [] {
            ShaderSnippet sn;
            sn.name = "probe";
            sn.fragmentDecl = "uniform sampler2D probe_depth;\nuniform sampler2D probe_ao;\n";
            sn.colorCode = "ivec2 probePx = ivec2(gl_FragCoord.xy);\n"
                           "sgfx_color = vec4(texelFetch(probe_ao, probePx, 0).g / 64.0,\n"
                           "                  texelFetch(probe_depth, probePx, 0).r, 0.0, 1.0);\n";
            sn.samplers = {{"probe_depth", "scene.depth"}, {"probe_ao", "ao.map"}};
            return sn;
        }();
        return s;
    }
    void setupFrame(FrameSetup& f) const override { f.requestSceneDepth({.when = PassPhase::BeforeMain}); }
};

// Fog (split), AO, an OIT glass and soft smoke on the left; the probe's panel on the right.
FloatImage renderWithEffects(bool probe) {
    auto v = Viewer::createHeadless(kSize, kSize);
    v->renderer().options().colorTarget = RendererOptions::ColorTarget::Rgba32F;
    v->camera()->setPerspective(60.0f, 0.5f, 500.0f);
    v->camera()->setLookAt({0, 0, 3}, {0, 10, 3}, {0, 0, 1});
    v->camera()->computeNearFar = false;
    auto root = Group::create();
    auto fog = splitFog();
    auto ao = AmbientOcclusionNode::create();
    auto oit = TransparencyBin::create(TransparencyMode::WeightedBlended);
    root->addChild(fog);
    fog->addChild(ao);
    auto left = Transform::create(glm::translate(glm::mat4(1.0f), {-6, 0, 0}));
    ao->addChild(left);
    left->addChild(panel(6, 20, {0.8f, 0.7f, 0.6f}));
    left->addChild(oit);
    oit->addChild(panel(2, 12, {0.1f, 0.6f, 0.3f}, 0.5f));
    auto smoke = ParticleSystemNode::smoke(1.0f, 200);
    ParticleSettings soft = smoke->settings();
    soft.softness = 0.5f;
    smoke->setSettings(soft);
    auto smokeAt = Transform::create(glm::translate(glm::mat4(1.0f), {-6, 15, 1}));
    smokeAt->addChild(smoke);
    fog->addChild(smokeAt);
    if (probe) {
        auto p = std::make_shared<ProbeEffect>();
        auto right = Transform::create(glm::translate(glm::mat4(1.0f), {6, 0, 0}));
        right->addChild(panel(4, 20, {1, 1, 1}));
        p->addChild(right);
        root->addChild(p);
    }
    // And a volume, so every effect that reads the scene's depth is here.
    auto volumeAt =
        Transform::create(glm::scale(glm::translate(glm::mat4(1.0f), {-8, 25, 2}), glm::vec3(3.0f)));
    volumeAt->addChild(VolumeNode::create({}, VolumeGrid::sphere(8)));
    fog->addChild(volumeAt);
    v->setSceneData(root);
    v->frame(0.5);
    expectNoGlErrors(*v);
    EXPECT_EQ(v->renderer().stats().geometryPasses, 2u)
        << "split fog, AO, OIT, soft smoke and a volume: the depth pre-pass and the main pass";
    return v->renderer().readPixelsLinear();
}

} // namespace

TEST(FrameGraphRender, AFifthEffectReadsTwoResourcesAndNothingElseChanges) {
    const FloatImage without = renderWithEffects(false), with = renderWithEffects(true);
    ASSERT_EQ(without.rgba.size(), with.rgba.size());
    // The probe panel's centre: x = 6 at distance 20 from an eye looking along +Y, 60° fov.
    const double n = 0.5, f = 500.0, z = 20.0;
    const double window = 0.5 * ((f + n) / (f - n) - 2.0 * f * n / ((f - n) * z)) + 0.5;
    const int px = int(std::lround(kSize * (0.5 + 0.5 * (6.0 / z) / std::tan(glm::radians(30.0))))),
              py = kSize / 2;
    const float* probe = &with.rgba[(std::size_t(py) * kSize + std::size_t(px)) * 4];
    EXPECT_NEAR(probe[0], z / 64.0, 1e-4) << "the occlusion map's linear depth";
    EXPECT_NEAR(probe[1], window, 1e-5) << "the scene depth";
    // The left half (fog, AO, OIT, smoke) is the same pixel for pixel.
    std::size_t compared = 0;
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize / 2 - 4; ++x)
            for (int c = 0; c < 4; ++c, ++compared) {
                const std::size_t i = (std::size_t(y) * kSize + std::size_t(x)) * 4 + std::size_t(c);
                ASSERT_EQ(without.rgba[i], with.rgba[i]) << "pixel " << x << "," << y << " channel " << c;
            }
    EXPECT_GT(compared, 0u);
}

TEST(FrameGraphRender, TwoSoftSystemsAndAVolumeShareOneSceneDepth) {
    auto v = viewer();
    auto root = Group::create();
    root->addChild(panel(400, 80, {0.9f, 0.3f, 0.1f})); // the wall the smoke and the medium stop at
    root->addChild(softSmoke({-2, 12, 2}));
    root->addChild(softSmoke({2, 12, 2}));
    VolumeParameters vp;
    vp.size = glm::vec3(4.0f);
    auto volume = Transform::create(glm::translate(glm::mat4(1.0f), {0, 20, 3}));
    volume->addChild(VolumeNode::create(vp, VolumeGrid::sphere(16)));
    root->addChild(volume);
    v->setSceneData(root);
    for (int i = 0; i < 3; ++i)
        v->frame(1.0 / 30.0);
    expectNoGlErrors(*v);
    const std::string& dot = v->renderer().lastFrameGraphDot();
    const auto depth = dotNodes(dot, "scene.depth");
    ASSERT_EQ(depth.size(), 1u) << dot;
    EXPECT_EQ(edgesInto(dot, depth[0].id), 1u) << "one writer of scene.depth\n" << dot;
    const auto copy = dotNodes(dot, "scene depth copy");
    ASSERT_EQ(copy.size(), 1u) << dot;
    EXPECT_FALSE(copy[0].dashed) << dot;
    EXPECT_TRUE(hasEdge(dot, copy[0].id, depth[0].id)) << "the copy writes it\n" << dot;
    const auto transparent = dotNodes(dot, "main: transparent");
    ASSERT_EQ(transparent.size(), 1u) << dot;
    EXPECT_TRUE(hasEdge(dot, depth[0].id, transparent[0].id)) << "the drawables read it\n" << dot;
    EXPECT_TRUE(dotNodes(dot, "scene depth").empty()) << "no pre-pass: every request is AfterOpaque";
    EXPECT_EQ(dot.find("particles: depth copy"), std::string::npos) << dot;
    EXPECT_EQ(dot.find("volume: depth copy"), std::string::npos) << dot;
    EXPECT_EQ(v->renderer().stats().geometryPasses, 1u);
    EXPECT_EQ(v->renderer().renderTargetBytes(), std::size_t(kSize) * kSize * 4)
        << "one D32F at the view's size";
}

// A half-resolution volume marches into two targets of the renderer's pool, made for the main
// pass's transparent items at half the draw target's size (odd sides rounding down); two volumes
// get a pair each, and a full-resolution one none.
TEST(FrameGraphRender, HalfResolutionVolumesDrawIntoPoolTargetsOfTheMainPass) {
    constexpr int w = 65, h = 63; // odd: 32x31 when rounding down, 33x32 up
    auto render = [&](int volumes, bool half) {
        auto v = Viewer::createHeadless(w, h);
        v->camera()->setPerspective(60.0f, 0.5f, 500.0f);
        v->camera()->setLookAt({0, 0, 3}, {0, 10, 3}, {0, 0, 1});
        v->camera()->computeNearFar = false;
        auto root = Group::create();
        root->addChild(panel(400, 80, {0.9f, 0.3f, 0.1f}));
        std::vector<std::shared_ptr<VolumeNode>> nodes;
        for (int i = 0; i < volumes; ++i) {
            VolumeParameters vp;
            vp.size = glm::vec3(4.0f);
            vp.halfResolution = half;
            nodes.push_back(VolumeNode::create(vp, VolumeGrid::sphere(16)));
            auto t = Transform::create(glm::translate(glm::mat4(1.0f), {i == 0 ? -3.0f : 3.0f, 20, 3}));
            t->addChild(nodes.back());
            root->addChild(t);
        }
        v->setSceneData(root);
        for (int i = 0; i < 3; ++i)
            v->frame(1.0 / 30.0);
        expectNoGlErrors(*v);
        return std::pair(std::move(v), std::move(nodes));
    };
    const std::size_t depthBytes = std::size_t(w) * h * 4;                // the scene depth (D32F)
    const std::size_t pairBytes = std::size_t(w / 2) * (h / 2) * (8 + 4); // RGBA16F + R32F
    auto name = [](const std::shared_ptr<VolumeNode>& n, const char* what) {
        char buf[64];
        std::snprintf(buf, sizeof buf, "volume.%s@%p", what, static_cast<const void*>(n.get()));
        return std::string(buf);
    };
    std::size_t fullCalls = 0;
    {
        auto [v, nodes] = render(1, false);
        const std::string& dot = v->renderer().lastFrameGraphDot();
        EXPECT_EQ(dot.find("volume.half"), std::string::npos) << "full resolution: no targets\n" << dot;
        EXPECT_EQ(v->renderer().renderTargetBytes(), depthBytes);
        fullCalls = v->renderer().stats().drawCalls; // the wall and the volume
    }
    for (int volumes : {1, 2}) {
        auto [v, nodes] = render(volumes, true);
        const std::string& dot = v->renderer().lastFrameGraphDot();
        const auto transparent = dotNodes(dot, "main: transparent");
        ASSERT_EQ(transparent.size(), 1u) << dot;
        EXPECT_FALSE(transparent[0].dashed) << dot;
        for (const auto& n : nodes)
            for (const auto& [what, format] :
                 {std::pair("halfColour", "RGBA16F"), std::pair("halfDepth", "R32F")}) {
                const std::string resource = name(n, what);
                const auto found = dotNodes(dot, resource);
                ASSERT_EQ(found.size(), 1u) << resource << "\n" << dot;
                const std::string label = resource + "\\n" + format + " " + std::to_string(w / 2) + "x" +
                                          std::to_string(h / 2) + " [slot ";
                EXPECT_NE(dot.find("label=\"" + label), std::string::npos) << "a pool resource at half size\n"
                                                                           << dot;
                EXPECT_EQ(edgesInto(dot, found[0].id), 1u) << resource << ": one writer\n" << dot;
                EXPECT_TRUE(hasEdge(dot, transparent[0].id, found[0].id))
                    << resource << " written by main: transparent\n"
                    << dot;
            }
        EXPECT_EQ(v->renderer().renderTargetBytes(), depthBytes + std::size_t(volumes) * pairBytes)
            << volumes << " volume(s): a pair each";
        EXPECT_EQ(v->renderer().stats().drawCalls,
                  fullCalls + std::size_t(volumes - 1) + std::size_t(volumes))
            << "each volume marched into its targets and upsampled them";
    }
}

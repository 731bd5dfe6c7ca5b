// The frame graph in real frames (OSMesa): one scene depth shared by the effects, passes culled when
// nothing reads what they make, the renderer's pool reusing its textures, and the graph's picture.
#include "TestUtil.h"

#include <fog/FogNode.h>
#include <particles/ParticleSystemNode.h>
#include <sgfx/Geometry.h>
#include <sgfx/Group.h>
#include <sgfx/Shapes.h>
#include <volume/VolumeNode.h>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include <regex>

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

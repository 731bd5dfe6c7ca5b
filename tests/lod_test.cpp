// LOD by size on screen: the pixel-size formula, which children the cull visitor queues either side
// of a switch, validation, and a headless render where two levels of different colours switch.
#include "TestUtil.h"

#include <sgfx/CullVisitor.h>
#include <sgfx/Geometry.h>
#include <sgfx/Group.h>
#include <sgfx/LOD.h>
#include <sgfx/Shapes.h>
#include <sgfx/Visitors.h>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

using namespace sgfx;
using namespace sgfx::test;

namespace {

std::shared_ptr<Geometry> namedBox(const std::string& name, float size = 1.0f) {
    auto g = shapes::box(glm::vec3(size));
    g->name = name;
    return g;
}

// 90° vertical field of view on a 100-pixel-tall viewport: at distance d a unit of length spans
// 50/d pixels, so a sphere of radius 1 is 100/d pixels across.
std::shared_ptr<Camera> camera90() {
    auto c = Camera::create();
    c->setViewport(0, 0, 100, 100);
    c->setPerspective(90.0f, 0.1f, 1000.0f);
    return c;
}

std::string queued(Camera& cam) {
    RenderQueue q;
    CullVisitor cv(cam, q);
    cv.run(cam);
    std::string names;
    for (const auto& it : q.opaque)
        names += it.geometry->name + " ";
    return names;
}

// An LOD with a user sphere of radius 1 at its origin: "near" above `switchPx`, "far" below.
std::shared_ptr<LOD> twoLevels(float switchPx) {
    auto lod = LOD::create();
    lod->name = "lod";
    lod->addChild(namedBox("near"), switchPx, std::numeric_limits<float>::infinity());
    lod->addChild(namedBox("far"), 0.0f, switchPx);
    lod->setUserSphere({0, 0, 0}, 1.0f);
    return lod;
}

} // namespace

TEST(Lod, PixelSizeMatchesHandComputation) {
    // Perspective, 90°: the view is 2d tall at distance d, over 100 px, so 50/d px per metre;
    // a radius-1 sphere at distance 10 is 2 m = 10 px across, wherever it is in the view.
    const glm::mat4 p = glm::perspective(glm::radians(90.0f), 1.0f, 0.1f, 1000.0f);
    EXPECT_NEAR(pixelSize({0, 0, -10}, 1.0f, p, 100), 10.0f, 1e-4f);
    EXPECT_NEAR(pixelSize({6, 0, -8}, 1.0f, p, 100), 10.0f, 1e-4f); // distance 10 off axis
    EXPECT_NEAR(pixelSize({0, 0, -20}, 3.0f, p, 100), 15.0f, 1e-4f);
    // 60°: half-height at distance d is d·tan 30°, so 2r px span r·h/(d·tan 30°) pixels.
    const glm::mat4 p60 = glm::perspective(glm::radians(60.0f), 1.5f, 0.1f, 1000.0f);
    EXPECT_NEAR(pixelSize({0, 0, -5}, 0.5f, p60, 64), 0.5f * 64.0f / (5.0f * std::tan(glm::radians(30.0f))),
                1e-3f);
    // Orthographic, 8 m tall on 80 px: 10 px per metre at any distance, so 2 m = 20 px.
    const glm::mat4 o = glm::ortho(-5.0f, 5.0f, -4.0f, 4.0f, 0.1f, 100.0f);
    EXPECT_NEAR(pixelSize({0, 0, -3}, 1.0f, o, 80), 20.0f, 1e-4f);
    EXPECT_NEAR(pixelSize({3, 2, -90}, 1.0f, o, 80), 20.0f, 1e-4f);
    // The eye at the centre: the largest finite size (the finest level), never inf or NaN.
    EXPECT_EQ(pixelSize({0, 0, 0}, 1.0f, p, 100), std::numeric_limits<float>::max());
}

TEST(Lod, CullQueuesTheLevelEitherSideOfTheSwitch) {
    auto cam = camera90();
    auto t = Transform::create();
    t->addChild(twoLevels(10.0f)); // switch at 100/d = 10 px: d = 10
    cam->addChild(t);
    for (auto [d, expected] :
         {std::pair{9.95f, "near "}, {10.05f, "far "}, {3.0f, "near "}, {50.0f, "far "}}) {
        cam->setLookAt({0, -d, 0}, {0, 0, 0});
        EXPECT_EQ(queued(*cam), expected) << "distance " << d;
    }
    // A scale of 2 doubles the sphere: the switch moves to d = 20.
    t->setMatrix(glm::scale(glm::mat4(1.0f), glm::vec3(2.0f)));
    cam->setLookAt({0, -19.9f, 0}, {0, 0, 0});
    EXPECT_EQ(queued(*cam), "near ");
    cam->setLookAt({0, -20.1f, 0}, {0, 0, 0});
    EXPECT_EQ(queued(*cam), "far ");
}

TEST(Lod, OrthographicSwitchesByViewHeightNotDistance) {
    auto cam = camera90();
    cam->addChild(twoLevels(10.0f));
    cam->setLookAt({0, -50, 0}, {0, 0, 0});
    // 100 px over a view 2h tall: the 2 m sphere spans 100/h px; the switch is at h = 10.
    cam->projectionMatrix = glm::ortho(-9.9f, 9.9f, -9.9f, 9.9f, 0.1f, 200.0f);
    EXPECT_EQ(queued(*cam), "near ");
    cam->projectionMatrix = glm::ortho(-10.1f, 10.1f, -10.1f, 10.1f, 0.1f, 200.0f);
    EXPECT_EQ(queued(*cam), "far ");
    cam->setLookAt({0, -5, 0}, {0, 0, 0}); // closer: the same level
    EXPECT_EQ(queued(*cam), "far ");
}

TEST(Lod, BoundSphereByDefaultAndOverlappingRanges) {
    auto cam = camera90();
    auto lod = LOD::create();
    lod->addChild(namedBox("a", 2.0f), 0.0f, 20.0f);
    lod->addChild(namedBox("b", 2.0f), 10.0f, 30.0f);
    lod->addChild(namedBox("always", 2.0f)); // plain addChild: [0, inf)
    cam->addChild(lod);
    // The bound of a 2 m box has radius sqrt(3): 100·sqrt(3)/d px.
    const float r = std::sqrt(3.0f);
    auto at = [&](float px) {
        cam->setLookAt({0, -100.0f * r / px, 0}, {0, 0, 0});
        return queued(*cam);
    };
    EXPECT_EQ(at(5.0f), "a always ");
    EXPECT_EQ(at(15.0f), "a b always ");
    EXPECT_EQ(at(25.0f), "b always ");
    EXPECT_EQ(at(35.0f), "always ");
}

TEST(Lod, OtherVisitorsSeeEveryChildAndTheBoundIsTheirUnion) {
    auto lod = LOD::create();
    auto a = namedBox("a");
    auto b = namedBox("b", 4.0f);
    lod->addChild(a, 100.0f, 1000.0f);
    lod->addChild(b, 0.0f, 100.0f);
    lod->setUserSphere({0, 0, 0}, 0.1f); // selection only: the bound stays the children's
    StatsVisitor stats;
    lod->accept(stats);
    EXPECT_EQ(stats.drawables, 2u);
    EXPECT_NEAR(lod->bound().radius, b->bound().radius, 1e-5f);
    ComputeBoundsVisitor cb;
    lod->accept(cb);
    EXPECT_NEAR(cb.max.x, 2.0f, 1e-6f);
}

TEST(Lod, RangesFollowInsertAndRemove) {
    auto lod = LOD::create();
    auto a = namedBox("a"), b = namedBox("b"), c = namedBox("c");
    lod->addChild(a, 1.0f, 2.0f);
    lod->addChild(b, 3.0f, 4.0f);
    lod->insertChild(0, c);
    ASSERT_EQ(lod->ranges().size(), 3u);
    EXPECT_EQ(lod->range(0).minPixels, 0.0f);
    EXPECT_EQ(lod->range(1).minPixels, 1.0f);
    EXPECT_TRUE(lod->removeChild(a.get()));
    ASSERT_EQ(lod->ranges().size(), 2u);
    EXPECT_EQ(lod->range(1).minPixels, 3.0f);
    lod->setRange(0, 5.0f, 6.0f);
    EXPECT_EQ(lod->range(0).maxPixels, 6.0f);
    lod->removeChildren();
    EXPECT_TRUE(lod->ranges().empty());
}

TEST(Lod, BadRangesAreRefusedNamingTheNodeAndChild) {
    auto lod = LOD::create();
    lod->name = "tree";
    lod->addChild(namedBox("a"), 0.0f, 10.0f);
    auto expectRefused = [&](auto&& f, const std::string& part) {
        try {
            f();
            ADD_FAILURE() << "no exception for " << part;
        } catch (const std::invalid_argument& e) {
            const std::string what = e.what();
            EXPECT_NE(what.find("'tree'"), std::string::npos) << what;
            EXPECT_NE(what.find(part), std::string::npos) << what;
        }
    };
    const float nan = std::numeric_limits<float>::quiet_NaN();
    expectRefused([&] { lod->addChild(namedBox("b"), 20.0f, 10.0f); }, "child 1");
    expectRefused([&] { lod->addChild(namedBox("b"), nan, 10.0f); }, "NaN");
    expectRefused([&] { lod->setRange(0, 0.0f, nan); }, "child 0");
    expectRefused([&] { lod->setRange(0, -1.0f, 5.0f); }, "negative");
    expectRefused([&] { lod->setUserSphere({0, 0, 0}, 0.0f); }, "radius");
    EXPECT_EQ(lod->numChildren(), 1u); // nothing was added
    EXPECT_EQ(lod->range(0).maxPixels, 10.0f);
    EXPECT_THROW(lod->setRange(3, 0.0f, 1.0f), std::out_of_range);
}

TEST(LodRender, TwoColouredLevelsSwitchAsTheCameraMoves) {
    constexpr int kSize = 64;
    auto v = Viewer::createHeadless(kSize, kSize);
    auto& cam = *v->camera();
    cam.setPerspective(60.0f, 0.1f, 100.0f);
    cam.clearColor = {0, 0, 0, 1};
    auto red = namedBox("red");
    red->getOrCreateStateSet().material.set(flatMaterial({1, 0, 0}));
    auto green = namedBox("green");
    green->getOrCreateStateSet().material.set(flatMaterial({0, 1, 0}));
    auto lod = LOD::create();
    lod->addChild(red, 20.0f, std::numeric_limits<float>::infinity());
    lod->addChild(green, 0.0f, 20.0f);
    lod->setUserSphere({0, 0, 0}, 1.0f);
    v->setSceneData(lod);
    // 1 m radius, 64 px, 60°: 64/(d·tan 30°) px, so the switch is at d = 5.54 m.
    const float switchDistance = 64.0f / (20.0f * std::tan(glm::radians(30.0f)));
    for (auto [d, colour] : {std::pair{switchDistance * 0.9f, glm::dvec3(1, 0, 0)},
                             {switchDistance * 1.1f, glm::dvec3(0, 1, 0)},
                             {switchDistance * 0.5f, glm::dvec3(1, 0, 0)}}) {
        cam.setLookAt({0, -d, 0}, {0, 0, 0});
        v->frame();
        const Image img = v->capture();
        const glm::ivec4 p = pixelAt(img, kSize / 2, kSize / 2);
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(p[c], srgbByte(colour[c]), 1) << "distance " << d << " channel " << c;
        EXPECT_EQ(v->stats().items, 1u) << "one level drawn at distance " << d;
    }
    for (const auto& e : v->renderer().takeGlErrors())
        ADD_FAILURE() << "GL: " << e;
}

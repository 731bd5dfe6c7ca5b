// Billboard: the rotation it computes for an eye (about an axis, or fully), its bound under every
// rotation, what the cull traversal queues, and a headless render where a card keeps its
// analytic on-screen size from every side while a plain card turns edge-on.
#include "TestUtil.h"

#include <sgfx/Billboard.h>
#include <sgfx/CullVisitor.h>
#include <sgfx/Geometry.h>
#include <sgfx/Group.h>
#include <sgfx/Shapes.h>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <random>

using namespace sgfx;
using namespace sgfx::test;

namespace {

glm::vec3 turn(const glm::mat4& r, const glm::vec3& v) {
    return glm::vec3(r * glm::vec4(v, 0.0f));
}

// A w x h card through the origin whose front (counter-clockwise) side faces -Y.
std::shared_ptr<Geometry> card(float w, float h) {
    auto g = Geometry::create();
    shapes::append(*g, *shapes::quad(w, h), glm::rotate(glm::mat4(1.0f), glm::half_pi<float>(), {1, 0, 0}));
    return g;
}

} // namespace

TEST(Billboard, AxialRotationTurnsTheNormalTowardsTheEyeAboutItsAxis) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-20.0f, 20.0f);
    for (bool tilted : {false, true}) {
        auto b = Billboard::create();
        if (tilted) { // any perpendicular pair works, not only Z up / -Y
            b->axis = glm::normalize(glm::vec3(1, 2, 2));
            b->normal = glm::normalize(glm::cross(b->axis, glm::vec3(0, 0, 1)));
        }
        for (int i = 0; i < 200; ++i) {
            const glm::vec3 eye(u(rng), u(rng), u(rng));
            const glm::mat4 r = b->orientation(eye);
            const glm::vec3 across = eye - b->axis * glm::dot(eye, b->axis);
            EXPECT_NEAR(glm::dot(turn(r, b->normal), glm::normalize(across)), 1.0f, 1e-4f) << i;
            EXPECT_NEAR(glm::length(turn(r, b->axis) - b->axis), 0.0f, 1e-5f) << "the axis stays";
            EXPECT_NEAR(glm::determinant(glm::mat3(r)), 1.0f, 1e-5f) << "a rotation";
        }
        // An eye on the axis, or nowhere: the rest pose.
        EXPECT_EQ(b->orientation(b->axis * 5.0f), glm::mat4(1.0f));
        EXPECT_EQ(b->orientation(glm::vec3(0.0f)), glm::mat4(1.0f));
        EXPECT_EQ(b->orientation(glm::vec3(std::nanf(""), 1, 1)), glm::mat4(1.0f));
    }
}

TEST(Billboard, PointRotEyeFacesTheEyeWithItsAxisTowardsTheViewUp) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(-20.0f, 20.0f);
    auto b = Billboard::create(Billboard::Mode::PointRotEye);
    for (int i = 0; i < 200; ++i) {
        const glm::vec3 eye(u(rng), u(rng), u(rng));
        const glm::vec3 up = glm::normalize(glm::vec3(u(rng), u(rng), u(rng)));
        const glm::mat4 r = b->orientation(eye, up);
        const glm::vec3 n = glm::normalize(eye);
        EXPECT_NEAR(glm::dot(turn(r, b->normal), n), 1.0f, 1e-4f) << i;
        // The turned axis is the view's up with its part along the eye removed.
        const glm::vec3 expected = glm::normalize(up - n * glm::dot(up, n));
        EXPECT_NEAR(glm::dot(turn(r, b->axis), expected), 1.0f, 1e-4f) << i;
        EXPECT_NEAR(glm::determinant(glm::mat3(r)), 1.0f, 1e-5f) << "a rotation, not a mirror";
    }
    // Up along the line of sight: the rest axis decides, still facing the eye.
    const glm::mat4 r = b->orientation({0, -10, 0}, {0, 1, 0});
    EXPECT_NEAR(glm::dot(turn(r, b->normal), glm::vec3(0, -1, 0)), 1.0f, 1e-5f);
    EXPECT_NEAR(glm::dot(turn(r, b->axis), glm::vec3(0, 0, 1)), 1.0f, 1e-5f);
}

TEST(Billboard, RefusesAnAxisAndNormalThatAreNotPerpendicularUnitVectors) {
    auto b = Billboard::create();
    b->name = "sign";
    b->normal = glm::vec3(0, -1, 0.5f);
    try {
        (void)b->orientation({1, 2, 3});
        ADD_FAILURE() << "no exception";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("sign"), std::string::npos) << e.what();
    }
    b->normal = glm::vec3(0, -1, 0);
    b->axis = glm::vec3(0, 0, 2);
    EXPECT_THROW((void)b->orientation({1, 2, 3}), std::invalid_argument);
}

TEST(Billboard, BoundHoldsTheChildrenInEveryOrientation) {
    for (auto mode : {Billboard::Mode::AxialRotation, Billboard::Mode::PointRotEye}) {
        auto b = Billboard::create(mode);
        auto box = shapes::box({1.0f, 0.5f, 2.0f});
        auto off = Transform::create(glm::translate(glm::mat4(1.0f), {3.0f, 1.0f, 4.0f}));
        off->addChild(box);
        b->addChild(off);
        const BoundingSphere s = b->bound();
        ASSERT_TRUE(s.valid());
        std::mt19937 rng(3);
        std::uniform_real_distribution<float> u(-30.0f, 30.0f);
        for (int i = 0; i < 100; ++i) {
            const glm::mat4 r = b->orientation({u(rng), u(rng), u(rng)}, {0, 0, 1});
            for (const glm::vec3& p : box->positions) {
                const glm::vec3 w = glm::vec3(r * off->matrix() * glm::vec4(p, 1.0f));
                EXPECT_LE(glm::length(w - s.center), s.radius * (1.0f + 1e-5f)) << i;
            }
        }
    }
}

TEST(Billboard, TheCullQueuesTheChildrenTurnedTowardsThisViewsEye) {
    auto cam = Camera::create();
    cam->setViewport(0, 0, 100, 100);
    cam->setPerspective(60.0f, 0.1f, 500.0f);
    cam->setLookAt({30, 40, 5}, {10, 0, 2});
    auto place = Transform::create(glm::translate(glm::mat4(1.0f), {10, 0, 0}) *
                                   glm::rotate(glm::mat4(1.0f), 0.4f, glm::vec3(0, 0, 1)));
    auto b = Billboard::create();
    b->addChild(card(2.0f, 3.0f));
    place->addChild(b);
    cam->addChild(place);
    RenderQueue q;
    CullVisitor cv(*cam, q);
    cv.run(*cam);
    ASSERT_EQ(q.opaque.size(), 1u);
    const glm::mat4& model = q.opaque[0].model;
    // The card's -Y side, in the world, points at the eye across the vertical axis.
    const glm::vec3 facing = glm::normalize(turn(model, {0, -1, 0}));
    const glm::vec3 toEye = glm::vec3(30, 40, 5) - glm::vec3(10, 0, 0);
    EXPECT_NEAR(glm::dot(facing, glm::normalize(glm::vec3(toEye.x, toEye.y, 0.0f))), 1.0f, 1e-4f);
    EXPECT_NEAR(turn(model, {0, 0, 1}).z, 1.0f, 1e-5f) << "still upright";
    EXPECT_EQ(glm::vec3(model[3]), glm::vec3(10, 0, 0)) << "turned about its own origin";
}

TEST(BillboardRender, ACardKeepsItsAnalyticSizeFromEverySideWhileAPlainCardTurnsEdgeOn) {
    constexpr int kSize = 128;
    constexpr float kDistance = 10.0f, kSide = 2.0f;
    auto v = Viewer::createHeadless(kSize, kSize);
    auto& cam = *v->camera();
    cam.setPerspective(60.0f, 0.1f, 100.0f);
    cam.clearColor = {0, 0, 0, 1};
    auto white = Material::create();
    white->ambient = glm::vec3(0);
    white->diffuse = glm::vec4(0, 0, 0, 1);
    white->emissive = glm::vec3(1);
    auto plain = card(kSide, kSide);
    plain->getOrCreateStateSet().material.set(white);
    plain->getOrCreateStateSet().cullFace.set(CullFace::None);
    auto b = Billboard::create();
    b->addChild(plain);
    auto lit = [](const Image& img) {
        int n = 0;
        for (int y = 0; y < img.height; ++y)
            for (int x = 0; x < img.width; ++x)
                n += pixelAt(img, x, y).r > 127;
        return n;
    };
    // Facing the eye at distance d, the card spans kSide · (kSize/2) / (d · tan 30°) pixels.
    const double side = kSide * (kSize / 2.0) / (kDistance * std::tan(glm::radians(30.0)));
    for (float yaw : {0.0f, 50.0f, 90.0f, 135.0f, 200.0f, 270.0f}) {
        const float a = glm::radians(yaw);
        cam.setLookAt({kDistance * std::sin(a), -kDistance * std::cos(a), 0.0f}, {0, 0, 0});
        v->setSceneData(b);
        v->frame();
        EXPECT_NEAR(lit(v->capture()), side * side, 0.04 * side * side) << "billboard, yaw " << yaw;
        v->setSceneData(plain);
        v->frame();
        const double plainArea = lit(v->capture());
        if (yaw == 90.0f || yaw == 270.0f) {
            EXPECT_LT(plainArea, 0.05 * side * side) << "edge-on, yaw " << yaw;
        }
    }
    for (const auto& e : v->renderer().takeGlErrors())
        ADD_FAILURE() << "GL: " << e;
}

// Under a stretching parent the turned matrix stretches the card differently in every direction:
// the cull's radius (near/far) must be the whole matrix's, as BoundingSphere::transformed gives.
TEST(Billboard, TheCullMeasuresTheTurnedMatrixUnderAStretch) {
    auto cam = Camera::create();
    cam->setViewport(0, 0, 100, 100);
    cam->setPerspective(60.0f, 0.1f, 500.0f);
    cam->setLookAt({25, 30, 4}, {0, 0, 2});
    auto stretch = Transform::create(glm::scale(glm::mat4(1.0f), {1.0f, 3.0f, 1.0f}));
    auto b = Billboard::create();
    auto g = card(4.0f, 1.0f);
    b->addChild(g);
    stretch->addChild(b);
    cam->addChild(stretch);
    RenderQueue q;
    CullVisitor cv(*cam, q);
    cv.run(*cam);
    ASSERT_EQ(q.opaque.size(), 1u);
    const BoundingSphere s = g->bound().transformed(cam->viewMatrix * q.opaque[0].model);
    EXPECT_NEAR(cv.computedNear, -s.center.z - s.radius, 1e-4f * s.radius);
    EXPECT_NEAR(cv.computedFar, -s.center.z + s.radius, 1e-4f * s.radius);
}

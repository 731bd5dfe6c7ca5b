// Camera manipulators: pure math, no GL context. Home framing is checked by projecting the box's
// corners, the motions against their definitions.
#include <sgfx/Camera.h>
#include <sgfx/Manipulator.h>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include <array>
#include <cmath>

using namespace sgfx;

namespace {

std::array<glm::vec3, 8> corners(glm::vec3 lo, glm::vec3 hi) {
    std::array<glm::vec3, 8> c;
    for (int i = 0; i < 8; ++i)
        c[std::size_t(i)] = {i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z};
    return c;
}

// Largest |ndc| of the box's corners (≤ 1: all in view) and whether all are in front of the eye.
float extentInView(const CameraManipulator& m, glm::vec3 lo, glm::vec3 hi, float fovy, float aspect) {
    const glm::mat4 clip = glm::perspective(glm::radians(fovy), aspect, 1e-3f, 1e6f) * m.viewMatrix();
    float worst = 0.0f;
    for (const glm::vec3& p : corners(lo, hi)) {
        const glm::vec4 c = clip * glm::vec4(p, 1.0f);
        if (c.w <= 0.0f) return INFINITY;
        worst = std::max({worst, std::abs(c.x / c.w), std::abs(c.y / c.w)});
    }
    return worst;
}

} // namespace

TEST(Manipulator, HomeFramesTheWholeBoxAtAnyAspectFromAnyDirection) {
    const glm::vec3 lo(-3, 10, 0), hi(5, 12, 30); // a tall, thin tower away from the origin
    for (float aspect : {0.5f, 1.0f, 16.0f / 9.0f, 3.0f})
        for (float yaw : {0.0f, 30.0f, 135.0f, -90.0f})
            for (float pitch : {-30.0f, 0.0f, 25.0f, 80.0f}) {
                OrbitManipulator orbit;
                FlyManipulator fly;
                for (CameraManipulator* m :
                     {static_cast<CameraManipulator*>(&orbit), static_cast<CameraManipulator*>(&fly)}) {
                    m->home(lo, hi, 40.0f, aspect, yaw, pitch);
                    const float e = extentInView(*m, lo, hi, 40.0f, aspect);
                    EXPECT_LE(e, 1.0f) << "aspect " << aspect << " yaw " << yaw << " pitch " << pitch;
                    // Not lost in the distance either (a thin tower seen from above fills least).
                    EXPECT_GT(e, 0.2f) << "aspect " << aspect << " yaw " << yaw << " pitch " << pitch;
                    EXPECT_NEAR(glm::length(m->target() - 0.5f * (lo + hi)), 0.0f, 1e-3f);
                }
                EXPECT_NEAR(glm::length(orbit.eye() - fly.eye()), 0.0f, 1e-3f);
            }
}

TEST(Manipulator, HomeOfAnEmptyOrBrokenBoxStillGivesAFiniteView) {
    OrbitManipulator m;
    m.home(glm::vec3(1), glm::vec3(-1), 45.0f, 1.0f);
    m.home(glm::vec3(NAN), glm::vec3(1), 45.0f, 1.0f);
    const glm::mat4 v = m.viewMatrix();
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j)
            EXPECT_TRUE(std::isfinite(v[i][j]));
    EXPECT_LE(extentInView(m, glm::vec3(-0.5f), glm::vec3(0.5f), 45.0f, 1.0f), 1.0f);
}

TEST(Manipulator, SetLookAtGivesTheLookAtMatrix) {
    const glm::vec3 eye(10, -20, 7), target(1, 2, 3);
    const glm::mat4 expected = glm::lookAt(eye, target, {0, 0, 1});
    OrbitManipulator orbit;
    FlyManipulator fly;
    orbit.setLookAt(eye, target);
    fly.setLookAt(eye, target);
    for (const CameraManipulator* m :
         {static_cast<const CameraManipulator*>(&orbit), static_cast<const CameraManipulator*>(&fly)})
        for (int i = 0; i < 4; ++i)
            for (int j = 0; j < 4; ++j)
                EXPECT_NEAR(m->viewMatrix()[i][j], expected[i][j], 1e-4f);
    Camera camera;
    orbit.apply(camera);
    EXPECT_NEAR(glm::length(camera.eyePosition() - eye), 0.0f, 1e-3f);
}

TEST(Manipulator, OrbitTurnsAroundItsCentreAtAFixedDistanceAndNeverFlips) {
    OrbitManipulator m;
    m.home({-1, -1, -1}, {1, 1, 1}, 45.0f, 1.0f);
    const glm::vec3 centre = m.centre;
    const float d = glm::length(m.eye() - centre);
    // A drag of the viewport's height turns by half a turn: two of them come back.
    const glm::vec3 start = m.eye();
    m.drag(MouseButton::Left, {300, 0}, 300);
    // Half a turn about the vertical axis through the centre.
    const glm::vec3 opposite(2.0f * centre.x - start.x, 2.0f * centre.y - start.y, start.z);
    EXPECT_NEAR(glm::length(m.eye() - opposite), 0.0f, 1e-3f);
    m.drag(MouseButton::Left, {300, 0}, 300);
    EXPECT_NEAR(glm::length(m.eye() - start), 0.0f, 1e-3f);
    for (int i = 0; i < 50; ++i) { // far over the pole and back: never upside down, never NaN
        m.drag(MouseButton::Left, {37, 91}, 300);
        EXPECT_NEAR(glm::length(m.eye() - m.centre), d, 1e-3f * d);
        EXPECT_LE(std::abs(glm::degrees(m.pitch)), 89.0f + 1e-3f);
        EXPECT_GT(glm::length(glm::cross(m.target() - m.eye(), glm::vec3(0, 0, 1))), 0.0f);
    }
    EXPECT_NEAR(glm::length(m.centre - centre), 0.0f, 1e-6f);
}

TEST(Manipulator, OrbitZoomAndPanAreReversible) {
    OrbitManipulator m;
    m.home({-1, -1, -1}, {1, 1, 1}, 45.0f, 1.0f);
    const glm::vec3 eye = m.eye(), centre = m.centre;
    const float d = m.distance;
    m.scroll(3);
    EXPECT_NEAR(m.distance, d * std::pow(0.85f, 3.0f), 1e-4f * d);
    m.scroll(-3);
    EXPECT_NEAR(m.distance, d, 1e-4f * d);
    m.drag(MouseButton::Right, {0, 120}, 300); // down: closer
    EXPECT_LT(m.distance, d);
    m.drag(MouseButton::Right, {0, -120}, 300);
    EXPECT_NEAR(m.distance, d, 1e-4f * d);
    m.drag(MouseButton::Middle, {40, -25}, 300); // the centre moves across the view, not along it
    const glm::vec3 moved = m.centre - centre;
    EXPECT_GT(glm::length(moved), 0.0f);
    EXPECT_NEAR(glm::dot(moved, glm::normalize(centre - eye)), 0.0f, 1e-4f);
    m.drag(MouseButton::Middle, {-40, 25}, 300);
    EXPECT_NEAR(glm::length(m.eye() - eye), 0.0f, 1e-4f);
}

TEST(Manipulator, OrbitKeysSlideTheCentreOverTheGround) {
    OrbitManipulator m;
    m.setLookAt({0, -10, 10}, {0, 0, 0}); // looking north and down
    m.move({0, 1, 0}, 1.0f, false);       // W: north, level, half the distance per second
    EXPECT_NEAR(m.centre.x, 0.0f, 1e-4f);
    EXPECT_NEAR(m.centre.y, 0.5f * m.distance, 1e-4f);
    EXPECT_NEAR(m.centre.z, 0.0f, 1e-4f);
    m.move({1, 0, 0}, 0.5f, true); // D, fast: east
    EXPECT_NEAR(m.centre.x, 4.0f * 0.5f * 0.5f * m.distance, 1e-4f);
}

TEST(Manipulator, FlyMovesAlongTheViewAndLooksWithoutMoving) {
    FlyManipulator m;
    m.home({-5, -5, 0}, {5, 5, 2}, 45.0f, 1.5f);
    const glm::vec3 eye = m.eye(), dir = m.direction();
    m.move({0, 1, 0}, 2.0f, false);
    EXPECT_NEAR(glm::length(m.eye() - (eye + 2.0f * m.speed * dir)), 0.0f, 1e-4f);
    m.move({0, -1, 0}, 2.0f, false);
    m.move({1, 0, 0}, 1.0f, false); // strafe: level and square to the view
    const glm::vec3 side = m.eye() - eye;
    EXPECT_NEAR(glm::length(side), m.speed, 1e-4f);
    EXPECT_NEAR(side.z, 0.0f, 1e-5f);
    EXPECT_NEAR(glm::dot(side, dir), 0.0f, 1e-4f);
    const glm::vec3 before = m.eye();
    m.drag(MouseButton::Left, {100, -60}, 400);
    EXPECT_EQ(m.eye(), before);
    EXPECT_GT(glm::length(m.direction() - dir), 0.1f);
    const float speed = m.speed;
    m.scroll(2);
    EXPECT_NEAR(m.speed, speed * 1.5625f, 1e-4f * speed);
}

#include "sgfx/Manipulator.h"

#include "sgfx/Camera.h"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>

namespace sgfx {

namespace {
constexpr float kMaxPitch = glm::radians(89.0f);
constexpr float kPi = 3.14159265358979f;

// Yaw 0 looks along +Y, growing anticlockwise seen from above; pitch > 0 looks down.
glm::vec3 lookDirection(float yaw, float pitch) {
    return {-std::sin(yaw) * std::cos(pitch), std::cos(yaw) * std::cos(pitch), -std::sin(pitch)};
}

void anglesOf(glm::vec3 d, float& yaw, float& pitch) {
    d = glm::normalize(d);
    yaw = std::atan2(-d.x, d.y);
    pitch = std::clamp(-std::asin(std::clamp(d.z, -1.0f, 1.0f)), -kMaxPitch, kMaxPitch);
}

bool finite(const glm::vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}
} // namespace

void CameraManipulator::home(const glm::vec3& min, const glm::vec3& max, float fovyDegrees, float aspect,
                             float yawDegrees, float pitchDegrees) {
    glm::vec3 lo = min, hi = max;
    if (!finite(lo) || !finite(hi) || glm::any(glm::greaterThan(lo, hi)))
        lo = glm::vec3(-0.5f), hi = glm::vec3(0.5f);
    const glm::vec3 centre = 0.5f * (lo + hi);
    radius_ = std::max(0.5f * glm::length(hi - lo), 1e-4f);
    // The bounding sphere inside the narrower of the two fields of view, with 5 % to spare.
    const float halfY = glm::radians(std::clamp(fovyDegrees, 1.0f, 179.0f)) * 0.5f;
    const float halfX = std::atan(std::tan(halfY) * std::max(aspect, 1e-3f));
    const float distance = 1.05f * radius_ / std::sin(std::min(halfX, halfY));
    const float yaw = glm::radians(yawDegrees),
                pitch = std::clamp(glm::radians(pitchDegrees), -kMaxPitch, kMaxPitch);
    setLookAt(centre - distance * lookDirection(yaw, pitch), centre);
}

glm::mat4 CameraManipulator::viewMatrix() const {
    return glm::lookAt(eye(), target(), {0.0f, 0.0f, 1.0f});
}

void CameraManipulator::apply(Camera& camera) const {
    camera.viewMatrix = viewMatrix();
}

// ---------------------------------------------------------------------------------- orbit

void OrbitManipulator::setLookAt(const glm::vec3& eyeAt, const glm::vec3& targetAt) {
    const glm::vec3 d = targetAt - eyeAt;
    distance = std::max(glm::length(d), 1e-4f);
    centre = targetAt;
    if (glm::length(d) > 0.0f) anglesOf(d, yaw, pitch);
}

void OrbitManipulator::drag(MouseButton button, glm::vec2 pixels, float viewportHeight) {
    const float h = std::max(viewportHeight, 1.0f);
    switch (button) {
    case MouseButton::Left: // a drag over the viewport's height turns by 180°
        yaw -= kPi * pixels.x / h;
        pitch = std::clamp(pitch + kPi * pixels.y / h, -kMaxPitch, kMaxPitch);
        break;
    case MouseButton::Right: // down zooms in: e^2 over the viewport's height
        distance = std::clamp(distance * std::exp(-2.0f * pixels.y / h), 1e-3f * radius_, 1e3f * radius_);
        break;
    case MouseButton::Middle: { // the centre follows the pointer at its own depth
        const glm::vec3 forward = lookDirection(yaw, pitch);
        const glm::vec3 right = glm::normalize(glm::cross(forward, {0.0f, 0.0f, 1.0f}));
        const glm::vec3 up = glm::cross(right, forward);
        const float perPixel = 2.0f * distance * std::tan(glm::radians(22.5f)) / h;
        centre += perPixel * (-pixels.x * right + pixels.y * up);
        break;
    }
    }
}

void OrbitManipulator::scroll(float steps) {
    distance = std::clamp(distance * std::pow(0.85f, steps), 1e-3f * radius_, 1e3f * radius_);
}

void OrbitManipulator::move(glm::vec3 axes, float seconds, bool fast) {
    // Over the ground: forward is the view direction without its vertical part.
    const glm::vec3 forward(-std::sin(yaw), std::cos(yaw), 0.0f);
    const glm::vec3 right(std::cos(yaw), std::sin(yaw), 0.0f);
    const float step = 0.5f * distance * seconds * (fast ? 4.0f : 1.0f);
    centre += step * (axes.x * right + axes.y * forward + axes.z * glm::vec3(0.0f, 0.0f, 1.0f));
}

glm::vec3 OrbitManipulator::eye() const {
    return centre - distance * lookDirection(yaw, pitch);
}

// ------------------------------------------------------------------------------------ fly

void FlyManipulator::setLookAt(const glm::vec3& eyeAt, const glm::vec3& targetAt) {
    position = eyeAt;
    const glm::vec3 d = targetAt - eyeAt;
    if (glm::length(d) > 0.0f) {
        anglesOf(d, yaw, pitch);
        focus = glm::length(d);
    }
    // Crossing the scene at its radius per second, as a walk through a room or a flight over a
    // terrain would feel.
    speed = std::max(radius_, 1e-3f);
}

glm::vec3 FlyManipulator::direction() const {
    return lookDirection(yaw, pitch);
}

void FlyManipulator::drag(MouseButton button, glm::vec2 pixels, float viewportHeight) {
    if (button != MouseButton::Left) return;
    // Looking: a drag over the viewport's height turns the head by 90°.
    const float h = std::max(viewportHeight, 1.0f);
    yaw -= 0.5f * kPi * pixels.x / h;
    pitch = std::clamp(pitch + 0.5f * kPi * pixels.y / h, -kMaxPitch, kMaxPitch);
}

void FlyManipulator::scroll(float steps) {
    speed = std::clamp(speed * std::pow(1.25f, steps), 1e-4f * radius_, 1e4f * radius_);
}

void FlyManipulator::move(glm::vec3 axes, float seconds, bool fast) {
    const glm::vec3 forward = direction();
    const glm::vec3 right(std::cos(yaw), std::sin(yaw), 0.0f);
    const float step = speed * seconds * (fast ? 4.0f : 1.0f);
    position += step * (axes.x * right + axes.y * forward + axes.z * glm::vec3(0.0f, 0.0f, 1.0f));
}

} // namespace sgfx

#pragma once
// Shared helpers for the tests: analytic sRGB encoding and small scene builders.
#include <sgfx/Camera.h>
#include <sgfx/Image.h>
#include <sgfx/Viewer.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

#include <glm/gtc/matrix_transform.hpp>

namespace sgfx::test {

// IEC 61966-2-1 sRGB encoding of a linear value, as the framebuffer applies it once.
inline double srgbEncode(double linear) {
    linear = std::clamp(linear, 0.0, 1.0);
    return linear <= 0.0031308 ? 12.92 * linear : 1.055 * std::pow(linear, 1.0 / 2.4) - 0.055;
}
inline int srgbByte(double linear) {
    return int(std::lround(srgbEncode(linear) * 255.0));
}

inline glm::ivec4 pixelAt(const Image& img, int x, int y) {
    const std::uint8_t* p = img.pixel(x, y);
    return {p[0], p[1], p[2], img.channels > 3 ? p[3] : 255};
}

// A headless viewer looking from +Z down at the origin (Y up on screen)
// with an orthographic projection of the given half-size, so a quad at z=0 fills known pixels.
inline std::unique_ptr<Viewer> orthoTopViewer(int size, float halfExtent) {
    auto v = Viewer::createHeadless(size, size);
    auto& cam = *v->camera();
    cam.setLookAt({0, 0, 10}, {0, 0, 0}, {0, 1, 0});
    cam.projectionMatrix = glm::ortho(-halfExtent, halfExtent, -halfExtent, halfExtent, 0.1f, 100.0f);
    cam.clearColor = {0, 0, 0, 1};
    return v;
}

} // namespace sgfx::test

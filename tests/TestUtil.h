#pragma once
// Shared helpers for the tests: analytic sRGB encoding and small scene builders.
#include <sgfx/Camera.h>
#include <sgfx/Image.h>
#include <sgfx/Material.h>
#include <sgfx/Viewer.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

namespace sgfx::test {

/// True when the suite runs in CI (CI=true): a missing prerequisite fails there instead of skipping.
inline bool underCi() {
    const char* ci = std::getenv("CI");
    return ci && std::string(ci) == "true";
}

/// A test's prerequisite (shared assets, EGL...): when `available` is false the test fails under
/// CI=true naming `what`, and elsewhere skips, which CTest lists at the end among the tests that
/// did not run. Use it in the test body (it returns from it).
#define SGFX_REQUIRE(available, what)                                                                        \
    do {                                                                                                     \
        if (!(available)) {                                                                                  \
            if (::sgfx::test::underCi()) FAIL() << "missing prerequisite under CI=true: " << what;           \
            GTEST_SKIP() << "missing prerequisite: " << what;                                                \
        }                                                                                                    \
    } while (false)

/// For a test that checks more when a prerequisite is there: whether it is; when it is missing,
/// a failure naming it under CI=true, a printed note elsewhere.
inline bool optionalPrerequisite(bool available, const std::string& what) {
    if (available) return true;
    if (underCi())
        ADD_FAILURE() << "missing prerequisite under CI=true: " << what;
    else
        std::printf("sgfx-test: part of this test skipped, missing prerequisite: %s\n", what.c_str());
    return false;
}

// IEC 61966-2-1 sRGB encoding of a linear value, as the framebuffer applies it once.
inline double srgbEncode(double linear) {
    linear = std::clamp(linear, 0.0, 1.0);
    return linear <= 0.0031308 ? 12.92 * linear : 1.055 * std::pow(linear, 1.0 / 2.4) - 0.055;
}
inline int srgbByte(double linear) {
    return int(std::lround(srgbEncode(linear) * 255.0));
}

// A glTF metallic-roughness material of these factors (opaque).
inline std::shared_ptr<Material> metallicRoughness(glm::vec3 base, float metallic, float roughness) {
    auto m = Material::create();
    m->model = ShadingModel::MetallicRoughness;
    m->diffuse = glm::vec4(base, 1.0f);
    m->metallic = metallic;
    m->roughness = roughness;
    return m;
}

// A material that shows exactly colour c (emissive only: no ambient, no diffuse) with alpha.
inline std::shared_ptr<Material> flatMaterial(glm::vec3 c, float alpha = 1.0f) {
    auto m = Material::create();
    m->ambient = glm::vec3(0);
    m->diffuse = glm::vec4(0, 0, 0, alpha);
    m->emissive = c;
    return m;
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

// One frame of `scene` through orthoTopViewer(size, halfExtent).
inline Image renderTop(int size, float halfExtent, std::shared_ptr<Node> scene) {
    auto v = orthoTopViewer(size, halfExtent);
    v->setSceneData(std::move(scene));
    v->frame();
    return v->capture();
}

// An application's own program that knows nothing of sgfx's effects: transforms positions and
// writes the uniform `appColor`. The composer wraps its fragment stage for effects.
inline const char* const kForeignVert = R"(#version 450 core
layout(location = 0) in vec3 a_position;
uniform mat4 sgfx_model;
layout(std140, binding = 0) uniform SgfxFrame {
    mat4 sgfx_view; mat4 sgfx_projection; mat4 sgfx_viewProjection; mat4 sgfx_invViewProjection;
    vec4 sgfx_eye; vec4 sgfx_viewport; vec4 sgfx_ambientLight; vec4 sgfx_time; ivec4 sgfx_lightCount;
    vec4 sgfx_lightVector[8]; vec4 sgfx_lightColor[8];
};
void main() { gl_Position = sgfx_viewProjection * sgfx_model * vec4(a_position, 1.0); }
)";
inline const char* const kForeignFrag = R"(#version 450 core
uniform vec3 appColor;
layout(location = 0) out vec4 fragOut;
void main() {
    fragOut = vec4(appColor, 1.0);
}
)";

// An application's fragment shader that opts into ambient occlusion: it shows 1 − k.
inline const char* const kForeignAoFrag = R"(#version 450 core
#ifdef SGFX_AMBIENT_OCCLUSION
float sgfx_ambientOcclusion();
#endif
out vec4 fragOut;
void main() {
    float k = 0.0;
#ifdef SGFX_AMBIENT_OCCLUSION
    k = sgfx_ambientOcclusion();
#endif
    fragOut = vec4(vec3(1.0 - k), 1.0);
}
)";

// An application's fragment shader that opts into shadows: it shows the visibility of the view's
// light 0 at its pixel (1 without a ShadowNode above it). The world position comes from the
// window position through the frame block's inverse view-projection; a zero normal asks for no
// normal offset.
inline const char* const kForeignShadowFrag = R"(#version 450 core
#ifdef SGFX_LIGHT_VISIBILITY
float sgfx_lightVisibility(int light, vec3 worldPos, vec3 worldNormal);
#endif
layout(std140, binding = 0) uniform SgfxFrame {
    mat4 sgfx_view; mat4 sgfx_projection; mat4 sgfx_viewProjection; mat4 sgfx_invViewProjection;
    vec4 sgfx_eye; vec4 sgfx_viewport; vec4 sgfx_ambientLight; vec4 sgfx_time; ivec4 sgfx_lightCount;
    vec4 sgfx_lightVector[8]; vec4 sgfx_lightColor[8];
};
out vec4 fragOut;
void main() {
    float v = 1.0;
#ifdef SGFX_LIGHT_VISIBILITY
    vec4 ndc = vec4((gl_FragCoord.xy - sgfx_viewport.xy) / sgfx_viewport.zw * 2.0 - 1.0, gl_FragCoord.z * 2.0 - 1.0, 1.0);
    vec4 world = sgfx_invViewProjection * ndc;
    v = sgfx_lightVisibility(0, world.xyz / world.w, vec3(0.0));
#endif
    fragOut = vec4(vec3(v), 1.0);
}
)";

// Number of colour channels (RGB) of two equally sized images that differ by more than `tolerance`.
inline int channelsDiffering(const Image& a, const Image& b, int tolerance = 1) {
    int n = 0;
    for (int y = 0; y < a.height; ++y)
        for (int x = 0; x < a.width; ++x)
            for (int c = 0; c < 3; ++c)
                n += std::abs(pixelAt(a, x, y)[c] - pixelAt(b, x, y)[c]) > tolerance;
    return n;
}

// RFC 4648 base64, for data: URIs in hand-made glTF files.
inline std::string base64(const std::vector<unsigned char>& bytes) {
    static const char* t = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (std::size_t i = 0; i < bytes.size(); i += 3) {
        const unsigned v = unsigned(bytes[i]) << 16 |
                           (i + 1 < bytes.size() ? unsigned(bytes[i + 1]) << 8 : 0u) |
                           (i + 2 < bytes.size() ? unsigned(bytes[i + 2]) : 0u);
        out += t[v >> 18 & 63];
        out += t[v >> 12 & 63];
        out += i + 1 < bytes.size() ? t[v >> 6 & 63] : '=';
        out += i + 2 < bytes.size() ? t[v & 63] : '=';
    }
    return out;
}

/// Fails the current test with every GL error the viewer's renderer collected.
inline void expectNoGlErrors(Viewer& v) {
    for (const auto& e : v.renderer().takeGlErrors())
        ADD_FAILURE() << "GL: " << e;
}

} // namespace sgfx::test

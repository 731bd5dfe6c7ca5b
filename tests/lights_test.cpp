// Punctual lights (KHR_lights_punctual): range, inverse-square falloff and spot cones against
// closed forms computed here from the spec's formulas; the light list (more lights than the
// unrolled loop takes) against the sum of the closed forms; per-vertex lighting; Light's checks.
// Linear float targets. The glTF side is in lights_gltf_test.cpp.
#include "TestUtil.h"

#include <sgfx/Geometry.h>
#include <sgfx/Group.h>
#include <sgfx/Shapes.h>

#include <glm/gtc/constants.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <random>

using namespace sgfx;
using namespace sgfx::test;

namespace {

constexpr int kSize = 64;
constexpr float kHalf = 2.0f;
const glm::dvec3 kAlbedo(0.8, 0.6, 0.4);

std::unique_ptr<Viewer> floatViewer(std::unique_ptr<Viewer> v) {
    v->renderer().options().colorTarget = RendererOptions::ColorTarget::Rgba32F;
    return v;
}

glm::dvec3 worldOfPixel(int px, int py) {
    return {-kHalf + (px + 0.5) / kSize * 2 * kHalf, kHalf - (py + 0.5) / kSize * 2 * kHalf, 0.0};
}

glm::dvec3 pixel(const FloatImage& img, int x, int y) {
    const float* p = &img.rgba[(std::size_t(y) * std::size_t(img.width) + std::size_t(x)) * 4];
    return {p[0], p[1], p[2]};
}

// A Lambert quad (Blinn-Phong without specular) facing +Z at z = 0.
std::shared_ptr<Geometry> lambertQuad(float size) {
    auto q = shapes::quad(size, size);
    auto m = Material::create();
    m->diffuse = glm::vec4(glm::vec3(kAlbedo), 1.0f);
    q->getOrCreateStateSet().material.set(m);
    return q;
}

// KHR_lights_punctual, written from the spec: what a light of colour × intensity `c` adds to a
// Lambert surface of albedo kAlbedo at P with normal +Z, in sgfx's units (light colours are
// irradiance over π: a white surface facing a light shows its colour).
struct Punctual {
    glm::dvec3 position{0.0}, color{1.0};
    double range = 0.0; // 0: unlimited
    bool inverseSquare = true;
    bool spot = false;
    glm::dvec3 axis{0, 0, -1};
    double inner = 0.0, outer = glm::quarter_pi<double>();

    // The spec's reference spot code, as angles: a = (cos θ − cos outer) / (cos inner − cos outer)
    // clamped to [0, 1], squared.
    double cone(const glm::dvec3& P) const {
        if (!spot) return 1.0;
        const double cd = glm::dot(glm::normalize(axis), glm::normalize(P - position));
        const double a = std::clamp((cd - std::cos(outer)) / (std::cos(inner) - std::cos(outer)), 0.0, 1.0);
        return a * a;
    }
    // The spec's recommended range window over d² (or the window alone, without falloff).
    double distance(const glm::dvec3& P) const {
        const double d = glm::length(position - P);
        const double window = range > 0.0 ? std::clamp(1.0 - std::pow(d / range, 4.0), 0.0, 1.0) : 1.0;
        return window / (inverseSquare ? d * d : 1.0);
    }
    glm::dvec3 at(const glm::dvec3& P) const {
        const double NdotL = std::max(glm::normalize(position - P).z, 0.0);
        return kAlbedo * color * distance(P) * cone(P) * NdotL;
    }
    std::shared_ptr<Light> node() const {
        auto l = Light::create(spot ? LightType::Spot : LightType::Point);
        l->position = glm::vec3(position);
        l->color = glm::vec3(color);
        l->range = float(range);
        l->falloff = inverseSquare ? LightFalloff::InverseSquare : LightFalloff::None;
        l->direction = glm::vec3(axis);
        l->innerConeAngle = float(inner);
        l->outerConeAngle = float(outer);
        return l;
    }
};

// |got − want| within a relative and an absolute tolerance, per channel.
bool near(const glm::dvec3& got, const glm::dvec3& want, double rel = 2e-3, double abs = 2e-4) {
    for (int c = 0; c < 3; ++c)
        if (!(std::abs(got[c] - want[c]) <= rel * std::abs(want[c]) + abs)) return false;
    return true;
}

// The quad under `lights`, seen from above (orthographic), `unrolled` = maxUnrolledLights.
FloatImage renderTop(const std::vector<Punctual>& lights, int unrolled,
                     RendererOptions::Lighting lighting = RendererOptions::Lighting::PerPixel,
                     std::shared_ptr<Node> surface = nullptr) {
    auto v = floatViewer(orthoTopViewer(kSize, kHalf));
    v->renderer().options().maxUnrolledLights = unrolled;
    v->renderer().options().lighting = lighting;
    auto root = Group::create();
    for (const Punctual& p : lights)
        root->addChild(p.node());
    root->addChild(surface ? surface : lambertQuad(2 * kHalf));
    v->setSceneData(root);
    v->frame();
    expectNoGlErrors(*v);
    return v->renderer().readPixelsLinear();
}

} // namespace

TEST(Lights, PointLightWithRangeFallsOffAsTheSpecSays) {
    Punctual p;
    p.position = {0.3, -0.2, 0.6};
    p.color = {1.0, 0.9, 0.7};
    p.range = 1.7;
    for (int unrolled : {8, 0}) { // the unrolled loop, then the light list
        SCOPED_TRACE(unrolled);
        const FloatImage img = renderTop({p}, unrolled);
        int lit = 0, dark = 0, bad = 0;
        for (int y = 0; y < kSize; ++y)
            for (int x = 0; x < kSize; ++x) {
                const glm::dvec3 want = p.at(worldOfPixel(x, y)), got = pixel(img, x, y);
                if (!near(got, want) && ++bad <= 5)
                    ADD_FAILURE() << "pixel " << x << "," << y << ": " << got.r << " want " << want.r;
                lit += want.r > 0.05;
                dark += glm::length(worldOfPixel(x, y) - p.position) > p.range;
            }
        EXPECT_EQ(bad, 0);
        EXPECT_GT(lit, 500);  // the falloff is seen over many pixels
        EXPECT_GT(dark, 500); // and so is the range: beyond it, nothing
    }
}

TEST(Lights, SpotIsFullInsideTheInnerConeZeroOutsideTheOuterAndTheSpecsCurveBetween) {
    Punctual s;
    s.spot = true;
    s.position = {0.2, 0.1, 1.5};
    s.axis = glm::normalize(glm::dvec3(0.3, -0.2, -1.0));
    s.inner = 0.25;
    s.outer = 0.5;
    s.color = {2.0, 1.5, 1.0};
    for (bool inverseSquare : {true, false})
        for (int unrolled : {8, 0}) {
            SCOPED_TRACE(testing::Message()
                         << "inverse square " << inverseSquare << ", unrolled " << unrolled);
            s.inverseSquare = inverseSquare;
            const FloatImage img = renderTop({s}, unrolled);
            int inside = 0, outside = 0, between = 0, bad = 0;
            for (int y = 0; y < kSize; ++y)
                for (int x = 0; x < kSize; ++x) {
                    const glm::dvec3 P = worldOfPixel(x, y), got = pixel(img, x, y);
                    const double theta = std::acos(glm::dot(s.axis, glm::normalize(P - s.position)));
                    Punctual full = s;
                    full.spot = false;
                    glm::dvec3 want = s.at(P);
                    if (theta < s.inner - 1e-3) {
                        ++inside;
                        want = full.at(P); // the unattenuated light
                    } else if (theta > s.outer + 1e-3) {
                        ++outside;
                        want = glm::dvec3(0.0);
                    } else {
                        ++between;
                    }
                    if (!near(got, want) && ++bad <= 5)
                        ADD_FAILURE() << "pixel " << x << "," << y << " at " << theta << " rad: " << got.r
                                      << " want " << want.r;
                }
            EXPECT_EQ(bad, 0);
            EXPECT_GT(inside, 100);
            EXPECT_GT(outside, 100);
            EXPECT_GT(between, 100);
        }
}

TEST(Lights, ManyLightsInTheListGiveTheSumOfTheirClosedForms) {
    // 120 ranged point and spot lights, plus lights without a range (in every tile), seen in
    // perspective at 160×120 (partial tiles on the top row): every pixel is the sum of the
    // closed forms, so no light is missing from a tile or listed twice.
    std::mt19937 rng(7);
    auto u = [&](double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); };
    std::vector<Punctual> lights;
    for (int i = 0; i < 120; ++i) {
        Punctual p;
        p.position = {u(-3, 3), u(-3, 3), u(0.15, 0.8)};
        p.color = {u(0.02, 0.15), u(0.02, 0.15), u(0.02, 0.15)};
        p.range = u(0.4, 1.6);
        p.spot = i % 6 == 0;
        p.axis = glm::normalize(glm::dvec3(u(-0.5, 0.5), u(-0.5, 0.5), -1.0));
        p.inner = 0.2;
        p.outer = 0.7;
        lights.push_back(p);
    }
    Punctual unlimited; // no range: reaches every tile
    unlimited.position = {-1.0, 1.5, 2.5};
    unlimited.color = glm::dvec3(0.5);
    lights.push_back(unlimited);
    const int w = 160, h = 120;
    auto v = floatViewer(Viewer::createHeadless(w, h));
    auto& cam = *v->camera();
    cam.setPerspective(50.0f, 0.1f, 100.0f);
    cam.setLookAt({0.4f, -4.0f, 3.2f}, {0.0f, 0.3f, 0.0f}, {0, 0, 1});
    cam.clearColor = {0, 0, 0, 1};
    auto root = Group::create();
    for (const Punctual& p : lights)
        root->addChild(p.node());
    root->addChild(lambertQuad(6.0f));
    v->setSceneData(root);
    v->frame();
    expectNoGlErrors(*v);
    const FloatImage img = v->renderer().readPixelsLinear();
    const glm::mat4 proj = glm::perspective(glm::radians(50.0f), float(w) / float(h), 0.1f, 100.0f);
    const glm::vec4 viewport(0, 0, w, h);
    int tested = 0, bad = 0;
    for (int py = 0; py < h; ++py)
        for (int px = 0; px < w; ++px) {
            // The pixel centre's ray (window y runs up, the image's rows down) onto z = 0.
            const glm::vec3 win(float(px) + 0.5f, float(h - 1 - py) + 0.5f, 0.0f);
            const glm::dvec3 a = glm::unProject(win, cam.viewMatrix, proj, viewport);
            const glm::dvec3 b = glm::unProject(win + glm::vec3(0, 0, 1), cam.viewMatrix, proj, viewport);
            const glm::dvec3 P = a + (b - a) * (a.z / (a.z - b.z));
            if (std::abs(P.x) > 2.95 || std::abs(P.y) > 2.95) continue;
            glm::dvec3 want(0.0);
            for (const Punctual& p : lights)
                want += p.at(P);
            ++tested;
            if (!near(pixel(img, px, py), want, 3e-3, 3e-4) && ++bad <= 5)
                ADD_FAILURE() << "pixel " << px << "," << py << ": " << pixel(img, px, py).r << " want "
                              << want.r;
        }
    EXPECT_EQ(bad, 0);
    EXPECT_GT(tested, 8000);
}

TEST(Lights, PerVertexLightingAttenuatesAndReadsTheList) {
    // A finely tessellated quad: Gouraud sums per vertex. The unrolled loop and the light list
    // give the same image, and the spot leaves the far corner dark (attenuation per vertex).
    auto grid =
        shapes::heightfield(-kHalf, -kHalf, 2 * kHalf, 2 * kHalf, 48, 48, [](float, float) { return 0.0f; });
    auto m = Material::create();
    m->diffuse = glm::vec4(glm::vec3(kAlbedo), 1.0f);
    grid->getOrCreateStateSet().material.set(m);
    Punctual spot;
    spot.spot = true;
    spot.position = {-1.0, 1.0, 1.0};
    spot.inner = 0.2;
    spot.outer = 0.4;
    Punctual point;
    point.position = {0.8, 0.5, 0.5};
    point.range = 1.0;
    const std::vector<Punctual> lights{spot, point};
    const auto gouraud = RendererOptions::Lighting::PerVertex;
    const FloatImage unrolled = renderTop(lights, 8, gouraud, grid);
    const FloatImage listed = renderTop(lights, 0, gouraud, grid);
    double maxDiff = 0.0, peak = 0.0;
    for (std::size_t i = 0; i < unrolled.rgba.size(); ++i) {
        maxDiff = std::max(maxDiff, double(std::abs(unrolled.rgba[i] - listed.rgba[i])));
        peak = std::max(peak, double(unrolled.rgba[i]));
    }
    EXPECT_LT(maxDiff, 1e-4);
    EXPECT_GT(peak, 0.3);
    // Both lights are far from the bottom right corner: the spot's cone and the point's range.
    EXPECT_LT(pixel(listed, kSize - 3, kSize - 3).r, 1e-6);
    // Under the spot its closed form holds (a vertex every 1.33 pixels, a smooth light).
    EXPECT_NEAR(pixel(listed, 16, 16).r, spot.at(worldOfPixel(16, 16)).r, 0.02);
}

TEST(Lights, BadValuesNameTheLightAndTheField) {
    auto expectRefused = [](const Light& l, const std::string& field) {
        try {
            l.validate();
            ADD_FAILURE() << "accepted a bad " << field;
        } catch (const std::invalid_argument& e) {
            EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find("lamp"), std::string::npos) << e.what();
        }
    };
    auto l = Light::create(LightType::Spot);
    l->name = "lamp";
    EXPECT_NO_THROW(l->validate());
    l->innerConeAngle = 0.9f; // not below the outer angle (π/4)
    expectRefused(*l, "outerConeAngle");
    l->innerConeAngle = -0.1f;
    expectRefused(*l, "innerConeAngle");
    l->innerConeAngle = 0.1f;
    l->outerConeAngle = 2.0f;
    expectRefused(*l, "outerConeAngle");
    l->outerConeAngle = 0.5f;
    l->range = -1.0f;
    expectRefused(*l, "range");
    l->range = 2.0f;
    l->intensity = std::nanf("");
    expectRefused(*l, "intensity");
    l->intensity = 1.0f;
    l->falloff = LightFalloff(7);
    expectRefused(*l, "falloff");
    l->falloff = LightFalloff::InverseSquare;
    EXPECT_NO_THROW(l->validate());
    // The cull refuses it too: a frame with a bad cone throws, naming the light.
    auto v = orthoTopViewer(16, 1.0f);
    l->outerConeAngle = 0.05f;
    auto root = Group::create();
    root->addChild(l);
    v->setSceneData(root);
    EXPECT_THROW(v->frame(), std::invalid_argument);
    auto badOption = orthoTopViewer(16, 1.0f);
    badOption->renderer().options().maxUnrolledLights = 9;
    badOption->setSceneData(Group::create());
    EXPECT_THROW(badOption->frame(), std::invalid_argument);
}

TEST(Lights, LightsAreCollectedWhenTheirGroupIsOutOfView) {
    // A lamp whose post is out of view still lights the visible ground: a Light keeps its
    // ancestors from being culled; its range sphere decides.
    Punctual p;
    p.position = {kHalf + 0.5, 0.0, 0.3}; // beside the view
    p.range = 1.5;
    auto post = Group::create();
    post->addChild(shapes::box({0.1f, 0.1f, 0.6f}));
    auto light = p.node();
    light->position = {0.0f, 0.0f, 0.3f}; // on the post, placed by its Transform
    post->addChild(light);
    auto place =
        Transform::create(glm::translate(glm::mat4(1.0f), glm::vec3(p.position.x, p.position.y, 0.0)));
    place->addChild(post);
    auto v = floatViewer(orthoTopViewer(kSize, kHalf));
    auto root = Group::create();
    root->addChild(place);
    root->addChild(lambertQuad(2 * kHalf));
    v->setSceneData(root);
    v->frame();
    const FloatImage img = v->renderer().readPixelsLinear();
    const int x = kSize - 2, y = kSize / 2;
    EXPECT_GT(p.at(worldOfPixel(x, y)).r, 0.05);
    EXPECT_TRUE(near(pixel(img, x, y), p.at(worldOfPixel(x, y))));
}

TEST(Lights, ForeignShadersSeeTheFirstEightLightsWithTheList) {
    // Beyond eight lights the built-in material reads the list, but the frame block a foreign
    // shader declares keeps its meaning: sgfx_lightCount.x <= 8 and those lights filled in.
    static const char* const frag = R"(#version 450 core
layout(std140, binding = 0) uniform SgfxFrame {
    mat4 sgfx_view; mat4 sgfx_projection; mat4 sgfx_viewProjection; mat4 sgfx_invViewProjection;
    vec4 sgfx_eye; vec4 sgfx_viewport; vec4 sgfx_ambientLight; vec4 sgfx_time; ivec4 sgfx_lightCount;
    vec4 sgfx_lightVector[8]; vec4 sgfx_lightColor[8];
};
layout(location = 0) out vec4 fragOut;
void main() {
    float sum = 0.0;
    for (int i = 0; i < sgfx_lightCount.x; ++i) sum += sgfx_lightColor[i].r;
    fragOut = vec4(sum / 4.0, float(sgfx_lightCount.x) / 16.0, 0.0, 1.0);
}
)";
    auto v = orthoTopViewer(16, 1.0f);
    v->renderer().options().colorTarget = RendererOptions::ColorTarget::Rgba32F;
    auto root = Group::create();
    for (int i = 0; i < 12; ++i) {
        auto l = Light::create(LightType::Directional);
        l->color = glm::vec3(0.05f * float(i + 1));
        root->addChild(l);
    }
    auto q = shapes::quad(2.0f, 2.0f);
    q->getOrCreateStateSet().program.set(ShaderProgram::create("app_lights", kForeignVert, frag));
    root->addChild(q);
    v->setSceneData(root);
    v->frame();
    expectNoGlErrors(*v);
    const FloatImage img = v->renderer().readPixelsLinear();
    const float* p = &img.rgba[(8 * 16 + 8) * 4];
    EXPECT_NEAR(p[1], 8.0f / 16.0f, 1e-6f) << "sgfx_lightCount.x";
    EXPECT_NEAR(p[0], 0.05f * 36.0f / 4.0f, 1e-5f) << "the first eight lights' colours"; // 1 + ... + 8 = 36
}

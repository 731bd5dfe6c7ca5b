// KHR_lights_punctual in the glTF loader: types, colours, intensities (lux and candela to sgfx's
// irradiance over π), ranges, cones and world directions after the Y-up to Z-up turn; pixels
// against glTF's own formula (L = c_diff / π · E · N·L); bad values and indices name the file
// and the element.
#include "TestUtil.h"

#include <sgfx/GltfLoader.h>
#include <sgfx/Group.h>
#include <sgfx/Shapes.h>

#include <glm/gtc/constants.hpp>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>

using namespace sgfx;
using namespace sgfx::test;

namespace {

const double kPi = glm::pi<double>();

// Four lights on four nodes: a sun turned −90° about X (pointing down), a point light moved to
// (1, 2, 3), a spot turned +90° about Y at (0, 4, 0), and a spot with the defaults.
const char* const kLights = R"({
  "asset": {"version": "2.0"},
  "extensionsUsed": ["KHR_lights_punctual"],
  "extensions": {"KHR_lights_punctual": {"lights": [
    {"name": "sun", "type": "directional", "color": [1.0, 0.9, 0.8], "intensity": 3.0},
    {"type": "point", "color": [0.5, 1.0, 0.25], "intensity": 20.0, "range": 7.5},
    {"name": "spot", "type": "spot", "intensity": 100.0, "range": 12.0,
     "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.6}},
    {"type": "spot", "spot": {}}
  ]}},
  "scene": 0,
  "scenes": [{"nodes": [0, 1, 2, 3]}],
  "nodes": [
    {"name": "sun node", "rotation": [-0.70710678, 0, 0, 0.70710678],
     "extensions": {"KHR_lights_punctual": {"light": 0}}},
    {"translation": [1, 2, 3], "extensions": {"KHR_lights_punctual": {"light": 1}}},
    {"translation": [0, 4, 0], "rotation": [0, 0.70710678, 0, 0.70710678],
     "extensions": {"KHR_lights_punctual": {"light": 2}}},
    {"extensions": {"KHR_lights_punctual": {"light": 3}}}
  ]
})";

std::filesystem::path writeFile(const std::string& name, const std::string& json) {
    const auto path = std::filesystem::temp_directory_path() / name;
    std::ofstream(path) << json;
    return path;
}

// Every Light below `node` with its world matrix, in graph order.
void collect(const Node& node, const glm::mat4& m, std::vector<std::pair<const Light*, glm::mat4>>& out) {
    glm::mat4 here = m;
    if (const auto* t = dynamic_cast<const Transform*>(&node)) here = m * t->matrix();
    if (const auto* l = dynamic_cast<const Light*>(&node)) out.emplace_back(l, m);
    if (const auto* g = dynamic_cast<const Group*>(&node))
        for (const auto& c : g->children())
            collect(*c, here, out);
}

void expectVec(const glm::vec3& got, const glm::dvec3& want, double tol = 1e-5) {
    EXPECT_NEAR(got.x, want.x, tol);
    EXPECT_NEAR(got.y, want.y, tol);
    EXPECT_NEAR(got.z, want.z, tol);
}

} // namespace

TEST(GltfLights, LightsBecomeSgfxLightsInWorldSpace) {
    GltfStats stats;
    const auto root = loadGltf(writeFile("sgfx_lights.gltf", kLights), {}, &stats);
    EXPECT_EQ(stats.lights, 4u);
    EXPECT_TRUE(stats.warnings.empty()) << stats.warnings.front();
    std::vector<std::pair<const Light*, glm::mat4>> lights;
    collect(*root, glm::mat4(1.0f), lights);
    ASSERT_EQ(lights.size(), 4u);
    auto worldDirection = [&](int i) {
        return glm::normalize(glm::mat3(lights[std::size_t(i)].second) *
                              lights[std::size_t(i)].first->direction);
    };
    auto worldPosition = [&](int i) {
        return glm::vec3(lights[std::size_t(i)].second *
                         glm::vec4(lights[std::size_t(i)].first->position, 1.0f));
    };
    // glTF (x, y, z) is sgfx (x, −z, y); a light shines down its local −Z.
    const Light& sun = *lights[0].first;
    EXPECT_EQ(sun.type, LightType::Directional);
    EXPECT_EQ(sun.name, "sun");
    expectVec(sun.color, {1.0, 0.9, 0.8});
    EXPECT_NEAR(sun.intensity, 3.0 / kPi, 1e-6); // lux → irradiance over π
    expectVec(worldDirection(0), {0, 0, -1});    // glTF −Y: down

    const Light& point = *lights[1].first;
    EXPECT_EQ(point.type, LightType::Point);
    EXPECT_EQ(point.falloff, LightFalloff::InverseSquare);
    expectVec(point.color, {0.5, 1.0, 0.25});
    EXPECT_NEAR(point.intensity, 20.0 / kPi, 1e-5); // candela → over π, and 1/d²
    EXPECT_FLOAT_EQ(point.range, 7.5f);
    expectVec(worldPosition(1), {1, -3, 2});

    const Light& spot = *lights[2].first;
    EXPECT_EQ(spot.type, LightType::Spot);
    EXPECT_EQ(spot.falloff, LightFalloff::InverseSquare);
    EXPECT_NEAR(spot.intensity, 100.0 / kPi, 1e-4);
    EXPECT_FLOAT_EQ(spot.range, 12.0f);
    EXPECT_FLOAT_EQ(spot.innerConeAngle, 0.2f);
    EXPECT_FLOAT_EQ(spot.outerConeAngle, 0.6f);
    expectVec(worldPosition(2), {0, 0, 4});
    expectVec(worldDirection(2), {-1, 0, 0}); // glTF −Z turned +90° about Y: −X, the same in sgfx

    const Light& plain = *lights[3].first;
    EXPECT_EQ(plain.type, LightType::Spot);
    EXPECT_FLOAT_EQ(plain.innerConeAngle, 0.0f);
    EXPECT_NEAR(plain.outerConeAngle, kPi / 4, 1e-6);
    EXPECT_EQ(plain.range, 0.0f); // unlimited
    EXPECT_NEAR(plain.intensity, 1.0 / kPi, 1e-6);
    expectVec(worldDirection(3), {0, 1, 0}); // glTF −Z is sgfx +Y
}

TEST(GltfLights, PixelsFollowGltfsFormula) {
    // A sun of E = 2 lux straight down and a point light of I = 5 cd with a range, over a
    // Lambert quad: glTF's renderer gives c_diff / π · (E + I · window / d² · N·L).
    const std::string json = R"({
      "asset": {"version": "2.0"},
      "extensions": {"KHR_lights_punctual": {"lights": [
        {"type": "directional", "intensity": 2.0},
        {"type": "point", "intensity": 5.0, "range": 3.0}]}},
      "scenes": [{"nodes": [0, 1]}],
      "nodes": [
        {"rotation": [-0.70710678, 0, 0, 0.70710678], "extensions": {"KHR_lights_punctual": {"light": 0}}},
        {"translation": [0.5, 1.0, -0.3], "extensions": {"KHR_lights_punctual": {"light": 1}}}]
    })";
    const auto lights = loadGltf(writeFile("sgfx_lights_pixels.gltf", json));
    const glm::dvec3 albedo(0.7, 0.5, 0.3);
    auto quad = shapes::quad(4.0f, 4.0f);
    auto m = Material::create();
    m->diffuse = glm::vec4(glm::vec3(albedo), 1.0f);
    quad->getOrCreateStateSet().material.set(m);
    auto root = Group::create();
    root->addChild(lights);
    root->addChild(quad);
    auto v = orthoTopViewer(32, 2.0f);
    v->renderer().options().colorTarget = RendererOptions::ColorTarget::Rgba32F;
    v->setSceneData(root);
    v->frame();
    const FloatImage img = v->renderer().readPixelsLinear();
    const glm::dvec3 lamp(0.5, 0.3, 1.0); // glTF (0.5, 1.0, −0.3) in Z-up
    for (int y = 1; y < 32; y += 5)
        for (int x = 1; x < 32; x += 5) {
            const glm::dvec3 P(-2.0 + (x + 0.5) / 8.0, 2.0 - (y + 0.5) / 8.0, 0.0);
            const double d = glm::length(lamp - P);
            const double window = std::clamp(1.0 - std::pow(d / 3.0, 4.0), 0.0, 1.0);
            const double E = 2.0 + 5.0 * window / (d * d) * (lamp.z - P.z) / d;
            const float* p = &img.rgba[(std::size_t(y) * 32 + std::size_t(x)) * 4];
            for (int c = 0; c < 3; ++c)
                EXPECT_NEAR(p[c], albedo[c] / kPi * E, 1e-3 * albedo[c] / kPi * E) << x << "," << y;
        }
}

TEST(GltfLights, BadValuesAndIndicesNameTheFileAndElement) {
    struct Case {
        const char* light;     // the lights array's one entry
        const char* nodeLight; // the node's extension object
        const char* element;   // expected in the message
    };
    const Case cases[] = {
        {R"({"type": "point", "intensity": -1})", R"({"light": 0})", "lights[0].intensity"},
        {R"({"type": "point", "range": 0})", R"({"light": 0})", "lights[0].range"},
        {R"({"type": "point", "range": -2})", R"({"light": 0})", "lights[0].range"},
        {R"({"type": "point", "color": [1, 1]})", R"({"light": 0})", "lights[0].color"},
        {R"({"type": "point", "color": [1, 2, 0]})", R"({"light": 0})", "lights[0].color[1]"},
        {R"({"type": "area"})", R"({"light": 0})", "lights[0].type"},
        {R"({"intensity": 1})", R"({"light": 0})", "lights[0].type"},
        {R"({"type": "spot"})", R"({"light": 0})", "lights[0].spot"},
        {R"({"type": "spot", "spot": {"innerConeAngle": 0.5, "outerConeAngle": 0.5}})", R"({"light": 0})",
         "lights[0].spot.innerConeAngle"},
        {R"({"type": "spot", "spot": {"outerConeAngle": 2.0}})", R"({"light": 0})",
         "lights[0].spot.outerConeAngle"},
        {R"({"type": "spot", "spot": {"innerConeAngle": "wide"}})", R"({"light": 0})", "spot.innerConeAngle"},
        {R"({"type": "point"})", R"({"light": 1})", "nodes[0].extensions.KHR_lights_punctual.light"},
        {R"({"type": "point"})", R"({"light": -1})", "nodes[0].extensions.KHR_lights_punctual.light"},
        {R"({"type": "point"})", R"({"light": 0.5})", "nodes[0].extensions.KHR_lights_punctual.light"},
        {R"({"type": "point"})", R"({})", "nodes[0].extensions.KHR_lights_punctual"},
    };
    int i = 0;
    for (const Case& k : cases) {
        const std::string json = std::string(R"({"asset": {"version": "2.0"},
          "extensions": {"KHR_lights_punctual": {"lights": [)") +
                                 k.light + R"(]}},
          "scenes": [{"nodes": [0]}], "nodes": [{"extensions": {"KHR_lights_punctual": )" +
                                 k.nodeLight + "}}]}";
        const std::string name = "sgfx_bad_light_" + std::to_string(i++) + ".gltf";
        try {
            (void)loadGltf(writeFile(name, json));
            ADD_FAILURE() << "loaded " << k.light << " / " << k.nodeLight;
        } catch (const LoadError& e) {
            const std::string what = e.what();
            EXPECT_NE(what.find(name), std::string::npos) << what;
            EXPECT_NE(what.find(k.element), std::string::npos) << "want " << k.element << ": " << what;
        }
    }
}

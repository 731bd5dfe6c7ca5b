// glTF material extensions: KHR_materials_unlit, KHR_materials_clearcoat, KHR_materials_specular
// and KHR_materials_emissive_strength (transmission's pixels: transmission_test.cpp; its loader here).
// Rendered pixels (linear float targets, 64×64, orthographic from +Z) against the Khronos formulas written
// out here in double precision; the loader against small files written by the test and against the shared
// sample models' JSON.
#include "TestUtil.h"

#include <sgfx/Geometry.h>
#include <sgfx/GltfLoader.h>
#include <sgfx/Group.h>
#include <sgfx/NodeVisitor.h>
#include <sgfx/Shapes.h>
#include <sgfx/nodes/fog/FogNode.h>

#include <glm/gtc/constants.hpp>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <set>

using namespace sgfx;
using namespace sgfx::test;

namespace {

constexpr int kSize = 64;
constexpr float kHalf = 2.0f;
const glm::dvec3 kEye(0.0, 0.0, 10.0);
const glm::dvec3 kUp(0.0, 0.0, 1.0); // the quad's normal
const std::pair<int, int> kPixels[] = {{32, 32}, {5, 5}, {60, 10}, {20, 50}, {45, 45}};

std::unique_ptr<Viewer> floatViewer() {
    auto v = orthoTopViewer(kSize, kHalf);
    v->renderer().options().colorTarget = RendererOptions::ColorTarget::Rgba32F;
    return v;
}

glm::dvec3 worldOfPixel(int px, int py) {
    return {-kHalf + (px + 0.5) / kSize * 2 * kHalf, kHalf - (py + 0.5) / kSize * 2 * kHalf, 0.0};
}

glm::dvec3 viewAt(int px, int py) {
    return glm::normalize(kEye - worldOfPixel(px, py));
}

glm::dvec3 pixel(const FloatImage& img, int x, int y) {
    const float* p = &img.rgba[(std::size_t(y) * std::size_t(img.width) + std::size_t(x)) * 4];
    return {p[0], p[1], p[2]};
}

double srgbDecode(double e) {
    return e <= 0.04045 ? e / 12.92 : std::pow((e + 0.055) / 1.055, 2.4);
}

// A 1×1 texture holding `bytes`; value() is what sampling it gives (decoded when sRGB).
struct Texel {
    glm::ivec4 bytes;
    bool srgb;
    std::shared_ptr<Texture> texture() const {
        auto img = Image::create(1, 1, 4);
        for (int c = 0; c < 4; ++c)
            img->pixels[std::size_t(c)] = std::uint8_t(bytes[c]);
        auto t = Texture::create(img, srgb);
        t->minFilter = t->magFilter = Filter::Nearest;
        return t;
    }
    glm::dvec4 value() const {
        glm::dvec4 v = glm::dvec4(bytes) / 255.0;
        if (srgb)
            for (int c = 0; c < 3; ++c)
                v[c] = srgbDecode(v[c]);
        return v;
    }
};

// The glTF BRDF's specular lobe without Fresnel, π·D·Vis (spec appendix B: GGX, height-correlated
// Smith), with the renderer's documented clamp of the perceptual roughness at 0.045.
double lobe(glm::dvec3 N, glm::dvec3 V, glm::dvec3 L, double roughness) {
    const double a = std::pow(std::max(roughness, 0.045), 2.0), a2 = a * a;
    const glm::dvec3 H = glm::normalize(L + V);
    const double NL = std::max(glm::dot(N, L), 0.0), NV = std::max(glm::dot(N, V), 1e-4);
    const double NH = std::max(glm::dot(N, H), 0.0);
    if (NL <= 0.0) return 0.0;
    const double d = NH * NH * (a2 - 1.0) + 1.0;
    const double D = a2 / (glm::pi<double>() * d * d);
    const double Vis =
        0.5 / (NL * std::sqrt(NV * NV * (1.0 - a2) + a2) + NV * std::sqrt(NL * NL * (1.0 - a2) + a2));
    return glm::pi<double>() * D * Vis;
}

glm::dvec3 schlick(glm::dvec3 f0, glm::dvec3 f90, double cosine) {
    return f0 + (f90 - f0) * std::pow(1.0 - cosine, 5.0);
}

// What KHR_materials_specular changes in the dielectric part (its "Implementation" section).
struct SpecularExt {
    double factor = 1.0;
    glm::dvec3 colour{1.0};
};

// One directional light of colour `light` (irradiance over π, as the renderer documents), no
// ambient: the metallic-roughness material with KHR_materials_specular's F0/F90 and
// (1 - max(F)) diffuse weight.
glm::dvec3 shade(glm::dvec3 base, double metallic, double roughness, const SpecularExt& ext, glm::dvec3 N,
                 glm::dvec3 V, glm::dvec3 L, glm::dvec3 light) {
    const glm::dvec3 dielectricF0 = glm::min(0.04 * ext.colour, glm::dvec3(1.0)) * ext.factor;
    const glm::dvec3 f0 = glm::mix(dielectricF0, base, metallic);
    const glm::dvec3 f90 = glm::dvec3(glm::mix(ext.factor, 1.0, metallic));
    const glm::dvec3 F = schlick(f0, f90, std::max(glm::dot(V, glm::normalize(L + V)), 0.0));
    const double maxF = std::max(F.r, std::max(F.g, F.b));
    const double NL = std::max(glm::dot(N, L), 0.0);
    return light * NL *
           ((1.0 - maxF) * glm::mix(base, glm::dvec3(0.0), metallic) + F * lobe(N, V, L, roughness));
}

// KHR_materials_clearcoat's layering: base·(1 - w·Fc) + w·Fc·lobe(N_c, clearcoat roughness).
glm::dvec3 coat(glm::dvec3 base, double weight, double roughness, glm::dvec3 Nc, glm::dvec3 V, glm::dvec3 L,
                glm::dvec3 light) {
    const double Fc = 0.04 + 0.96 * std::pow(1.0 - std::abs(glm::dot(Nc, V)), 5.0);
    const double NL = std::max(glm::dot(Nc, L), 0.0);
    return base * (1.0 - weight * Fc) + weight * Fc * light * NL * lobe(Nc, V, L, roughness);
}

struct Scene {
    std::shared_ptr<Group> root = Group::create();
    std::shared_ptr<Light> sun = Light::create(LightType::Directional);
    explicit Scene(glm::vec3 direction, float ambient = 0.0f) {
        sun->direction = glm::normalize(direction);
        sun->color = glm::vec3(1.0f);
        root->addChild(sun);
        auto amb = Light::create(LightType::Ambient);
        amb->color = glm::vec3(ambient);
        root->addChild(amb);
    }
    glm::dvec3 towardsLight() const { return -glm::normalize(glm::dvec3(sun->direction)); }
};

std::shared_ptr<Geometry> quadWith(const std::shared_ptr<Material>& m) {
    auto q = shapes::quad(2 * kHalf, 2 * kHalf);
    q->getOrCreateStateSet().material.set(m);
    return q;
}

FloatImage render(Scene& scene, const std::shared_ptr<Node>& content) {
    auto v = floatViewer();
    scene.root->addChild(content);
    v->setSceneData(scene.root);
    v->frame();
    EXPECT_TRUE(v->renderer().takeGlErrors().empty());
    return v->renderer().readPixelsLinear();
}

std::shared_ptr<Material> metalRough(glm::vec3 base, float metallic, float roughness) {
    return metallicRoughness(base, metallic, roughness);
}

void expectPixels(const FloatImage& img, const std::function<glm::dvec3(glm::dvec3 V)>& expected,
                  const std::string& what) {
    for (auto [px, py] : kPixels) {
        const glm::dvec3 want = expected(viewAt(px, py)), got = pixel(img, px, py);
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(got[c], want[c], 2e-3 + 2e-3 * want[c])
                << what << " pixel " << px << "," << py << " c" << c;
    }
}

} // namespace

TEST(MaterialExt, UnlitIsTheBaseColourWhateverTheLights) {
    const Texel texel{{200, 90, 30, 255}, true};
    const glm::dvec4 factor(0.9, 0.8, 0.5, 1.0), vertex(0.5, 1.0, 0.75, 1.0);
    auto makeQuad = [&] {
        auto m = Material::create();
        m->model = ShadingModel::Unlit;
        m->diffuse = glm::vec4(factor);
        m->baseColorTexture = texel.texture();
        m->emissive = glm::vec3(0.3f); // not part of an unlit material
        m->ambient = glm::vec3(1.0f);  // nor is ambient light
        m->specular = glm::vec3(1.0f); // nor highlights
        m->metallic = 1.0f;            // nor metal
        auto q = quadWith(m);
        q->colors.assign(q->positions.size(), glm::vec4(vertex));
        return q;
    };
    const glm::dvec3 expected = glm::dvec3(factor * texel.value() * vertex);
    for (const glm::vec3 sun : {glm::vec3(0, 0, -1), glm::vec3(0.6f, -0.2f, -0.3f)})
        for (const float ambient : {0.0f, 0.7f}) {
            Scene scene(sun, ambient);
            auto point = Light::create(LightType::Point);
            point->position = {0.5f, 0.5f, 1.0f};
            scene.root->addChild(point);
            const FloatImage img = render(scene, makeQuad());
            expectPixels(
                img, [&](glm::dvec3) { return expected; }, "unlit");
        }
    // Effects still apply at the colour hook: fog changes the unlit colour.
    Scene plain({0, 0, -1});
    const glm::dvec3 clear = pixel(render(plain, makeQuad()), 32, 32);
    Scene foggy({0, 0, -1});
    FogParameters fp = FogParameters::ground();
    fp.density = 0.5f;
    auto fog = FogNode::create(fp);
    fog->addChild(makeQuad());
    const glm::dvec3 fogged = pixel(render(foggy, fog), 32, 32);
    EXPECT_GT(glm::length(fogged - clear), 0.02) << "fog did not reach the unlit material";
}

TEST(MaterialExt, ClearcoatAddsTheGgxLayerOverTheBase) {
    struct Case {
        glm::vec3 base;
        float metallic, roughness, clearcoat, coatRoughness;
        glm::vec3 sun;
        glm::vec3 emissive;
    };
    const Case cases[] = {
        // Black base, light along the view: the added highlight is the F0 = 0.04 GGX lobe.
        {{0, 0, 0}, 0.0f, 1.0f, 1.0f, 0.5f, {0, 0, -1}, {0, 0, 0}},
        // Coloured base, half a coat, light from aside, emission darkened by the coat too.
        {{0.8f, 0.3f, 0.1f}, 0.0f, 0.7f, 0.5f, 0.3f, {-0.3f, -0.2f, -1.0f}, {0.05f, 0.1f, 0.0f}},
        // A metal under a rough coat.
        {{0.9f, 0.6f, 0.2f}, 1.0f, 0.4f, 1.0f, 0.6f, {0.2f, 0.1f, -1.0f}, {0, 0, 0}},
    };
    for (const Case& k : cases) {
        Scene off(k.sun), on(k.sun);
        auto m = metalRough(k.base, k.metallic, k.roughness);
        m->emissive = k.emissive;
        const FloatImage without = render(off, quadWith(m));
        auto c = metalRough(k.base, k.metallic, k.roughness);
        c->emissive = k.emissive;
        c->clearcoat = k.clearcoat;
        c->clearcoatRoughness = k.coatRoughness;
        const FloatImage with = render(on, quadWith(c));
        const glm::dvec3 L = on.towardsLight();
        auto base = [&](glm::dvec3 V) {
            return glm::dvec3(k.emissive) +
                   shade(k.base, k.metallic, k.roughness, {}, kUp, V, L, glm::dvec3(1));
        };
        expectPixels(without, base, "clearcoat off");
        expectPixels(
            with,
            [&](glm::dvec3 V) {
                return coat(base(V), k.clearcoat, k.coatRoughness, kUp, V, L, glm::dvec3(1));
            },
            "clearcoat on");
    }
    // At normal incidence on black, on minus off is the closed form: 0.04·D·Vis·π with D = 1/(π α²),
    // Vis = 1/4, less 0.04 of the base's own highlight.
    Scene scene({0, 0, -1});
    auto m = metalRough({0, 0, 0}, 0.0f, 1.0f);
    m->clearcoat = 1.0f;
    m->clearcoatRoughness = 0.5f;
    const glm::dvec3 got = pixel(render(scene, quadWith(m)), 32, 32);
    const double a2 = std::pow(0.5, 4.0), base = 0.04 / (4.0 * 1.0);
    EXPECT_NEAR(got.r, 0.04 / (4.0 * a2) + base * (1.0 - 0.04), 4e-3);
}

TEST(MaterialExt, ClearcoatAndSpecularShadeTheLightListAsTheUnrolledLoop) {
    // Beyond RendererOptions::maxUnrolledLights every light comes from the list (lights.glsl):
    // the coat and the specular extension's F0 and F90 must shade there as in the unrolled loop,
    // and both as the spec's layering says.
    const glm::vec3 sun(-0.3f, -0.2f, -1.0f);
    auto frameWith = [&](int maxUnrolled) {
        Scene scene(sun);
        auto c = metalRough({0.8f, 0.3f, 0.1f}, 0.0f, 0.7f);
        c->clearcoat = 0.5f;
        c->clearcoatRoughness = 0.3f;
        c->specularFactor = 0.5f;
        c->specularColorFactor = {1.0f, 0.5f, 0.25f};
        auto v = floatViewer();
        v->renderer().options().maxUnrolledLights = maxUnrolled;
        scene.root->addChild(quadWith(c));
        v->setSceneData(scene.root);
        v->frame();
        EXPECT_TRUE(v->renderer().takeGlErrors().empty());
        return v->renderer().readPixelsLinear();
    };
    const FloatImage unrolled = frameWith(8), listed = frameWith(0);
    const glm::dvec3 L = -glm::normalize(glm::dvec3(sun));
    const SpecularExt ext{0.5, {1.0, 0.5, 0.25}};
    auto expected = [&](glm::dvec3 V) {
        return coat(shade({0.8, 0.3, 0.1}, 0.0, 0.7, ext, kUp, V, L, glm::dvec3(1)), 0.5, 0.3, kUp, V, L,
                    glm::dvec3(1));
    };
    expectPixels(unrolled, expected, "unrolled loop");
    expectPixels(listed, expected, "light list");
}

TEST(MaterialExt, ClearcoatMapsScaleTheFactorsAndTiltTheLayer) {
    const Texel weight{{128, 0, 0, 255}, false}, rough{{0, 153, 0, 255}, false};
    const Texel normal{{218, 128, 218, 255}, false}; // tilted about 45° along the tangent
    const glm::dvec3 L(0, 0, 1);
    for (const bool tilted : {false, true}) {
        Scene scene({0, 0, -1});
        auto m = metalRough({0.2f, 0.2f, 0.2f}, 0.0f, 0.9f);
        m->clearcoat = 0.8f;
        m->clearcoatRoughness = 0.6f;
        m->clearcoatTexture = weight.texture();
        m->clearcoatRoughnessTexture = rough.texture();
        if (tilted) m->clearcoatNormalTexture = normal.texture();
        const FloatImage img = render(scene, quadWith(m));
        const double w = 0.8 * weight.value().r, r = 0.6 * rough.value().g;
        // The tilt's angle is what matters at normal incidence: cos θ = m.z / |m|.
        const glm::dvec3 n = glm::dvec3(normal.value()) * 2.0 - 1.0;
        const double cosT = n.z / glm::length(n);
        const glm::dvec3 Nc = tilted ? glm::dvec3(std::sqrt(1 - cosT * cosT), 0.0, cosT) : kUp;
        const glm::dvec3 V = viewAt(32, 32);
        const glm::dvec3 want = coat(shade({0.2, 0.2, 0.2}, 0.0, 0.9, {}, kUp, V, L, glm::dvec3(1)), w, r, Nc,
                                     V, L, glm::dvec3(1));
        const glm::dvec3 got = pixel(img, 32, 32);
        // The pixel's view is 0.03 m off the axis; a tilt's sign would move Nc·V by < 1e-3.
        EXPECT_NEAR(got.g, want.g, 3e-3 + 3e-3 * want.g) << (tilted ? "tilted" : "flat");
    }
}

TEST(MaterialExt, SpecularFactorAndColourSetTheDielectricFresnel) {
    const glm::vec3 base(0.5f, 0.4f, 0.3f);
    const Texel strength{{255, 255, 255, 128}, false}, tint{{255, 200, 60, 255}, true};
    struct Case {
        float factor;
        glm::vec3 colour;
        bool maps;
    };
    for (const Case k : {Case{0.0f, glm::vec3(1.0f), false}, Case{0.7f, {30.0f, 0.5f, 0.0f}, false},
                         Case{1.0f, {1.0f, 0.25f, 0.0f}, false}, Case{0.9f, {2.0f, 1.0f, 0.5f}, true}}) {
        SCOPED_TRACE(k.factor);
        Scene scene({-0.3f, -0.2f, -1.0f});
        auto m = metalRough(base, 0.0f, 0.5f);
        m->specularFactor = k.factor;
        m->specularColorFactor = k.colour;
        if (k.maps) {
            m->specularTexture = strength.texture();
            m->specularColorTexture = tint.texture();
        }
        const FloatImage img = render(scene, quadWith(m));
        SpecularExt ext{k.factor, glm::dvec3(k.colour)};
        if (k.maps) {
            ext.factor *= strength.value().a;
            ext.colour *= glm::dvec3(tint.value());
        }
        const glm::dvec3 L = scene.towardsLight();
        expectPixels(
            img, [&](glm::dvec3 V) { return shade(base, 0.0, 0.5, ext, kUp, V, L, glm::dvec3(1)); },
            "specular");
        if (k.factor == 0.0f) // no highlight at all: Lambert alone
            expectPixels(
                img, [&](glm::dvec3) { return glm::dvec3(base) * glm::dot(kUp, L); }, "specular 0");
    }
    // A metal ignores the extension.
    Scene a({-0.3f, -0.2f, -1.0f}), b({-0.3f, -0.2f, -1.0f});
    auto metal = metalRough(base, 1.0f, 0.5f);
    const glm::dvec3 plain = pixel(render(a, quadWith(metal)), 32, 32);
    auto tinted = metalRough(base, 1.0f, 0.5f);
    tinted->specularFactor = 0.0f;
    tinted->specularColorFactor = {0.0f, 1.0f, 5.0f};
    EXPECT_NEAR(glm::length(pixel(render(b, quadWith(tinted)), 32, 32) - plain), 0.0, 1e-5);
}

namespace {

// A glTF file with a 4×4 m quad (two triangles in glTF's XZ plane, so on the Z-up ground) with
// texture coordinates, a 1×1 PNG beside it as texture 0 and the given materials (JSON array).
std::filesystem::path gltfQuad(const std::string& name, const std::string& materials,
                               const std::string& extensionsUsed = "") {
    auto img = Image::create(1, 1, 4);
    img->pixels = {255, 255, 255, 255};
    writePng(std::filesystem::temp_directory_path() / "sgfx_matext.png", *img);
    const std::vector<float> data = {-2, 0, -2, 2, 0, -2, 2, 0, 2, -2, 0, -2, 2, 0, 2, -2, 0, 2, // POSITION
                                     0,  0, 1,  0, 1, 1,  0, 0, 1, 1,  0, 1};                    // TEXCOORD_0
    std::vector<unsigned char> bytes(data.size() * 4);
    std::memcpy(bytes.data(), data.data(), bytes.size());
    const std::string json =
        "{\"asset\":{\"version\":\"2.0\"}," + extensionsUsed +
        "\"buffers\":[{\"byteLength\":" + std::to_string(bytes.size()) +
        ",\"uri\":\"data:application/octet-stream;base64," + base64(bytes) +
        "\"}],\"bufferViews\":[{\"buffer\":0,\"byteLength\":72},{\"buffer\":0,\"byteOffset\":72,"
        "\"byteLength\":48}],"
        "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":6,\"type\":\"VEC3\","
        "\"min\":[-2,0,-2],\"max\":[2,0,2]},{\"bufferView\":1,\"componentType\":5126,\"count\":6,\"type\":"
        "\"VEC2\"}],"
        "\"images\":[{\"uri\":\"sgfx_matext.png\"}],\"textures\":[{\"source\":0}],"
        "\"scene\":0,\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{\"mesh\":0}],"
        "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0,\"TEXCOORD_0\":1},\"material\":0}]}],"
        "\"materials\":" +
        materials + "}";
    const auto path = std::filesystem::temp_directory_path() / name;
    std::ofstream(path) << json;
    return path;
}

class CollectMaterials : public NodeVisitor {
public:
    CollectMaterials()
        : NodeVisitor(Mode::AllChildren) {}
    void apply(Geometry& g) override {
        if (g.stateSet() && g.stateSet()->material.value)
            found.push_back(g.stateSet()->material.value->get());
    }
    std::vector<const Material*> found;
};

std::vector<const Material*> materialsOf(Node& root) {
    CollectMaterials c;
    root.accept(c);
    return c.found;
}

void expectLoadError(const std::string& file, const std::string& materials, const std::string& element) {
    try {
        (void)loadGltf(gltfQuad(file, materials));
        ADD_FAILURE() << "loaded " << materials;
    } catch (const LoadError& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find(file), std::string::npos) << what;
        EXPECT_NE(what.find(element), std::string::npos) << what;
    }
}

} // namespace

TEST(MaterialExt, EmissiveStrengthScalesEmission) {
    glm::dvec3 got[2];
    for (int i = 0; i < 2; ++i) {
        const std::string strength = i ? "3" : "1";
        const auto root = loadGltf(gltfQuad(
            "sgfx_matext_emissive" + strength + ".gltf",
            R"([{"doubleSided":true,"pbrMetallicRoughness":{"baseColorFactor":[0,0,0,1]},"emissiveFactor":[0.1,0.05,0.2],
"extensions":{"KHR_materials_emissive_strength":{"emissiveStrength":)" +
                strength + "}}}]",
            R"("extensionsUsed":["KHR_materials_emissive_strength"],)"));
        Scene scene({0, 0, -1});
        got[i] = pixel(render(scene, root), 32, 32);
    }
    // No light reaches a black dielectric's diffuse part, and what the highlight adds is the same
    // in both: the difference is (3 - 1) × the emissive factor.
    const glm::dvec3 diff = got[1] - got[0];
    EXPECT_NEAR(diff.r, 0.2, 2e-3);
    EXPECT_NEAR(diff.g, 0.1, 2e-3);
    EXPECT_NEAR(diff.b, 0.4, 2e-3);
}

TEST(MaterialExt, LoaderReadsEachExtension) {
    GltfStats st;
    const auto root = loadGltf(
        gltfQuad(
            "sgfx_matext_all.gltf",
            R"([{"pbrMetallicRoughness":{"baseColorFactor":[0.2,0.4,0.6,1]},
"extensions":{"KHR_materials_clearcoat":{"clearcoatFactor":0.75,"clearcoatRoughnessFactor":0.25,
  "clearcoatTexture":{"index":0},"clearcoatRoughnessTexture":{"index":0,"texCoord":0},
  "clearcoatNormalTexture":{"index":0,"scale":0.5,"extensions":{"KHR_texture_transform":{"scale":[2,3]}}}},
 "KHR_materials_specular":{"specularFactor":0.3,"specularColorFactor":[2,0.5,0],
  "specularTexture":{"index":0},"specularColorTexture":{"index":0}}}}])",
            R"("extensionsUsed":["KHR_materials_clearcoat","KHR_materials_specular","KHR_texture_transform"],)"),
        {}, &st);
    EXPECT_TRUE(st.warnings.empty()) << st.warnings.front();
    const auto mats = materialsOf(*root);
    ASSERT_EQ(mats.size(), 1u);
    const Material& m = *mats[0];
    EXPECT_EQ(m.model, ShadingModel::MetallicRoughness);
    EXPECT_FLOAT_EQ(m.clearcoat, 0.75f);
    EXPECT_FLOAT_EQ(m.clearcoatRoughness, 0.25f);
    EXPECT_FLOAT_EQ(m.clearcoatNormalScale, 0.5f);
    ASSERT_TRUE(m.clearcoatTexture && m.clearcoatRoughnessTexture && m.clearcoatNormalTexture);
    EXPECT_FALSE(m.clearcoatTexture->srgb);
    EXPECT_EQ(m.mapping(MaterialMap::ClearcoatNormal).scale, glm::vec2(2.0f, 3.0f));
    EXPECT_TRUE(m.mapping(MaterialMap::Clearcoat).isIdentity());
    EXPECT_FLOAT_EQ(m.specularFactor, 0.3f);
    EXPECT_EQ(m.specularColorFactor, glm::vec3(2.0f, 0.5f, 0.0f));
    ASSERT_TRUE(m.specularTexture && m.specularColorTexture);
    EXPECT_FALSE(m.specularTexture->srgb);
    EXPECT_TRUE(m.specularColorTexture->srgb); // RGB, encoded in sRGB (the spec)

    // The loaded graphs stay alive while their materials are read (materialsOf returns pointers).
    const NodePtr unlitRoot = loadGltf(gltfQuad(
        "sgfx_matext_unlit.gltf",
        R"([{"pbrMetallicRoughness":{"baseColorFactor":[1,0.5,0.25,1]},"extensions":{"KHR_materials_unlit":{}}}])",
        R"("extensionsUsed":["KHR_materials_unlit"],"extensionsRequired":["KHR_materials_unlit"],)"));
    const auto unlit = materialsOf(*unlitRoot);
    ASSERT_EQ(unlit.size(), 1u);
    EXPECT_EQ(unlit[0]->model, ShadingModel::Unlit);
    EXPECT_EQ(unlit[0]->diffuse, glm::vec4(1.0f, 0.5f, 0.25f, 1.0f));

    // Defaults when the extension objects are empty: no coat, the core's specular.
    const NodePtr plainRoot =
        loadGltf(gltfQuad("sgfx_matext_defaults.gltf",
                          R"([{"extensions":{"KHR_materials_clearcoat":{},"KHR_materials_specular":{}}}])"));
    const auto plain = materialsOf(*plainRoot);
    ASSERT_EQ(plain.size(), 1u);
    EXPECT_EQ(plain[0]->clearcoat, 0.0f);
    EXPECT_EQ(plain[0]->clearcoatRoughness, 0.0f);
    EXPECT_EQ(plain[0]->specularFactor, 1.0f);
    EXPECT_EQ(plain[0]->specularColorFactor, glm::vec3(1.0f));
}

TEST(MaterialExt, LoaderNamesTheFileAndElementOfBadValues) {
    const std::string cc = "materials[0].extensions.KHR_materials_clearcoat.";
    const std::string sp = "materials[0].extensions.KHR_materials_specular.";
    expectLoadError("sgfx_matext_bad1.gltf",
                    R"([{"extensions":{"KHR_materials_clearcoat":{"clearcoatFactor":2}}}])",
                    cc + "clearcoatFactor");
    expectLoadError("sgfx_matext_bad2.gltf",
                    R"([{"extensions":{"KHR_materials_clearcoat":{"clearcoatRoughnessFactor":-0.5}}}])",
                    cc + "clearcoatRoughnessFactor");
    expectLoadError("sgfx_matext_bad3.gltf",
                    R"([{"extensions":{"KHR_materials_clearcoat":{"clearcoatFactor":"shiny"}}}])",
                    cc + "clearcoatFactor");
    expectLoadError("sgfx_matext_bad4.gltf",
                    R"([{"extensions":{"KHR_materials_clearcoat":{"clearcoatTexture":{"index":7}}}}])",
                    cc + "clearcoatTexture");
    expectLoadError("sgfx_matext_bad5.gltf",
                    R"([{"extensions":{"KHR_materials_clearcoat":{"clearcoatNormalTexture":{"scale":1}}}}])",
                    cc + "clearcoatNormalTexture.index");
    expectLoadError("sgfx_matext_bad6.gltf",
                    R"([{"extensions":{"KHR_materials_specular":{"specularFactor":1.5}}}])",
                    sp + "specularFactor");
    expectLoadError("sgfx_matext_bad7.gltf",
                    R"([{"extensions":{"KHR_materials_specular":{"specularColorFactor":[1,-1,1]}}}])",
                    sp + "specularColorFactor");
    expectLoadError("sgfx_matext_bad8.gltf",
                    R"([{"extensions":{"KHR_materials_specular":{"specularColorFactor":[1,1]}}}])",
                    sp + "specularColorFactor");
    // The material's own checks name the field too.
    auto m = Material::create();
    m->clearcoat = 1.5f;
    EXPECT_THROW(m->validate(), std::invalid_argument);
    m->clearcoat = 0.5f;
    m->specularColorFactor = glm::vec3(std::nanf(""));
    try {
        m->validate();
        ADD_FAILURE();
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("specularColorFactor"), std::string::npos) << e.what();
    }
}

TEST(MaterialExt, LoaderReadsTransmissionVolumeAndIor) {
    GltfStats st;
    const NodePtr root = loadGltf(
        gltfQuad(
            "sgfx_matext_transmission.gltf",
            R"([{"extensions":{"KHR_materials_transmission":{"transmissionFactor":0.8,
  "transmissionTexture":{"index":0}},
 "KHR_materials_volume":{"thicknessFactor":0.25,"thicknessTexture":{"index":0,"texCoord":0},
  "attenuationDistance":2.5,"attenuationColor":[0.9,0.5,0]},
 "KHR_materials_ior":{"ior":1.33}}}])",
            R"("extensionsUsed":["KHR_materials_transmission","KHR_materials_volume","KHR_materials_ior"],)"),
        {}, &st);
    EXPECT_TRUE(st.warnings.empty()) << st.warnings.front();
    const auto mats = materialsOf(*root);
    ASSERT_EQ(mats.size(), 1u); // the quad uses materials[0]
    const Material& m = *mats[0];
    EXPECT_FLOAT_EQ(m.transmission, 0.8f);
    EXPECT_FLOAT_EQ(m.thickness, 0.25f);
    EXPECT_FLOAT_EQ(m.attenuationDistance, 2.5f);
    EXPECT_FLOAT_EQ(m.ior, 1.33f);
    EXPECT_FLOAT_EQ(m.attenuationColor.r, 0.9f);
    EXPECT_GT(m.attenuationColor.b, 0.0f); // 0 absorbs everything: the smallest float stands in
    EXPECT_LT(m.attenuationColor.b, 1e-30f);
    ASSERT_TRUE(m.transmissionTexture && m.thicknessTexture);
    EXPECT_FALSE(m.transmissionTexture->srgb);
    EXPECT_FALSE(m.thicknessTexture->srgb);
    EXPECT_NO_THROW(m.validate());
    // The extensions' defaults (empty objects), and ior 0, which KHR_materials_ior allows.
    for (int i : {1, 2}) {
        const NodePtr other = loadGltf(gltfQuad(
            "sgfx_matext_transmission" + std::to_string(i) + ".gltf",
            i == 1
                ? R"([{"extensions":{"KHR_materials_transmission":{},"KHR_materials_volume":{},"KHR_materials_ior":{}}}])"
                : R"([{"extensions":{"KHR_materials_ior":{"ior":0}}}])"));
        const auto d = materialsOf(*other);
        ASSERT_EQ(d.size(), 1u);
        EXPECT_EQ(d[0]->transmission, 0.0f);
        EXPECT_EQ(d[0]->thickness, 0.0f);
        EXPECT_TRUE(std::isinf(d[0]->attenuationDistance));
        EXPECT_EQ(d[0]->attenuationColor, glm::vec3(1.0f));
        EXPECT_EQ(d[0]->ior, i == 1 ? 1.5f : 0.0f);
    }
}

TEST(MaterialExt, LoaderNamesBadTransmissionVolumeAndIorValues) {
    const std::string p = "materials[0].extensions.";
    expectLoadError("sgfx_matext_badt1.gltf",
                    R"([{"extensions":{"KHR_materials_transmission":{"transmissionFactor":1.5}}}])",
                    p + "KHR_materials_transmission.transmissionFactor");
    expectLoadError("sgfx_matext_badt2.gltf", R"([{"extensions":{"KHR_materials_ior":{"ior":0.5}}}])",
                    p + "KHR_materials_ior.ior");
    expectLoadError("sgfx_matext_badt2b.gltf", R"([{"extensions":{"KHR_materials_ior":{"ior":1e39}}}])",
                    p + "KHR_materials_ior.ior"); // finite as a double, infinite as a float
    expectLoadError("sgfx_matext_badt3.gltf",
                    R"([{"extensions":{"KHR_materials_volume":{"thicknessFactor":-1}}}])",
                    p + "KHR_materials_volume.thicknessFactor");
    expectLoadError("sgfx_matext_badt4.gltf",
                    R"([{"extensions":{"KHR_materials_volume":{"attenuationDistance":0}}}])",
                    p + "KHR_materials_volume.attenuationDistance");
    expectLoadError("sgfx_matext_badt5.gltf",
                    R"([{"extensions":{"KHR_materials_volume":{"attenuationColor":[1,2,1]}}}])",
                    p + "KHR_materials_volume.attenuationColor");
    expectLoadError("sgfx_matext_badt6.gltf",
                    R"([{"extensions":{"KHR_materials_transmission":{"transmissionTexture":{"index":9}}}}])",
                    p + "KHR_materials_transmission.transmissionTexture");
    for (const auto& [field, set] : std::vector<std::pair<std::string, std::function<void(Material&)>>>{
             {"transmission", [](Material& x) { x.transmission = -0.1f; }},
             {"ior", [](Material& x) { x.ior = 0.9f; }},
             {"thickness", [](Material& x) { x.thickness = std::nanf(""); }},
             {"attenuationDistance", [](Material& x) { x.attenuationDistance = 0.0f; }},
             {"attenuationColor", [](Material& x) { x.attenuationColor = glm::vec3(0.0f); }}}) {
        Material bad;
        set(bad);
        try {
            bad.validate();
            ADD_FAILURE() << field;
        } catch (const std::invalid_argument& e) {
            EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
        }
    }
}

TEST(MaterialExt, UnknownOptionalExtensionWarnsOncePerFile) {
    GltfStats st;
    const std::string sheen = R"({"extensions":{"KHR_materials_sheen":{"sheenColorFactor":[1,0,0]}}})";
    (void)loadGltf(gltfQuad("sgfx_matext_sheen.gltf", "[" + sheen + "," + sheen + "," + sheen + "]",
                            R"("extensionsUsed":["KHR_materials_sheen"],)"),
                   {}, &st);
    std::size_t mentions = 0;
    for (const std::string& w : st.warnings)
        mentions += w.find("KHR_materials_sheen") != std::string::npos;
    EXPECT_EQ(mentions, 1u);
}

TEST(MaterialExt, SharedSampleModelsLoadTheirDeclaredMaterials) {
    const auto dir = std::filesystem::path(SGFX_SOURCE_DIR) / ".." / "shared" / "assets" / "gltf";
    auto model = [&](const std::string& name) { return dir / name / "glTF" / (name + ".gltf"); };
    if (!optionalPrerequisite(std::filesystem::exists(model("UnlitTest")), "shared glTF set A2")) return;
    for (const std::string name :
         {"UnlitTest", "SpecularTest", "ClearCoatCarPaint", "TransmissionRoughnessTest"}) {
        SCOPED_TRACE(name);
        nlohmann::json doc;
        std::ifstream(model(name)) >> doc;
        const auto root = loadGltf(model(name));
        const auto loaded = materialsOf(*root);
        ASSERT_FALSE(loaded.empty());
        // Every material the file declares with an extension, and some mesh uses, is loaded with it.
        std::set<std::size_t> used;
        for (const auto& mesh : doc["meshes"])
            for (const auto& p : mesh["primitives"])
                if (p.contains("material")) used.insert(p["material"].get<std::size_t>());
        std::size_t checked = 0;
        for (const std::size_t i : used) {
            const auto& jm = doc["materials"][i];
            const auto& ext = jm.value("extensions", nlohmann::json::object());
            const auto pbr = jm.value("pbrMetallicRoughness", nlohmann::json::object());
            const auto bc = pbr.value("baseColorFactor", std::vector<float>{1, 1, 1, 1});
            auto matches = [&](const Material& m) {
                if (m.diffuse != glm::vec4(bc[0], bc[1], bc[2], bc[3])) return false;
                if (ext.contains("KHR_materials_unlit")) return m.model == ShadingModel::Unlit;
                if (m.model != ShadingModel::MetallicRoughness) return false;
                if (ext.contains("KHR_materials_clearcoat")) {
                    const auto& c = ext["KHR_materials_clearcoat"];
                    if (m.clearcoat != c.value("clearcoatFactor", 0.0f) ||
                        m.clearcoatRoughness != c.value("clearcoatRoughnessFactor", 0.0f))
                        return false;
                }
                if (ext.contains("KHR_materials_specular")) {
                    const auto& s = ext["KHR_materials_specular"];
                    const auto col = s.value("specularColorFactor", std::vector<float>{1, 1, 1});
                    if (m.specularFactor != s.value("specularFactor", 1.0f) ||
                        m.specularColorFactor != glm::vec3(col[0], col[1], col[2]) ||
                        bool(m.specularTexture) != s.contains("specularTexture") ||
                        bool(m.specularColorTexture) != s.contains("specularColorTexture"))
                        return false;
                }
                if (m.transmission != ext.value("KHR_materials_transmission", nlohmann::json::object())
                                          .value("transmissionFactor", 0.0f) ||
                    m.ior != ext.value("KHR_materials_ior", nlohmann::json::object()).value("ior", 1.5f) ||
                    m.thickness != ext.value("KHR_materials_volume", nlohmann::json::object())
                                       .value("thicknessFactor", 0.0f))
                    return false;
                return true;
            };
            if (ext.empty()) continue;
            ++checked;
            EXPECT_TRUE(
                std::any_of(loaded.begin(), loaded.end(), [&](const Material* m) { return matches(*m); }))
                << "materials[" << i << "] " << jm.dump();
        }
        EXPECT_GT(checked, 0u);
        // And each draws without a GL error (clearcoat under a transformed normal map, textured specular).
        Scene scene({-0.3f, -0.2f, -1.0f}, 0.2f);
        auto v = floatViewer();
        const BoundingSphere b = root->bound();
        v->camera()->setLookAt(b.center + glm::vec3(0.0f, -3.0f, 1.0f) * b.radius, b.center, {0, 0, 1});
        v->camera()->setPerspective(50.0f, 0.1f * b.radius, 10.0f * b.radius);
        scene.root->addChild(root);
        v->setSceneData(scene.root);
        ASSERT_NO_THROW(v->frame());
        EXPECT_TRUE(v->renderer().takeGlErrors().empty());
    }
}

TEST(MaterialExt, ExtensionVariantsCompileWithEveryLightingPath) {
    // Per-vertex lighting draws clearcoat without the layer (documented) but must compile; G-buffer
    // and depth passes (fog) drop the extension bits.
    for (const bool perVertex : {false, true})
        for (const ShadingModel model : {ShadingModel::Unlit, ShadingModel::MetallicRoughness}) {
            auto v = floatViewer();
            if (perVertex) v->renderer().options().lighting = RendererOptions::Lighting::PerVertex;
            Scene scene({-0.3f, 0.2f, -1.0f}, 0.2f);
            auto m = metalRough({0.5f, 0.5f, 0.5f}, 0.2f, 0.5f);
            m->model = model;
            m->clearcoat = 0.5f;
            m->specularFactor = 0.5f;
            m->transmission = 0.5f;
            m->thickness = 0.1f;
            m->clearcoatNormalTexture = m->specularColorTexture = m->thicknessTexture =
                Texel{{128, 128, 255, 255}, false}.texture();
            m->alphaCutoff = 0.3f;
            auto fog = FogNode::create(FogParameters::ground());
            fog->addChild(quadWith(m));
            scene.root->addChild(fog);
            v->setSceneData(scene.root);
            ASSERT_NO_THROW(v->frame());
            EXPECT_TRUE(v->renderer().takeGlErrors().empty());
            EXPECT_GT(pixel(v->renderer().readPixelsLinear(), 32, 32).r, 0.01);
        }
}

// The built-in material beyond Blinn-Phong: the metallic-roughness model against a CPU copy of
// glTF's BRDF (spec appendix B), its maps, per-map texture coordinates and transforms, instanced
// geometry, and the normals and tangents MeshTools makes. Linear float targets, 64×64.
#include "TestUtil.h"

#include <sgfx/Geometry.h>
#include <sgfx/Group.h>
#include <sgfx/MeshTools.h>
#include <sgfx/Shapes.h>
#include <sgfx/Visitors.h>
#include <sgfx/nodes/ao/AmbientOcclusionNode.h>
#include <sgfx/nodes/fog/FogNode.h>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

using namespace sgfx;
using namespace sgfx::test;

namespace {

constexpr int kSize = 64;
constexpr float kHalf = 2.0f;

std::unique_ptr<Viewer> floatOrthoViewer() {
    auto v = orthoTopViewer(kSize, kHalf);
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

std::shared_ptr<Node> quadWith(std::shared_ptr<Material> m, float size = 4.0f) {
    auto q = shapes::quad(size, size);
    q->getOrCreateStateSet().material.set(std::move(m));
    return q;
}

std::shared_ptr<Texture> texture1x1(glm::dvec4 linear, bool srgb) {
    auto img = Image::create(1, 1, 4);
    for (int c = 0; c < 4; ++c)
        img->pixels[std::size_t(c)] = std::uint8_t(
            std::lround(std::clamp(c < 3 && srgb ? srgbEncode(linear[c]) : linear[c], 0.0, 1.0) * 255.0));
    auto t = Texture::create(img, srgb);
    t->minFilter = t->magFilter = Filter::Nearest;
    return t;
}

// glTF 2.0 appendix B, in double precision, with lights given as irradiance over π (so a white
// Lambert surface facing a light shows its colour, as the renderer documents).
glm::dvec3 gltfBrdf(glm::dvec3 base, double metallic, double roughness, glm::dvec3 N, glm::dvec3 V,
                    glm::dvec3 L, glm::dvec3 light, glm::dvec3 ambientLight) {
    const glm::dvec3 cdiff = glm::mix(base, glm::dvec3(0.0), metallic);
    const glm::dvec3 f0 = glm::mix(glm::dvec3(0.04), base, metallic);
    const double alpha = std::pow(std::max(roughness, 0.045), 2.0), a2 = alpha * alpha;
    const glm::dvec3 H = glm::normalize(L + V);
    const double NdotL = std::max(glm::dot(N, L), 0.0), NdotV = std::max(glm::dot(N, V), 1e-4);
    const double NdotH = std::max(glm::dot(N, H), 0.0), VdotH = std::max(glm::dot(V, H), 0.0);
    const glm::dvec3 F = f0 + (1.0 - f0) * std::pow(1.0 - VdotH, 5.0);
    const double d = NdotH * NdotH * (a2 - 1.0) + 1.0;
    const double D = a2 / (glm::pi<double>() * d * d);
    const double vis = 0.5 / (NdotL * std::sqrt(NdotV * NdotV * (1 - a2) + a2) +
                              NdotV * std::sqrt(NdotL * NdotL * (1 - a2) + a2));
    const glm::dvec3 diffuse = (1.0 - F) * cdiff;
    const glm::dvec3 specular = glm::pi<double>() * F * D * vis;
    return ambientLight * (cdiff + f0) + light * NdotL * (diffuse + specular);
}

struct Lit {
    std::shared_ptr<Group> root = Group::create();
    std::shared_ptr<Light> sun = Light::create(LightType::Directional);
    Lit(glm::vec3 direction, glm::vec3 color, float ambient) {
        sun->direction = glm::normalize(direction);
        sun->color = color;
        root->addChild(sun);
        auto amb = Light::create(LightType::Ambient);
        amb->color = glm::vec3(ambient);
        root->addChild(amb);
    }
};

} // namespace

TEST(Material, MetallicRoughnessMatchesTheGltfBrdf) {
    const glm::dvec3 base(0.8, 0.5, 0.3);
    struct Case {
        float metallic, roughness;
    };
    for (const Case k :
         {Case{0.0f, 0.5f}, Case{1.0f, 0.3f}, Case{0.5f, 0.8f}, Case{0.0f, 1.0f}, Case{1.0f, 0.1f}}) {
        auto v = floatOrthoViewer();
        Lit scene({-0.4f, -0.3f, -1.0f}, {0.9f, 0.85f, 0.8f}, 0.1f);
        auto m = Material::create();
        m->model = ShadingModel::MetallicRoughness;
        m->diffuse = glm::vec4(glm::vec3(base), 1.0f);
        m->metallic = k.metallic;
        m->roughness = k.roughness;
        m->emissive = {0.02f, 0.0f, 0.01f};
        scene.root->addChild(quadWith(m));
        v->setSceneData(scene.root);
        v->frame();
        const FloatImage img = v->renderer().readPixelsLinear();
        const glm::dvec3 L = -glm::normalize(glm::dvec3(scene.sun->direction)), eye(0, 0, 10);
        double spread = 0.0;
        for (auto [px, py] : {std::pair{5, 5}, {32, 32}, {60, 10}, {20, 50}, {45, 45}, {40, 40}}) {
            const glm::dvec3 P = worldOfPixel(px, py);
            const glm::dvec3 expected =
                glm::dvec3(m->emissive) + gltfBrdf(base, k.metallic, k.roughness, {0, 0, 1},
                                                   glm::normalize(eye - P), L, glm::dvec3(scene.sun->color),
                                                   glm::dvec3(0.1));
            const glm::dvec3 got = pixel(img, px, py);
            for (int c = 0; c < 3; ++c)
                EXPECT_NEAR(got[c], expected[c], 2e-3 + 2e-3 * expected[c])
                    << "metallic " << k.metallic << " roughness " << k.roughness << " pixel " << px << ","
                    << py;
            spread = std::max(
                spread, std::abs(expected.r - gltfBrdf(base, k.metallic, k.roughness, {0, 0, 1}, {0, 0, 1}, L,
                                                       glm::dvec3(scene.sun->color), glm::dvec3(0.1))
                                                  .r));
        }
        // The view direction matters (specular): the test would see a wrong V.
        if (k.roughness < 0.5f) {
            EXPECT_GT(spread, 0.01);
        }
    }
}

TEST(Material, MetallicRoughnessMapsScaleTheFactors) {
    // Texture G scales roughness, B metallic; occlusion darkens ambient only; emissive map
    // multiplies emissive. Each render equals the factor-only material with the product.
    auto render = [](const std::shared_ptr<Material>& m, float sunScale) {
        auto v = floatOrthoViewer();
        Lit scene({-0.2f, -0.5f, -1.0f}, glm::vec3(0.8f * sunScale), 0.3f);
        scene.root->addChild(quadWith(m));
        v->setSceneData(scene.root);
        v->frame();
        return pixel(v->renderer().readPixelsLinear(), 32, 32);
    };
    auto make = [] {
        auto m = Material::create();
        m->model = ShadingModel::MetallicRoughness;
        m->diffuse = {0.7f, 0.6f, 0.5f, 1.0f};
        return m;
    };
    auto mapped = make();
    mapped->metallic = 1.0f;
    mapped->roughness = 0.9f;
    mapped->metallicRoughnessTexture = texture1x1({0.0, 0.6, 0.4, 1.0}, false);
    auto plain = make();
    plain->metallic = float(std::lround(0.4 * 255) / 255.0);
    plain->roughness = 0.9f * float(std::lround(0.6 * 255) / 255.0);
    const glm::dvec3 a = render(mapped, 1.0f), b = render(plain, 1.0f);
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(a[c], b[c], 1e-4);

    // Occlusion: ambient-only scene (no sun) scales by 1 + strength·(ao − 1).
    auto occluded = make();
    occluded->occlusionTexture = texture1x1({0.5, 0, 0, 1}, false);
    occluded->occlusionStrength = 0.6f;
    const double ao = std::lround(0.5 * 255) / 255.0;
    const glm::dvec3 dark = render(occluded, 0.0f), bright = render(make(), 0.0f);
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(dark[c], bright[c] * (1.0 + 0.6 * (ao - 1.0)), 1e-4);
    // ... and leaves direct light alone.
    const glm::dvec3 litDark = render(occluded, 1.0f), litBright = render(make(), 1.0f);
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(litBright[c] - litDark[c], bright[c] - dark[c], 1e-4)
            << litBright[c] << " " << litDark[c] << " " << bright[c] << " " << dark[c];

    // Emissive texture (sRGB) times the factor.
    auto glowing = make();
    glowing->emissive = {0.5f, 1.0f, 2.0f};
    glowing->emissiveTexture = texture1x1({0.2, 0.4, 0.1, 1}, true);
    const glm::dvec3 glow = render(glowing, 1.0f) - litBright;
    const glm::dvec3 expected(0.5 * 0.2, 1.0 * 0.4, 2.0 * 0.1);
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(glow[c], expected[c], 0.01 * expected[c] + 1e-3);
}

TEST(Material, TextureTransformAndSecondSetPickTheTexel) {
    // A 2×2 texture (nearest): red, green / blue, white. The quad's uv runs (0,0) top-left to
    // (1,1) bottom-right. With offset, rotation and scale the texel at each pixel is the one the
    // CPU finds at T·R·S·uv (repeat wrap).
    auto img = Image::create(2, 2, 4);
    img->pixels = {255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 255, 255, 255, 255};
    const glm::dvec3 texel[4] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}};
    auto tex = Texture::create(img, false);
    tex->minFilter = tex->magFilter = Filter::Nearest;
    struct Case {
        TextureMapping mapping;
        bool secondSet;
    };
    TextureMapping shifted;
    shifted.offset = {0.5f, 0.0f};
    TextureMapping turned;
    turned.rotation = 0.3f;
    turned.scale = {1.5f, 0.75f};
    turned.offset = {0.1f, -0.2f};
    TextureMapping second = turned;
    second.texCoord = 1;
    for (const Case k :
         {Case{TextureMapping{}, false}, Case{shifted, false}, Case{turned, false}, Case{second, true}}) {
        auto v = floatOrthoViewer();
        auto m = Material::create();
        m->ambient = glm::vec3(1.0f); // colour = ambient light × ambient × texel
        m->diffuse = glm::vec4(0, 0, 0, 1);
        m->baseColorTexture = tex;
        m->mapping(MaterialMap::BaseColor) = k.mapping;
        auto q = shapes::quad(4.0f, 4.0f);
        if (k.secondSet)
            for (const glm::vec2 uv : q->texcoords)
                q->texcoords1.push_back({1.0f - uv.x, uv.y}); // mirrored in u
        q->getOrCreateStateSet().material.set(m);
        auto root = Group::create();
        auto amb = Light::create(LightType::Ambient);
        amb->color = glm::vec3(1.0f);
        root->addChild(amb);
        root->addChild(q);
        v->setSceneData(root);
        v->frame();
        const FloatImage out = v->renderer().readPixelsLinear();
        const glm::mat3 t = k.mapping.matrix();
        int checked = 0;
        for (int py = 2; py < kSize; py += 5)
            for (int px = 2; px < kSize; px += 5) {
                glm::dvec2 uv((px + 0.5) / kSize, (py + 0.5) / kSize);
                if (k.secondSet) uv.x = 1.0 - uv.x;
                const glm::dvec3 w = glm::dmat3(t) * glm::dvec3(uv, 1.0);
                const double fx = (w.x - std::floor(w.x)) * 2.0, fy = (w.y - std::floor(w.y)) * 2.0;
                // Skip pixels within a hair of a texel edge, where rounding may go either way.
                if (std::abs(fx - std::round(fx)) < 0.05 || std::abs(fy - std::round(fy)) < 0.05) continue;
                const glm::dvec3 expected = texel[int(fy) * 2 + int(fx)];
                const glm::dvec3 got = pixel(out, px, py);
                ++checked;
                for (int c = 0; c < 3; ++c)
                    ASSERT_NEAR(got[c], expected[c], 1e-3) << "pixel " << px << "," << py;
            }
        EXPECT_GT(checked, 100);
    }
}

TEST(Material, NormalMapFrameMatchesSuppliedAndComputedTangents) {
    // A normal map tilted towards +v's opposite (texture "up", n_t = (0, 0.6, 0.8)) must tilt the
    // +Z quad's normal towards +Y, as glTF (bitangent up the image) asks, whether the tangents
    // come from the shape, from computeTangents, or from screen-space derivatives (none).
    auto img = Image::create(1, 1, 3);
    const glm::dvec3 nt(0.0, 0.6, 0.8);
    for (int c = 0; c < 3; ++c)
        img->pixels[std::size_t(c)] = std::uint8_t(std::lround((nt[c] * 0.5 + 0.5) * 255.0));
    auto normalMap = Texture::create(img, false);
    glm::dvec3 decoded;
    for (int c = 0; c < 3; ++c)
        decoded[c] = img->pixels[std::size_t(c)] / 255.0 * 2.0 - 1.0;
    const glm::dvec3 N = glm::normalize(decoded); // world (x, y, z) = tangent-space (t, b, n) here
    const glm::dvec3 L = glm::normalize(glm::dvec3(0, 1, 1));
    for (int variant = 0; variant < 3; ++variant) {
        auto v = floatOrthoViewer();
        Lit scene({0, -1, -1}, glm::vec3(1.0f), 0.0f);
        auto m = Material::create();
        m->diffuse = {0.8f, 0.8f, 0.8f, 1};
        m->normalTexture = normalMap;
        auto q = shapes::quad(4.0f, 4.0f);
        const auto supplied = q->tangents;
        if (variant > 0) q->tangents.clear();
        if (variant == 2) {
            computeTangents(*q);
            ASSERT_EQ(q->tangents.size(), supplied.size());
            for (std::size_t i = 0; i < supplied.size(); ++i)
                EXPECT_NEAR(glm::distance(q->tangents[i], supplied[i]), 0.0f, 1e-5f) << i;
        }
        q->getOrCreateStateSet().material.set(m);
        scene.root->addChild(q);
        v->setSceneData(scene.root);
        v->frame();
        const double expected = 0.8 * std::max(glm::dot(N, L), 0.0);
        EXPECT_NEAR(pixel(v->renderer().readPixelsLinear(), 32, 32).r, expected, 2e-3)
            << "variant " << variant;
        // A flipped bitangent would give 0.8·N·L with N = (0, −0.6, 0.8): far from it.
        EXPECT_GT(std::abs(expected - 0.8 * glm::dot(glm::normalize(glm::dvec3(0, -0.6, 0.8)), L)), 0.3);
    }
}

TEST(Material, InstancedGeometryDrawsEveryInstanceInOneCall) {
    auto v = floatOrthoViewer();
    auto q = shapes::quad(0.5f, 0.5f);
    const glm::vec3 offsets[3] = {{-1, -1, 0}, {1, 0.5f, 0}, {0, 1.2f, 0}};
    for (glm::vec3 o : offsets)
        q->instances.push_back(glm::scale(glm::translate(glm::mat4(1.0f), o), glm::vec3(1.0f, 1.5f, 1.0f)));
    auto m = Material::create();
    m->ambient = glm::vec3(0);
    m->diffuse = {0, 0, 0, 1};
    m->emissive = {0.25f, 0.5f, 0.75f};
    q->getOrCreateStateSet().material.set(m);
    auto root = Group::create();
    root->addChild(q);
    v->setSceneData(root);
    v->frame();
    EXPECT_EQ(v->renderer().stats().drawCalls, 1u);
    EXPECT_EQ(v->renderer().stats().triangles, 6u);
    EXPECT_EQ(q->triangleCount(), 6u);
    const FloatImage img = v->renderer().readPixelsLinear();
    auto pixelOf = [](glm::vec3 w) {
        return std::pair{int((w.x + kHalf) / (2 * kHalf) * kSize), int((kHalf - w.y) / (2 * kHalf) * kSize)};
    };
    for (glm::vec3 o : offsets) {
        const auto [px, py] = pixelOf(o);
        EXPECT_NEAR(pixel(img, px, py).g, 0.5, 1e-4) << o.x << "," << o.y;
        // Scaled 1.5× in y: 0.3 m above the centre is inside, 0.3 m right is outside.
        EXPECT_NEAR(
            pixel(img, pixelOf(o + glm::vec3(0, 0.3f, 0)).first, pixelOf(o + glm::vec3(0, 0.3f, 0)).second).g,
            0.5, 1e-4);
        EXPECT_NEAR(
            pixel(img, pixelOf(o + glm::vec3(0.3f, 0, 0)).first, pixelOf(o + glm::vec3(0.3f, 0, 0)).second).g,
            0.0, 1e-4);
    }
    EXPECT_NEAR(pixel(img, 32, 32).g, 0.0, 1e-4); // nothing at the origin
    // Bounds cover every instance.
    ComputeBoundsVisitor bounds;
    root->accept(bounds);
    EXPECT_NEAR(bounds.min.x, -1.25f, 1e-5f);
    EXPECT_NEAR(bounds.max.y, 1.2f + 0.375f, 1e-5f);
    const BoundingSphere s = q->bound();
    for (glm::vec3 o : offsets)
        EXPECT_LE(glm::distance(o, s.center), s.radius);
    // A NaN instance is refused with its index.
    q->instances.push_back(glm::mat4(std::nanf("")));
    try {
        q->validate();
        ADD_FAILURE() << "no error";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("instances[3]"), std::string::npos) << e.what();
    }
}

TEST(MeshTools, CreaseAngleKeepsHardEdgesAndSmoothsSoftOnes) {
    auto box = shapes::box({2, 2, 2});
    box->normals.clear();
    box->tangents.clear();
    computeNormals(*box, 0.0f);
    EXPECT_EQ(box->positions.size(), 24u); // flat: 4 corners per face
    EXPECT_EQ(box->triangleCount(), 12u);
    computeNormals(*box, glm::radians(60.0f));
    EXPECT_EQ(box->positions.size(), 24u); // 90° edges stay hard
    for (std::size_t i = 0; i < box->positions.size(); ++i) {
        const glm::vec3 n = box->normals[i];
        EXPECT_NEAR(std::abs(n.x) + std::abs(n.y) + std::abs(n.z), 1.0f, 1e-5f); // axis-aligned
    }
    computeNormals(*box, glm::radians(100.0f));
    // Every corner smooth: corners whose texcoords differ stay apart but agree; the rest weld.
    EXPECT_LE(box->positions.size(), 24u);
    EXPECT_GE(box->positions.size(), 8u);
    for (std::size_t i = 0; i < box->positions.size(); ++i)
        EXPECT_NEAR(glm::dot(box->normals[i], glm::normalize(box->positions[i])), 1.0f, 1e-5f);
    auto sphere = shapes::sphere(1.0f, 32, 16);
    const std::size_t triangles = sphere->triangleCount();
    sphere->normals.clear();
    computeNormals(*sphere, glm::radians(30.0f));
    EXPECT_EQ(sphere->triangleCount(), triangles);
    for (std::size_t i = 0; i < sphere->positions.size(); ++i)
        EXPECT_GT(glm::dot(sphere->normals[i], glm::normalize(sphere->positions[i])), 0.985f) << i;
    EXPECT_THROW(computeNormals(*sphere, -1.0f), std::invalid_argument);
    auto points = Geometry::create();
    points->positions = {{0, 0, 0}};
    points->mode = PrimitiveMode::Points;
    EXPECT_THROW(computeNormals(*points, 0.0f), std::invalid_argument);
}

TEST(MeshTools, TangentsFollowTheTextureAndSplitMirroredFaces) {
    // Every shape's own tangents (T = dP/du, w from glTF's bitangent-up rule) are reproduced;
    // on the cylinder's side within half a segment (its seam vertices see faces on one side only).
    for (const auto& shape : {shapes::box({1, 2, 3}), shapes::quad(2, 1), shapes::cylinder(1, 2, 12)}) {
        auto g = shape->clone();
        g->tangents.clear();
        computeTangents(*g);
        ASSERT_EQ(g->positions.size(), shape->positions.size());
        const float tolerance =
            shape->positions.size() > 30 ? 2.0f * std::sin(glm::radians(15.0f)) + 1e-4f : 1e-4f;
        for (std::size_t i = 0; i < g->positions.size(); ++i) {
            EXPECT_LE(glm::distance(glm::vec3(g->tangents[i]), glm::vec3(shape->tangents[i])), tolerance)
                << i;
            EXPECT_EQ(g->tangents[i].w, shape->tangents[i].w) << i;
        }
    }
    // Two quads sharing an edge, the second with its u mirrored: the shared vertices split,
    // one copy per handedness.
    auto g = Geometry::create();
    g->positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {2, 0, 0}, {2, 1, 0}};
    g->normals.assign(6, {0, 0, 1});
    g->texcoords = {{0, 1}, {1, 1}, {1, 0}, {0, 0}, {0, 1}, {0, 0}};
    g->indices = {0, 1, 2, 0, 2, 3, 1, 4, 5, 1, 5, 2};
    computeTangents(*g);
    EXPECT_EQ(g->positions.size(), 8u);
    int mirrored = 0;
    for (std::size_t i = 0; i < g->positions.size(); ++i) {
        const glm::vec4 t = g->tangents[i];
        if (t.w < 0) {
            ++mirrored;
            EXPECT_NEAR(t.x, -1.0f, 1e-5f); // u runs to −x on the mirrored quad
        } else {
            EXPECT_NEAR(t.x, 1.0f, 1e-5f);
        }
    }
    EXPECT_EQ(mirrored, 4);
}

TEST(Material, EveryMetallicRoughnessVariantCompilesUnderTheEffects) {
    // Maps × blend/mask × per-pixel/per-vertex lighting × instancing, under AO and fog: each
    // variant (main, depth and G-buffer passes) compiles, and no pixel is NaN.
    auto tex = texture1x1({0.5, 0.5, 0.5, 0.5}, false);
    for (int variant = 0; variant < 16; ++variant) {
        SCOPED_TRACE(variant);
        auto v = floatOrthoViewer();
        if (variant & 1) v->renderer().options().lighting = RendererOptions::Lighting::PerVertex;
        Lit scene({-0.3f, 0.2f, -1.0f}, glm::vec3(1.0f), 0.2f);
        auto point = Light::create(LightType::Point);
        point->position = {0, 0, 2};
        scene.root->addChild(point);
        auto m = Material::create();
        m->model = ShadingModel::MetallicRoughness;
        if (variant & 2) {
            m->baseColorTexture = m->metallicRoughnessTexture = m->occlusionTexture = m->emissiveTexture =
                m->normalTexture = tex;
            m->mapping(MaterialMap::Occlusion).texCoord = 1;
            m->mapping(MaterialMap::BaseColor).rotation = 0.3f;
        }
        auto q = shapes::quad(3.0f, 3.0f);
        q->texcoords1 = q->texcoords;
        if (variant & 4) m->alphaCutoff = 0.4f;
        if (variant & 8) {
            q->getOrCreateStateSet().blend.set(BlendMode::Alpha);
            q->instances = {glm::mat4(1.0f), glm::translate(glm::mat4(1.0f), {0.5f, 0.5f, 0.1f})};
        }
        q->getOrCreateStateSet().material.set(m);
        auto ao = AmbientOcclusionNode::create();
        ao->addChild(q);
        auto fog = FogNode::create(FogParameters::ground());
        fog->addChild(ao);
        scene.root->addChild(fog);
        v->setSceneData(scene.root);
        ASSERT_NO_THROW(v->frame());
        const FloatImage img = v->renderer().readPixelsLinear();
        for (float f : img.rgba)
            ASSERT_TRUE(std::isfinite(f));
        EXPECT_GT(pixel(img, 32, 32).r + pixel(img, 32, 32).g, 0.01);
        EXPECT_TRUE(v->renderer().takeGlErrors().empty());
    }
}

TEST(Material, ProfilingOptionsStoreLinearBytesAndTheConstantFloor) {
    // RendererOptions::ColorTarget::Unorm8Debug stores linear colour in 8 bits (the float
    // target's image within one step), and debugConstantShading writes the diffuse colour alone.
    auto render = [](RendererOptions::ColorTarget target, bool constant) {
        auto v = orthoTopViewer(kSize, kHalf);
        v->renderer().options().colorTarget = target;
        v->renderer().options().debugConstantShading = constant;
        Lit scene({-0.4f, -0.3f, -1.0f}, {0.9f, 0.85f, 0.8f}, 0.1f);
        auto m = Material::create();
        m->model = ShadingModel::MetallicRoughness;
        m->diffuse = {0.8f, 0.5f, 0.3f, 1.0f};
        m->roughness = 0.4f;
        scene.root->addChild(quadWith(m));
        v->setSceneData(scene.root);
        v->frame();
        return v->renderer().readPixelsLinear();
    };
    const FloatImage exact = render(RendererOptions::ColorTarget::Rgba32F, false);
    const FloatImage bytes = render(RendererOptions::ColorTarget::Unorm8Debug, false);
    const FloatImage floor = render(RendererOptions::ColorTarget::Unorm8Debug, true);
    for (auto [px, py] : {std::pair{5, 5}, {32, 32}, {60, 10}}) {
        const glm::dvec3 e = pixel(exact, px, py), b = pixel(bytes, px, py), f = pixel(floor, px, py);
        for (int c = 0; c < 3; ++c) {
            EXPECT_NEAR(b[c], std::min(e[c], 1.0), 0.5 / 255.0 + 1e-6) << px << "," << py;
            EXPECT_NEAR(f[c], glm::dvec3(0.8, 0.5, 0.3)[c], 0.5 / 255.0 + 1e-6) << px << "," << py;
        }
    }
    EXPECT_GT(std::abs(pixel(exact, 32, 32).r - 0.8), 0.02); // the lit image differs from the floor
}

TEST(Material, BadValuesNameTheField) {
    auto m = Material::create();
    m->roughness = 1.5f;
    EXPECT_THROW(m->validate(), std::invalid_argument);
    m->roughness = 0.5f;
    m->metallic = std::nanf("");
    try {
        m->validate();
        ADD_FAILURE();
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("metallic"), std::string::npos);
    }
    m->metallic = 0.0f;
    m->mapping(MaterialMap::Emissive).texCoord = 2;
    try {
        m->validate();
        ADD_FAILURE();
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("mappings[5]"), std::string::npos);
    }
}

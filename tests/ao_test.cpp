// AmbientOcclusionNode on OSMesa (≤ 96×96), ambient light only: a white ambient material under a
// white ambient light shows 1 − k in every pixel (read back linear, from a float target), so the
// occlusion k of the map is measured directly where the seed's geometry says what it must be.
#include "TestUtil.h"

#include <sgfx/Geometry.h>
#include <sgfx/Group.h>
#include <sgfx/ShaderComposer.h>
#include <sgfx/Shapes.h>
#include <sgfx/gl/Objects.h>
#include <sgfx/nodes/ao/AmbientOcclusionNode.h>
#include <sgfx/nodes/fog/FogNode.h>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include <cstdio>
#include <optional>

using namespace sgfx;
using namespace sgfx::test;

namespace {

constexpr int kSize = 96;

std::shared_ptr<Material> white() {
    auto m = Material::create();
    m->ambient = glm::vec3(1.0f);
    m->diffuse = glm::vec4(0, 0, 0, 1);
    m->specular = glm::vec3(0.0f);
    return m;
}

std::shared_ptr<Node> placed(const glm::mat4& m, std::shared_ptr<Geometry> g) {
    g->getOrCreateStateSet().material.set(white());
    auto t = Transform::create(m);
    t->addChild(g);
    return t;
}

glm::mat4 at(glm::vec3 p) {
    return glm::translate(glm::mat4(1.0f), p);
}

// A plane of size s in the z = 0 plane.
std::shared_ptr<Node> floorPlane(float s = 200.0f) {
    return placed(glm::mat4(1.0f), shapes::quad(s, s));
}

struct Render {
    FloatImage image;
    glm::mat4 viewProjection;
    // Occlusion at the pixel where world point p lands (1 − linear value).
    double k(glm::vec3 p) const {
        const glm::vec4 c = viewProjection * glm::vec4(p, 1.0f);
        const glm::vec2 ndc = glm::vec2(c) / c.w;
        const int x = int((ndc.x * 0.5f + 0.5f) * float(image.width));
        const int y = int((0.5f - ndc.y * 0.5f) * float(image.height));
        return kAt(x, y);
    }
    double kAt(int x, int y) const {
        return 1.0 - double(image.rgba[(std::size_t(y) * image.width + x) * 4]);
    }
    bool background(int x, int y) const {
        return image.rgba[(std::size_t(y) * image.width + x) * 4 + 2] > 5.0f;
    }
};

// Renders `scene` under an ambient light (and `ao` when given) from eye to target.
Render renderAo(std::shared_ptr<Node> scene, std::optional<AmbientOcclusionParameters> ao, glm::vec3 eye,
                glm::vec3 target, bool ortho = false, float orthoHalf = 3.0f, float farPlane = 500.0f) {
    auto v = Viewer::createHeadless(kSize, kSize);
    v->renderer().options().colorTarget = RendererOptions::ColorTarget::Rgba32F;
    auto& cam = *v->camera();
    cam.setPerspective(60.0f, 0.5f, farPlane);
    cam.setLookAt(eye, target,
                  std::abs(glm::normalize(target - eye).z) > 0.99f ? glm::vec3(0, 1, 0) : glm::vec3(0, 0, 1));
    if (ortho) cam.projectionMatrix = glm::ortho(-orthoHalf, orthoHalf, -orthoHalf, orthoHalf, 0.1f, 100.0f);
    cam.clearColor = {10.0f, 10.0f, 10.0f, 1.0f}; // background: blue > 5 marks it
    auto root = Group::create();
    root->addChild(Light::create(LightType::Ambient));
    if (ao) {
        auto node = AmbientOcclusionNode::create(*ao);
        node->addChild(scene);
        root->addChild(node);
    } else {
        root->addChild(scene);
    }
    v->setSceneData(root);
    v->frame();
    for (const auto& e : v->renderer().takeGlErrors())
        ADD_FAILURE() << "GL: " << e;
    return {v->renderer().readPixelsLinear(), cam.projectionMatrix * cam.viewMatrix};
}

// Largest occlusion over the non-background pixels.
double worstK(const Render& r) {
    double worst = 0;
    for (int y = 0; y < r.image.height; ++y)
        for (int x = 0; x < r.image.width; ++x)
            if (!r.background(x, y)) worst = std::max(worst, r.kAt(x, y));
    return worst;
}

} // namespace

TEST(AmbientOcclusion, WithoutTheNodeTheAmbientIsUntouched) {
    const Render r = renderAo(floorPlane(), std::nullopt, {0, -5, 3}, {0, 5, 0});
    EXPECT_LE(worstK(r), 1e-4);
}

TEST(AmbientOcclusion, OpenPlaneDoesNotOccludeItselfAtAnyAngle) {
    // The seed's figure 4 argument (a hemisphere, not a sphere), and more: at grazing angles a
    // pixel spans more depth than δ; the tangent-plane test keeps the plane open, the seed's
    // stored-depth test does not.
    struct View {
        glm::vec3 eye, target;
        const char* name;
    };
    for (const View& view :
         {View{{0, -10, 1.2f}, {0, 30, 0}, "grazing"}, View{{0, -2, 12}, {0, 0, 0}, "steep"}}) {
        const double k = worstK(renderAo(floorPlane(), AmbientOcclusionParameters{}, view.eye, view.target));
        const double paper =
            worstK(renderAo(floorPlane(), AmbientOcclusionParameters::paper(), view.eye, view.target));
        std::printf("open plane, %s view: worst occlusion %.4f (seed's method %.4f)\n", view.name, k, paper);
        EXPECT_LE(k, 0.02) << view.name;
        if (std::string(view.name) == "grazing") {
            EXPECT_GT(paper, 0.1) << "the stored-depth comparison occludes a plane seen at a grazing angle";
        }
    }
}

TEST(AmbientOcclusion, InnerCornerDarkensTowardsTheCrease) {
    // A floor and a wall meeting at y = 2; points on the floor approaching the crease.
    auto scene = Group::create();
    scene->addChild(floorPlane(20));
    scene->addChild(
        placed(at({0, 2, 0}) * glm::rotate(glm::mat4(1.0f), glm::radians(90.0f), glm::vec3(1, 0, 0)),
               shapes::quad(20, 20)));
    const Render r = renderAo(scene, AmbientOcclusionParameters{}, {0, -3, 3}, {0, 2, 0});
    std::vector<double> k;
    for (float d : {1.2f, 0.6f, 0.4f, 0.25f, 0.15f, 0.08f, 0.04f})
        k.push_back(r.k({0.3f, 2.0f - d, 0.0f}));
    std::printf("inner corner, floor at 1.2 .. 0.04 m from the wall:");
    for (double v : k)
        std::printf(" %.3f", v);
    std::printf("\n");
    EXPECT_LE(k.front(), 0.02) << "beyond R from the wall: open";
    EXPECT_GT(k.back(), 0.15) << "at the crease";
    for (std::size_t i = 1; i < k.size(); ++i)
        EXPECT_GE(k[i], k[i - 1] - 0.04) << "rising towards the crease (within noise), step " << i;
}

TEST(AmbientOcclusion, BoxOnAPlaneDarkensTheContactLineOnly) {
    const AmbientOcclusionParameters p;
    auto scene = Group::create();
    scene->addChild(floorPlane(40));
    scene->addChild(placed(at({0, 0, 0.5f}), shapes::box({1, 1, 1})));
    const Render r = renderAo(scene, p, {2.5f, -4, 3.5f}, {0, 0, 0.3f});
    const double contact = r.k({0.3f, -0.55f, 0.0f});
    const double away = r.k({0.3f, -0.5f - 3.0f * p.radius, 0.0f});
    std::printf("box on plane: contact %.3f, 3R away %.3f\n", contact, away);
    EXPECT_GT(contact, 0.15);
    EXPECT_LE(away, 0.02);
}

TEST(AmbientOcclusion, PlaneFiveKilometresAwayShowsNoFalseOcclusion) {
    // A wall 5 km away and the ground running to it, near plane 0.5 m: with 32-bit linear depth
    // and the kernel fading where it covers under a pixel, nothing is occluded.
    auto scene = Group::create();
    scene->addChild(
        placed(at({0, 5000, 0}) * glm::rotate(glm::mat4(1.0f), glm::radians(90.0f), glm::vec3(1, 0, 0)),
               shapes::quad(20000, 4000)));
    scene->addChild(floorPlane(12000));
    const Render r =
        renderAo(scene, AmbientOcclusionParameters{}, {0, 0, 2}, {0, 5000, 300}, false, 3.0f, 10000.0f);
    EXPECT_LE(worstK(r), 0.02);
}

TEST(AmbientOcclusion, AlphaCutOutsCastNoOcclusion) {
    // A wall standing on the floor whose left half is cut away by its alpha map (MASK): the floor
    // in front of the cut half stays open, in front of the solid half it darkens.
    auto alpha = Image::create(2, 1, 1);
    alpha->pixels = {0, 255};
    auto tex = Texture::create(alpha, false);
    tex->minFilter = tex->magFilter = Filter::Nearest;
    tex->wrapS = tex->wrapT = Wrap::ClampToEdge;
    auto m = white();
    m->alphaTexture = tex;
    m->alphaCutoff = 0.5f;
    auto wall = shapes::quad(4, 2);
    wall->getOrCreateStateSet().material.set(m);
    wall->getOrCreateStateSet().cullFace.set(CullFace::None);
    auto wallT = Transform::create(at({0, 0, 1}) *
                                   glm::rotate(glm::mat4(1.0f), glm::radians(90.0f), glm::vec3(1, 0, 0)));
    wallT->addChild(wall);
    auto scene = Group::create();
    scene->addChild(floorPlane(20));
    scene->addChild(wallT);
    const Render r = renderAo(scene, AmbientOcclusionParameters{}, {0, -4, 3}, {0, 0, 0.5f});
    const double cut = r.k({-1.0f, -0.06f, 0.0f}), solid = r.k({1.0f, -0.06f, 0.0f});
    std::printf("alpha cut-out: floor before the hole %.3f, before the wall %.3f\n", cut, solid);
    EXPECT_LE(cut, 0.02);
    EXPECT_GT(solid, 0.2);
}

TEST(AmbientOcclusion, NormalMapsAreHonoured) {
    // Grooves in the normal map tilt the hemisphere into the flat surface: more occlusion than
    // the same quad without the map.
    auto normals = Image::create(16, 16, 3);
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 16; ++x) {
            const glm::vec3 n =
                glm::normalize(glm::vec3(0.9f * std::sin(2.0f * 3.14159265f * float(x) / 16.0f), 0, 1));
            for (int c = 0; c < 3; ++c)
                normals->pixel(x, y)[c] = std::uint8_t(std::lround((n[c] * 0.5f + 0.5f) * 255.0f));
        }
    auto tex = Texture::create(normals, false);
    double mean[2] = {0, 0};
    for (int bumpy = 0; bumpy < 2; ++bumpy) {
        auto q = shapes::quad(4, 4);
        for (glm::vec2& uv : q->texcoords)
            uv *= 8.0f; // grooves 0.5 m apart
        auto m = white();
        if (bumpy) m->normalTexture = tex;
        q->getOrCreateStateSet().material.set(m);
        auto scene = Group::create();
        scene->addChild(q);
        AmbientOcclusionParameters p;
        p.normals = AoNormals::GBuffer; // normal maps live in the G-buffer, not in the depth
        const Render r = renderAo(scene, p, {0, -1, 4}, {0, 0, 0});
        int n = 0;
        for (int y = kSize / 4; y < 3 * kSize / 4; ++y)
            for (int x = kSize / 4; x < 3 * kSize / 4; ++x, ++n)
                mean[bumpy] += r.kAt(x, y);
        mean[bumpy] /= n;
    }
    std::printf("normal map: mean occlusion flat %.4f, grooved %.4f\n", mean[0], mean[1]);
    EXPECT_LE(mean[0], 0.01);
    EXPECT_GT(mean[1], mean[0] + 0.03);
}

TEST(AmbientOcclusion, BilateralBlurKeepsDepthEdgesSharperThanTheBox) {
    // Seen from above, a 3 m pillar's open top face meets the occluded floor at its base: the
    // box filter smears the floor's occlusion onto the top face, the bilateral one does not.
    auto scene = Group::create();
    scene->addChild(floorPlane(20));
    scene->addChild(placed(at({0, 0, 1.5f}), shapes::box({1.2f, 1.2f, 3})));
    int width[2] = {0, 0};
    for (int box = 0; box < 2; ++box) {
        AmbientOcclusionParameters p;
        p.blur = box ? AoBlur::Box : AoBlur::Bilateral;
        p.blurSize = 7;
        // Seen from above, what occludes the floor at the pillar's foot is the pillar's top, 3 m
        // up: the range check would discount it (its documented cost), and this test is about
        // the blur.
        p.rangeCheck = false;
        const Render r = renderAo(scene, p, {0, 0, 10}, {0, 0, 0}, true, 2.0f);
        // Along the middle row, inwards from the top face's last pixel before its edge at x = 0.6 m
        // (ortho ±2 m over 96 pixels: pixel 61's centre is at 0.5625 m).
        const int row = kSize / 2;
        for (int x = 61; x > kSize / 2 && r.kAt(x, row) > 0.02; --x)
            ++width[box];
        EXPECT_GT(r.kAt(64, row), 0.1) << "the floor at the pillar's foot is occluded";
        std::printf("%s blur: occlusion reaches %d pixels onto the pillar's top\n", box ? "box" : "bilateral",
                    width[box]);
    }
    EXPECT_LE(width[0], 1);
    EXPECT_GE(width[1], 2);
}

TEST(AmbientOcclusion, SameFrameTwiceGivesTheSameMap) {
    auto scene = Group::create();
    scene->addChild(floorPlane(20));
    scene->addChild(placed(at({0, 0, 0.5f}), shapes::box({1, 1, 1})));
    const Render a = renderAo(scene, AmbientOcclusionParameters{}, {2.5f, -4, 3.5f}, {0, 0, 0.3f});
    const Render b = renderAo(scene, AmbientOcclusionParameters{}, {2.5f, -4, 3.5f}, {0, 0, 0.3f});
    EXPECT_EQ(a.image.rgba, b.image.rgba);
}

TEST(AmbientOcclusion, HalfResolutionFollowsFullResolution) {
    auto scene = Group::create();
    scene->addChild(floorPlane(20));
    scene->addChild(placed(at({0, 0, 0.5f}), shapes::box({1, 1, 1})));
    AmbientOcclusionParameters half;
    half.halfResolution = true;
    const Render f = renderAo(scene, AmbientOcclusionParameters{}, {2.5f, -4, 3.5f}, {0, 0, 0.3f});
    const Render h = renderAo(scene, half, {2.5f, -4, 3.5f}, {0, 0, 0.3f});
    for (glm::vec3 p : {glm::vec3(0.3f, -0.55f, 0), glm::vec3(0.3f, -2.0f, 0), glm::vec3(0.2f, -0.3f, 1.0f)})
        EXPECT_NEAR(h.k(p), f.k(p), 0.08) << p.x << "," << p.y << "," << p.z;
    EXPECT_LE(worstK(h), 1.0);
}

TEST(AmbientOcclusion, BlendedSurfacesAreNotOccluded) {
    // A pane standing at the wall's foot: opaque it darkens near the crease, blended (alpha 1) it
    // keeps its full ambient.
    for (bool blended : {false, true}) {
        auto scene = Group::create();
        scene->addChild(floorPlane(20));
        scene->addChild(
            placed(at({0, 2, 0}) * glm::rotate(glm::mat4(1.0f), glm::radians(90.0f), glm::vec3(1, 0, 0)),
                   shapes::quad(20, 20)));
        auto pane = shapes::quad(2, 2);
        auto& ss = pane->getOrCreateStateSet();
        ss.material.set(white());
        if (blended) ss.blend.set(BlendMode::Alpha);
        auto t = Transform::create(at({0, 1.9f, 0.01f}));
        t->addChild(pane);
        scene->addChild(t);
        const Render r = renderAo(scene, AmbientOcclusionParameters{}, {0, -3, 3}, {0, 2, 0});
        const double k = r.k({0.2f, 1.95f, 0.01f});
        if (blended)
            EXPECT_LE(k, 1e-3);
        else
            EXPECT_GT(k, 0.1);
    }
}

TEST(AmbientOcclusion, ForeignShadersOptIn) {
    auto program = ShaderProgram::create("app_ao", kForeignVert, kForeignAoFrag);
    auto scene = Group::create();
    for (int i = 0; i < 2; ++i) {
        auto q = shapes::quad(20, 20);
        q->getOrCreateStateSet().program.set(program);
        q->getOrCreateStateSet().cullFace.set(CullFace::None);
        auto t = Transform::create(
            i == 0 ? glm::mat4(1.0f)
                   : at({0, 2, 0}) * glm::rotate(glm::mat4(1.0f), glm::radians(90.0f), glm::vec3(1, 0, 0)));
        t->addChild(q);
        scene->addChild(t);
    }
    const Render r = renderAo(scene, AmbientOcclusionParameters{}, {0, -3, 3}, {0, 2, 0});
    EXPECT_GT(r.k({0.3f, 1.96f, 0.0f}), 0.2) << "the crease, through the foreign shader";
    EXPECT_LE(r.k({0.3f, 0.5f, 0.0f}), 0.02);
}

TEST(AmbientOcclusion, FogAppliesAfterTheOcclusion) {
    // Homogeneous fog (falloff 0) over the corner: the crease pixel is the occluded ambient
    // 1 − k, then fogged over its distance: mix(1 − k, fog, 1 − e^(−ρ·S)).
    auto corner = [] {
        auto scene = Group::create();
        scene->addChild(floorPlane(20));
        scene->addChild(
            placed(at({0, 2, 0}) * glm::rotate(glm::mat4(1.0f), glm::radians(90.0f), glm::vec3(1, 0, 0)),
                   shapes::quad(20, 20)));
        return scene;
    };
    const glm::vec3 eye(0, -3, 3), crease(0.3f, 1.94f, 0.0f);
    const Render plain = renderAo(corner(), AmbientOcclusionParameters{}, eye, {0, 2, 0});
    const double k = plain.k(crease);
    ASSERT_GT(k, 0.1);
    FogParameters fp;
    fp.density = 0.05f;
    fp.falloff = 0.0f;
    fp.color = glm::vec3(0.2f, 0.4f, 0.6f);
    fp.sky = FogSky::Off;
    auto fog = FogNode::create(fp);
    auto ao = AmbientOcclusionNode::create();
    ao->addChild(corner());
    fog->addChild(ao);
    const Render fogged = renderAo(fog, std::nullopt, eye, {0, 2, 0});
    // The pixel's own surface point: the view ray through the pixel centre meets the floor.
    const glm::vec4 c = fogged.viewProjection * glm::vec4(crease, 1.0f);
    const int x = int((c.x / c.w * 0.5f + 0.5f) * kSize), y = int((0.5f - c.y / c.w * 0.5f) * kSize);
    const glm::mat4 inv = glm::inverse(fogged.viewProjection);
    const glm::vec2 ndc((x + 0.5f) / kSize * 2 - 1, 1 - (y + 0.5f) / kSize * 2);
    const glm::vec4 n4 = inv * glm::vec4(ndc, -1, 1), f4 = inv * glm::vec4(ndc, 1, 1);
    const glm::vec3 nearP = glm::vec3(n4) / n4.w, dir = glm::normalize(glm::vec3(f4) / f4.w - nearP);
    const glm::vec3 hit = nearP + dir * (-nearP.z / dir.z);
    const double kf = 1.0 - std::exp(-0.05 * glm::length(hit - eye));
    for (int ch = 0; ch < 3; ++ch) {
        const double expected = (1.0 - plain.kAt(x, y)) * (1 - kf) + fp.color[ch] * kf;
        EXPECT_NEAR(fogged.image.rgba[(std::size_t(y) * kSize + x) * 4 + ch], expected, 2e-3)
            << "channel " << ch;
    }
}

TEST(AmbientOcclusion, DebugViewShowsTheRawAndBlurredMaps) {
    auto scene = Group::create();
    scene->addChild(floorPlane(20));
    scene->addChild(placed(at({0, 0, 0.5f}), shapes::box({1, 1, 1})));
    double variation[2] = {0, 0};
    for (int blurred = 0; blurred < 2; ++blurred) {
        AmbientOcclusionParameters p;
        p.debugView = blurred ? AoDebugView::Blurred : AoDebugView::Raw;
        const Render r = renderAo(scene, p, {2.5f, -4, 3.5f}, {0, 0, 0.3f});
        // Pixel-to-pixel variation along the floor near the contact line: the noise the blur removes.
        const glm::vec4 c = r.viewProjection * glm::vec4(0.0f, -0.6f, 0.0f, 1.0f);
        const int y = int((0.5f - c.y / c.w * 0.5f) * kSize);
        for (int x = kSize / 4; x < 3 * kSize / 4; ++x)
            variation[blurred] += std::abs(r.kAt(x, y) - r.kAt(x - 1, y));
    }
    std::printf("debug view: row variation raw %.3f, blurred %.3f\n", variation[0], variation[1]);
    EXPECT_GT(variation[0], variation[1] * 1.5);
}

TEST(AmbientOcclusion, BadParametersAreRefused) {
    auto node = AmbientOcclusionNode::create();
    auto bad = [&](auto edit, const char* field) {
        AmbientOcclusionParameters p;
        edit(p);
        try {
            node->setParameters(p);
            ADD_FAILURE() << field << " accepted";
        } catch (const std::invalid_argument& e) {
            EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
        }
    };
    bad([](auto& p) { p.samples = 4; }, "samples");
    bad([](auto& p) { p.samples = 65; }, "samples");
    bad([](auto& p) { p.radius = 0.0f; }, "radius");
    bad([](auto& p) { p.radius = std::numeric_limits<float>::quiet_NaN(); }, "radius");
    bad([](auto& p) { p.bias = -1.0f; }, "bias");
    bad([](auto& p) { p.blurSize = 4; }, "blurSize");
    bad([](auto& p) { p.power = 0.0f; }, "power");
    bad([](auto& p) { p.kernel = AoKernel(5); }, "kernel");
    bad([](auto& p) { p.normals = AoNormals(7); }, "normals");
    EXPECT_EQ(node->parameters().samples, 32);
    EXPECT_EQ(node->parameters().normals, AoNormals::GBuffer);
}

TEST(AoKernel, HemisphereStaysInsideAndConcentratesTowardsTheCentre) {
    for (int m : {8, 32, 64}) {
        const auto k = ao::kernel(AoKernel::Hemisphere, m, 1);
        ASSERT_EQ(int(k.size()), m);
        int inner = 0;
        for (const glm::vec3& s : k) {
            EXPECT_LE(glm::length(s), 1.0f + 1e-6f);
            EXPECT_GE(s.z, 0.0f);
            inner += glm::length(s) < 0.5f;
        }
        EXPECT_GT(inner, m / 4) << "denser within R/2 than a uniform fill (1/8 of the samples)";
    }
    const auto cube = ao::kernel(AoKernel::PaperHalfCube, 64, 1);
    float longest = 0;
    for (const glm::vec3& s : cube)
        longest = std::max(longest, glm::length(s));
    EXPECT_GT(longest, 1.0f) << "the seed's half cube reaches beyond the unit hemisphere";
    EXPECT_EQ(ao::kernel(AoKernel::Hemisphere, 32, 7), ao::kernel(AoKernel::Hemisphere, 32, 7));
}

TEST(AmbientOcclusion, RangeCheckRemovesTheHaloOfAThinPoleOnAFarWall) {
    // A 0.4 m pole 2 m from the eye in front of a wall 12 m away: kernel points on the wall next
    // to the pole's silhouette land on the pole in the depth buffer, far in front. Without the
    // range check that counts as occlusion and the wall shows a dark halo around the pole; with
    // it the 12 m gap weighs each such sample smoothstep(0, 1, R / Δz) = smoothstep(0, 1, 0.17)
    // ≈ 0.08, and what is left of the halo is under a seventh of it.
    auto scene = Group::create();
    auto wallT = glm::rotate(at({0, 12, 0}), glm::radians(90.0f), glm::vec3(1, 0, 0));
    scene->addChild(placed(wallT, shapes::quad(60, 60)));
    scene->addChild(placed(at({0, 0, 0}), shapes::box({0.4f, 0.4f, 20.0f})));
    const glm::vec3 eye(0, -2, 0), target(0, 12, 0);
    auto halo = [&](bool rangeCheck) {
        AmbientOcclusionParameters p;
        p.radius = 2.0f;
        p.rangeCheck = rangeCheck;
        const Render r = renderAo(scene, p, eye, target);
        // The wall's pixels on the middle rows by their distance from the pole's silhouette (it
        // covers about x = 40..56; the kernel's 2 m is about 12 px on the wall at 14 m): the
        // darkest column within 8 px of it, and the mean of those 20 px and more away.
        const int mid = kSize / 2;
        double nearK = 0, farK = 0;
        int farN = 0;
        for (int d = 1; d <= 8; ++d) {
            double k = 0;
            for (int y = mid - 8; y < mid + 8; ++y)
                k += r.kAt(mid - 9 - d, y) + r.kAt(mid + 8 + d, y);
            nearK = std::max(nearK, k / 32.0);
        }
        for (int y = mid - 8; y < mid + 8; ++y)
            for (int x = 0; x < kSize; ++x)
                if (std::abs(x - mid) >= 29) farK += r.kAt(x, y), ++farN;
        return std::pair(nearK, farK / farN);
    };
    const auto [offNear, offFar] = halo(false);
    const auto [onNear, onFar] = halo(true);
    std::printf("pole halo on the wall: k near %.3f far %.3f without the range check, %.3f / %.3f with\n",
                offNear, offFar, onNear, onFar);
    EXPECT_GT(offNear - offFar, 0.2) << "without the check the wall darkens around the pole";
    EXPECT_LT(onNear - onFar, (offNear - offFar) / 7.0) << "with the check it does not";
    EXPECT_LT(onFar, 0.02);
}

// ------------------------------------------------------------------------------ temporal AO
// Quality of the cheap path against a many-sample reference (issue 24, Must 4): errors are the
// mean |k − k_ref| over the occluded pixels of a 128×96 view of a box and a pole on a floor.

namespace {

constexpr int kTw = 128, kTh = 96;

// One viewer kept over frames (the temporal history lives across them).
struct AoSequence {
    std::shared_ptr<Viewer> viewer = Viewer::createHeadless(kTw, kTh);
    std::shared_ptr<AmbientOcclusionNode> node;

    explicit AoSequence(const AmbientOcclusionParameters& p) {
        viewer->renderer().options().colorTarget = RendererOptions::ColorTarget::Rgba32F;
        viewer->camera()->setPerspective(60.0f, 0.5f, 100.0f);
        viewer->camera()->clearColor = {10.0f, 10.0f, 10.0f, 1.0f};
        auto scene = Group::create();
        scene->addChild(floorPlane(40));
        scene->addChild(placed(at({0, 0, 0.5f}), shapes::box({1, 1, 1})));
        scene->addChild(placed(at({-1.6f, 0.8f, 0.75f}), shapes::box({0.3f, 0.3f, 1.5f})));
        node = AmbientOcclusionNode::create(p);
        node->addChild(scene);
        auto root = Group::create();
        root->addChild(Light::create(LightType::Ambient));
        root->addChild(node);
        viewer->setSceneData(root);
    }
    // k per pixel (negative: background) of a frame seen from eye.
    std::vector<double> frame(glm::vec3 eye, glm::vec3 target = {0, 0, 0.3f}) {
        viewer->camera()->setLookAt(eye, target, {0, 0, 1});
        viewer->frame();
        for (const auto& e : viewer->renderer().takeGlErrors())
            ADD_FAILURE() << "GL: " << e;
        const FloatImage im = viewer->renderer().readPixelsLinear();
        std::vector<double> k(std::size_t(kTw * kTh));
        for (std::size_t i = 0; i < k.size(); ++i)
            k[i] = im.rgba[i * 4 + 2] > 5.0f ? -1.0 : 1.0 - double(im.rgba[i * 4]);
        return k;
    }
};

// The reference: full resolution, no blur, 4 × 64 = 256 taps (four seeds averaged).
std::vector<double> referenceK(glm::vec3 eye, glm::vec3 target = {0, 0, 0.3f}) {
    AmbientOcclusionParameters p;
    p.samples = 64, p.blurSize = 1;
    AoSequence one(p);
    std::vector<double> sum;
    for (std::uint32_t seed = 11; seed < 15; ++seed) {
        p.seed = seed;
        one.node->setParameters(p);
        const std::vector<double> k = one.frame(eye, target);
        if (sum.empty()) sum.assign(k.size(), 0.0);
        for (std::size_t i = 0; i < k.size(); ++i)
            sum[i] += k[i] / 4.0;
    }
    return sum;
}

// Over the pixels where either shows occlusion (k > 0.005): the open floor, 0 in both, would
// dilute the mean into the noise.
double meanError(const std::vector<double>& k, const std::vector<double>& ref) {
    double sum = 0;
    int n = 0;
    for (std::size_t i = 0; i < k.size(); ++i)
        if (ref[i] >= 0 && k[i] >= 0 && (ref[i] > 0.005 || k[i] > 0.005)) sum += std::abs(k[i] - ref[i]), ++n;
    return n ? sum / n : 1e9;
}

AmbientOcclusionParameters temporalParameters() {
    AmbientOcclusionParameters p;
    p.temporal = true;
    p.normals = AoNormals::FromDepth;
    return p;
}

const glm::vec3 kEye{2.5f, -4.5f, 3.0f};

} // namespace

TEST(AmbientOcclusionTemporal, StillFramesAreNoWorseThanTodaysDefault) {
    const std::vector<double> ref = referenceK(kEye);
    const double e32 = meanError(AoSequence(AmbientOcclusionParameters{}).frame(kEye), ref);
    AoSequence t(temporalParameters());
    double first = 0, last = 0;
    for (int i = 0; i < 8; ++i) {
        const double e = meanError(t.frame(kEye), ref);
        (i == 0 ? first : last) = e;
    }
    std::printf("temporal AO, still: E_32 = %.4f; frame 1 %.4f, frame 8 %.4f\n", e32, first, last);
    EXPECT_LE(last, e32);
    EXPECT_GT(first, last) << "one frame of 8 taps is noisier than 8 frames accumulated";
}

TEST(AmbientOcclusionTemporal, SlowPanStaysWithinTheAllowance) {
    // About 1 px/frame at the box: the eye and the target slide along x by 6 cm a frame.
    const glm::vec3 step{0.06f, 0, 0};
    const double e32 = meanError(AoSequence(AmbientOcclusionParameters{}).frame(kEye), referenceK(kEye));
    AoSequence t(temporalParameters());
    for (int i = 0; i < 14; ++i) {
        const glm::vec3 shift = float(i) * step;
        const std::vector<double> k = t.frame(kEye + shift, glm::vec3(0, 0, 0.3f) + shift);
        if (i < 8 || i % 2) continue; // frames 8, 10, 12 against their own reference
        const std::vector<double> ref = referenceK(kEye + shift, glm::vec3(0, 0, 0.3f) + shift);
        const double e = meanError(k, ref);
        std::printf("temporal AO, pan frame %d: %.4f (1.25·E_32 = %.4f)\n", i, e, 1.25 * e32);
        EXPECT_LE(e, 1.25 * e32) << "frame " << i;
    }
}

TEST(AmbientOcclusionTemporal, HistoryStartsAgainAfterACameraCutAndLeaksNothing) {
    // Eight frames at one place, then a jump of 3 m: the frame after it must be what a fresh
    // node makes there on a frame of the same kernel set (frame 8 ≡ 0 mod 8). Kept history would
    // blend the old view's k wherever the floor's depth matches.
    // The history textures go with the node: nothing is left behind.
    const long before = gl::liveObjects().total();
    {
        const glm::vec3 jump{3.0f, 0, 0};
        AoSequence cut(temporalParameters());
        for (int i = 0; i < 8; ++i)
            cut.frame(kEye);
        const std::vector<double> after = cut.frame(kEye + jump, glm::vec3(0, 0, 0.3f) + jump);
        AoSequence fresh(temporalParameters());
        const std::vector<double> first = fresh.frame(kEye + jump, glm::vec3(0, 0, 0.3f) + jump);
        double worst = 0;
        for (std::size_t i = 0; i < after.size(); ++i)
            worst = std::max(worst, std::abs(after[i] - first[i]));
        EXPECT_LE(worst, 1e-6);
    }
    EXPECT_EQ(gl::liveObjects().total(), before);
}

TEST(AmbientOcclusionTemporal, NormalsFromDepthKeepATiltedPlaneOpen) {
    // The tangent-plane test leaves a plane open only with its exact normal: a normal off by a
    // few degrees puts half the kernel under the surface. Planes tilted towards and away.
    for (float tilt : {-50.0f, 0.0f, 60.0f}) {
        auto plane = placed(glm::rotate(glm::mat4(1.0f), glm::radians(tilt), glm::vec3(1, 0, 0)),
                            shapes::quad(30, 30));
        AmbientOcclusionParameters p;
        p.normals = AoNormals::FromDepth;
        p.blurSize = 1;
        const double k = worstK(renderAo(plane, p, {0.5f, -6, 4}, {0, 0, 0}));
        EXPECT_LE(k, 0.02) << "tilt " << tilt;
        p.temporal = true;
        EXPECT_LE(worstK(renderAo(plane, p, {0.5f, -6, 4}, {0, 0, 0})), 0.02) << "temporal, tilt " << tilt;
    }
}

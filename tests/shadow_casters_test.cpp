// ShadowNode's casters, kind by kind (docs/plans/shadows.md §7): an alpha-masked leaf card casts
// its mask, a mirrored single-sided quad, instanced and automatically batched boxes and a billboard
// turned to the camera cast as drawn, a blended surface casts nothing by default. Expectations are
// computed here: rays from plane points to the sun against the card, and corners projected along
// the light onto the plane (p − L·p.z/L.z), as in shadow_test.cpp. Top view of a white Lambert
// plane lit by the sun alone, so v = pixel / (N·L).
#include "ShadowTestUtil.h"

#include <sgfx/Billboard.h>
#include <sgfx/Geometry.h>
#include <sgfx/Group.h>
#include <sgfx/Shapes.h>
#include <sgfx/Texture.h>
#include <sgfx/nodes/particles/ParticleSystemNode.h>
#include <sgfx/nodes/shadow/ShadowNode.h>
#include <sgfx/nodes/transparency/TransparencyBin.h>
#include <sgfx/nodes/volume/VolumeNode.h>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <optional>
#include <vector>

using namespace sgfx;
using namespace sgfx::test;
using namespace sgfx::test::shadows;

namespace {

constexpr int kSize = 128;
constexpr double kHalf = 4.0;
constexpr double kPixel = 2.0 * kHalf / kSize;

glm::dvec2 worldOfPixel(int x, int y) {
    return {-kHalf + (x + 0.5) * kPixel, kHalf - (y + 0.5) * kPixel};
}

// What a pixel of the plane should be: shadowed, lit, or too near an edge to say.
enum class Expect { Shadowed, Lit, Unsure };

// The scene: sun, then a ShadowNode over the plane and `casters`; rendered from above.
FloatImage renderTop(const glm::dvec3& L, const std::vector<std::shared_ptr<Node>>& casters,
                     ShadowOptions o = {}) {
    auto sun = Light::create(LightType::Directional);
    sun->direction = -glm::vec3(L);
    auto root = Group::create();
    root->addChild(sun);
    o.cascades = 1;
    auto shadows = ShadowNode::create(sun, o);
    shadows->addChild(lambert(shapes::quad(12.0f, 12.0f)));
    for (const auto& c : casters)
        shadows->addChild(c);
    root->addChild(shadows);
    auto v = topViewer(kSize, kHalf);
    v->setSceneData(root);
    v->frame();
    expectNoGlErrors(*v);
    return v->renderer().readPixelsLinear();
}

// Every pixel against `expect` (v < 0.5 is shadowed); counts and the first few mismatches.
struct Tally {
    int shadowed = 0, lit = 0, wrong = 0;
};
Tally check(const FloatImage& img, double cosSun, const std::function<Expect(glm::dvec2)>& expect) {
    Tally t;
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) {
            const glm::dvec2 w = worldOfPixel(x, y);
            const Expect e = expect(w);
            if (e == Expect::Unsure) continue;
            const double v = red(img, x, y) / cosSun;
            (e == Expect::Shadowed ? t.shadowed : t.lit) += 1;
            if ((v < 0.5) != (e == Expect::Shadowed) && ++t.wrong <= 5)
                ADD_FAILURE() << "pixel " << x << "," << y << " (" << w.x << ", " << w.y << "): v = " << v
                              << ", expected " << (e == Expect::Shadowed ? "shadow" : "light");
        }
    return t;
}

// Shadowed inside any of `shadows`, lit outside all; unsure within a pixel of an edge or over a
// footprint (what covers the plane in the view, a pixel wide margin).
std::function<Expect(glm::dvec2)> hulls(const std::vector<Hull>& shadows, const std::vector<Hull>& covers) {
    return [=](glm::dvec2 w) {
        for (const Hull& c : covers)
            if (signedDistance(c, w) < kPixel) return Expect::Unsure;
        double nearest = 1e30;
        for (const Hull& s : shadows)
            nearest = std::min(nearest, signedDistance(s, w));
        if (std::abs(nearest) < kPixel) return Expect::Unsure;
        return nearest < 0 ? Expect::Shadowed : Expect::Lit;
    };
}

} // namespace

// A 2 m leaf card standing upright (the xz plane, 0.5..2.5 m up), double-sided, its alpha a ring
// (1 for 0.25 ≤ r ≤ 0.45 of the card's uv square, else 0) with cutoff 0.5. A plane point is in
// shadow where its ray to the sun crosses the card inside the ring; points whose crossing lies
// within 0.04 (8 cm) of the ring's edges are left out (texel and pixel rounding).
TEST(ShadowCasters, LeafCardCastsItsAlphaMask) {
    auto ring = Image::create(64, 64, 1);
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) {
            const double r = glm::length(glm::dvec2((x + 0.5) / 64.0 - 0.5, (y + 0.5) / 64.0 - 0.5));
            *ring->pixel(x, y) = r >= 0.25 && r <= 0.45 ? 255 : 0;
        }
    auto m = white();
    m->alphaTexture = Texture::create(ring, false);
    m->alphaCutoff = 0.5f;
    auto card = shapes::quad(2.0f, 2.0f);
    card->getOrCreateStateSet().material.set(m);
    card->getOrCreateStateSet().cullFace.set(CullFace::None);
    // Rotated into the xz plane (quad y → world z), centred at 1.5 m.
    const glm::mat4 toCard = glm::translate(glm::mat4(1.0f), glm::vec3(0, 0, 1.5f)) *
                             glm::rotate(glm::mat4(1.0f), glm::half_pi<float>(), glm::vec3(1, 0, 0));
    const glm::dvec3 L = sunVector(-70.0, 60.0); // from −y, so the shadow falls towards +y
    const FloatImage img = renderTop(L, {placed(card, toCard)});
    const Tally t = check(img, L.z, [&](glm::dvec2 w) {
        if (std::abs(w.y) < 2 * kPixel) return Expect::Unsure; // the card seen edge-on
        const double s = -w.y / L.y;                           // the ray meets y = 0
        if (s < 0) return Expect::Lit;
        const glm::dvec3 q = glm::dvec3(w, 0.0) + s * L;
        const glm::dvec2 uv((q.x + 1.0) / 2.0, (q.z - 0.5) / 2.0);
        if (uv.x < -0.02 || uv.x > 1.02 || uv.y < -0.02 || uv.y > 1.02) return Expect::Lit;
        const double r = glm::length(uv - 0.5);
        if (std::abs(r - 0.25) < 0.04 || std::abs(r - 0.45) < 0.04) return Expect::Unsure;
        return r > 0.25 && r < 0.45 ? Expect::Shadowed : Expect::Lit;
    });
    EXPECT_EQ(t.wrong, 0);
    EXPECT_GT(t.shadowed, 100); // the ring (its hole and outside lit)
    EXPECT_GT(t.lit, 10000);
}

// A single-sided quad facing up, mirrored by scale(−1, 1, 1): its winding flips with the mirror,
// so the light still sees its front face and it casts (a wrong winding would cull it from the map).
TEST(ShadowCasters, MirroredSingleSidedQuadCasts) {
    const glm::dvec3 L = sunVector(20.0, 55.0);
    const glm::dmat4 m = glm::translate(glm::dmat4(1.0), glm::dvec3(-0.5, 0.3, 1.0)) *
                         glm::scale(glm::dmat4(1.0), glm::dvec3(-1.0, 1.0, 1.0));
    const FloatImage img = renderTop(L, {placed(lambert(shapes::quad(1.5f, 1.0f)), glm::mat4(m))});
    const std::vector<glm::dvec3> corners = boxCorners(m, {1.5, 1.0, 0.0});
    const Tally t = check(img, L.z, hulls({projected(corners, L)}, {footprint(corners)}));
    EXPECT_EQ(t.wrong, 0);
    EXPECT_GT(t.shadowed, 100);
}

// Four instances of one Geometry, and four nodes sharing a mesh and state (batched into one draw
// by automatic instancing): eight boxes, eight shadows.
TEST(ShadowCasters, InstancedAndBatchedBoxesCastEach) {
    const glm::dvec3 L = sunVector(200.0, 50.0), size(0.5, 0.4, 0.6);
    auto instanced = lambert(shapes::box(glm::vec3(size)));
    std::vector<std::shared_ptr<Node>> casters{instanced};
    std::vector<Hull> shadows, covers;
    auto shared = lambert(shapes::box(glm::vec3(size)));
    for (int i = 0; i < 4; ++i) {
        const glm::dmat4 a = glm::translate(glm::dmat4(1.0), glm::dvec3(-2.5 + 1.6 * i, 1.8, 0.8 + 0.1 * i));
        const glm::dmat4 b = glm::translate(glm::dmat4(1.0), glm::dvec3(-2.5 + 1.6 * i, -1.0, 0.9));
        instanced->instances.push_back(glm::mat4(a));
        casters.push_back(placed(shared, glm::mat4(b)));
        for (const glm::dmat4& m : {a, b}) {
            shadows.push_back(projected(boxCorners(m, size), L));
            covers.push_back(footprint(boxCorners(m, size)));
        }
    }
    const FloatImage img = renderTop(L, casters);
    const Tally t = check(img, L.z, hulls(shadows, covers));
    EXPECT_EQ(t.wrong, 0);
    EXPECT_GT(t.shadowed, 8 * 40);
}

// A billboard turned about Z towards the camera's eye (it stands off the view's axis, so the eye
// is to one side) casts as the camera draws it, not as it would face the light: the corners
// turned by hand, then projected.
TEST(ShadowCasters, BillboardCastsAsTheCameraSeesIt) {
    const glm::dvec3 L = sunVector(150.0, 45.0), at(2.0, 0.5, 0.5);
    auto bb = Billboard::create(Billboard::Mode::AxialRotation); // normal (0, −1, 0), axis Z
    auto card = lambert(shapes::quad(1.6f, 1.2f));
    card->getOrCreateStateSet().cullFace.set(CullFace::None);
    // The quad in the billboard's xz plane, its base on the billboard's origin.
    bb->addChild(placed(card, glm::translate(glm::mat4(1.0f), glm::vec3(0, 0, 0.6f)) *
                                  glm::rotate(glm::mat4(1.0f), glm::half_pi<float>(), glm::vec3(1, 0, 0))));
    const FloatImage img = renderTop(L, {placed(bb, glm::translate(glm::mat4(1.0f), glm::vec3(at)))});
    // The eye of the top view is (0, 0, 10): turning (0, −1, 0) about Z towards it horizontally
    // puts the card's normal along (−2, −0.5) normalised; its width runs along the perpendicular.
    const glm::dvec2 n = glm::normalize(glm::dvec2(-at.x, -at.y));
    const glm::dvec2 across(-n.y, n.x);
    std::vector<glm::dvec3> corners;
    for (const double s : {-0.8, 0.8})
        for (const double z : {0.0, 1.2})
            corners.push_back(at + glm::dvec3(across * s, z));
    const Hull edgeOn = {glm::dvec2(at) - across * 0.8 - n * 0.05, glm::dvec2(at) + across * 0.8 - n * 0.05,
                         glm::dvec2(at) + across * 0.8 + n * 0.05, glm::dvec2(at) - across * 0.8 + n * 0.05};
    const Tally t = check(img, L.z, hulls({projected(corners, L)}, {edgeOn}));
    EXPECT_EQ(t.wrong, 0);
    EXPECT_GT(t.shadowed, 150);
}

// A blended pane (opacity 0.6) over the plane casts nothing by default; with blendedCasterAlpha
// 0.5 it casts its projection, with 0.7 nothing again.
TEST(ShadowCasters, BlendedSurfacesCastOnlyAboveTheChosenOpacity) {
    const glm::dvec3 L = sunVector(30.0, 60.0);
    const glm::dmat4 at = glm::translate(glm::dmat4(1.0), glm::dvec3(0.0, 0.0, 1.0));
    const std::vector<glm::dvec3> corners = boxCorners(at, {2.0, 2.0, 0.0});
    for (const std::optional<float> threshold :
         {std::optional<float>{}, std::optional<float>{0.5f}, std::optional<float>{0.7f}}) {
        SCOPED_TRACE(threshold ? *threshold : -1.0f);
        auto pane = shapes::quad(2.0f, 2.0f);
        auto m = white();
        m->diffuse.a = 0.6f;
        pane->getOrCreateStateSet().material.set(m);
        pane->getOrCreateStateSet().blend.set(BlendMode::Alpha);
        ShadowOptions o;
        o.blendedCasterAlpha = threshold;
        const FloatImage img = renderTop(L, {placed(pane, glm::mat4(at))}, o);
        const bool casts = threshold && *threshold <= 0.6f;
        const Tally t = check(img, L.z,
                              hulls(casts ? std::vector<Hull>{projected(corners, L)} : std::vector<Hull>{},
                                    {footprint(corners)}));
        EXPECT_EQ(t.wrong, 0);
        EXPECT_GT(casts ? t.shadowed : t.lit, casts ? 150 : 8000);
    }
}

// An application's own shader that opts in (kForeignShadowFrag, TestUtil.h) shows the
// visibility: 0 in the box's shadow, 1 outside; without a ShadowNode it compiles and shows 1.
TEST(ShadowCasters, ForeignShadersOptInThroughTheHook) {
    const glm::dvec3 L = sunVector(120.0, 50.0);
    auto program = ShaderProgram::create("app_shadow", kForeignVert, kForeignShadowFrag);
    const glm::dmat4 at = glm::translate(glm::dmat4(1.0), glm::dvec3(0.3, -0.2, 1.0));
    for (const bool node : {true, false}) {
        SCOPED_TRACE(node ? "under a ShadowNode" : "without one");
        auto sun = Light::create(LightType::Directional);
        sun->direction = -glm::vec3(L);
        auto plane = shapes::quad(12.0f, 12.0f);
        plane->getOrCreateStateSet().program.set(program);
        auto parent = node ? std::static_pointer_cast<Group>(ShadowNode::create(sun)) : Group::create();
        parent->addChild(plane);
        parent->addChild(placed(lambert(shapes::box({1.0f, 0.8f, 0.6f})), glm::mat4(at)));
        auto root = Group::create();
        root->addChild(sun);
        root->addChild(parent);
        auto v = topViewer(kSize, kHalf);
        v->setSceneData(root);
        v->frame();
        expectNoGlErrors(*v);
        const FloatImage img = v->renderer().readPixelsLinear();
        const std::vector<glm::dvec3> corners = boxCorners(at, {1.0, 0.8, 0.6});
        const std::vector<Hull> shadows =
            node ? std::vector<Hull>{projected(corners, L)} : std::vector<Hull>{};
        const Tally t = check(img, 1.0, hulls(shadows, {footprint(corners)}));
        EXPECT_EQ(t.wrong, 0);
        EXPECT_GT(node ? t.shadowed : t.lit, node ? 200 : 10000);
    }
}

// The volume's single scattering of the sun is shadowed too: a homogeneous box lit straight from
// above, half under an opaque slab. Along a pixel's ray the sun term is the quadrature of
// T(t)·k_s·p·E·e^(−k_s·(1 − z)) over the box, computed here, and zero under the slab (x < 0);
// pixels whose rays stay on one side of x = 0 inside the box must match it within 2 %.
TEST(ShadowReceivers, VolumeScatteringIsShadowed) {
    const double ks = 0.6, E = 3.0, phase = 1.0 / (4.0 * std::numbers::pi);
    VolumeParameters p;
    p.size = glm::vec3(2.0f);
    p.absorption = 0.0f;
    p.scattering = float(ks);
    p.phase = VolumePhase::Isotropic;
    p.lightColor = glm::vec3(float(E));
    p.lightDirection = {0, 0, -1};
    p.earlyTermination = 1.0f;
    auto sun = Light::create(LightType::Directional);
    sun->direction = {0, 0, -1};
    auto shadows = ShadowNode::create(sun);
    shadows->addChild(VolumeNode::create(p));
    shadows->addChild(placed(lambert(shapes::box({5.0f, 10.0f, 0.2f})),
                             glm::translate(glm::mat4(1.0f), glm::vec3(-2.5f, 0.0f, 3.0f))));
    auto root = Group::create();
    root->addChild(sun);
    root->addChild(shadows);
    constexpr int N = 64;
    auto v = Viewer::createHeadless(N, N);
    v->renderer().options().colorTarget = RendererOptions::ColorTarget::Rgba32F;
    Camera& cam = *v->camera();
    cam.setPerspective(40.0f, 0.1f, 100.0f);
    cam.setLookAt({0, -5, 0}, {0, -4, 0}, {0, 0, 1});
    cam.computeNearFar = false;
    cam.clearColor = {0, 0, 0, 1};
    v->setSceneData(root);
    v->frame();
    expectNoGlErrors(*v);
    const FloatImage img = v->renderer().readPixelsLinear();
    const glm::dmat4 inv = glm::inverse(glm::dmat4(cam.projectionMatrix) * glm::dmat4(cam.viewMatrix));
    int checkedLit = 0, checkedShadowed = 0;
    for (int y = N / 2 - 8; y < N / 2 + 8; ++y)
        for (int x = 0; x < N; ++x) {
            const glm::dvec2 ndc((x + 0.5) / N * 2.0 - 1.0, 1.0 - (y + 0.5) / N * 2.0);
            const glm::dvec4 a = inv * glm::dvec4(ndc, -1.0, 1.0), b = inv * glm::dvec4(ndc, 1.0, 1.0);
            const glm::dvec3 o = glm::dvec3(a) / a.w, d = glm::normalize(glm::dvec3(b) / b.w - o);
            double t0 = 0.0, t1 = 1e30; // the ray in the box [−1, 1]³
            for (int k = 0; k < 3; ++k) {
                const double u = (-1.0 - o[k]) / d[k], w = (1.0 - o[k]) / d[k];
                t0 = std::max(t0, std::min(u, w));
                t1 = std::min(t1, std::max(u, w));
            }
            if (!(t1 > t0 + 0.5)) continue;
            const double xIn = o.x + t0 * d.x, xOut = o.x + t1 * d.x;
            if (std::min(xIn, xOut) < 0.15 && std::max(xIn, xOut) > -0.15) continue; // crosses the edge
            const bool lit = xIn > 0.0;
            double L = 0.0, T = 1.0;
            constexpr int kSteps = 4000;
            const double dt = (t1 - t0) / kSteps;
            for (int s = 0; s < kSteps; ++s) {
                const double z = o.z + (t0 + (s + 0.5) * dt) * d.z;
                const double mid = T * std::exp(-ks * dt / 2);
                if (lit) L += mid * ks * phase * E * std::exp(-ks * (1.0 - z)) * dt;
                T *= std::exp(-ks * dt);
            }
            const double got = red(img, x, y);
            EXPECT_NEAR(got, L, 0.02 * L + 2e-4) << "pixel " << x << "," << y << (lit ? " lit" : " shadowed");
            (lit ? checkedLit : checkedShadowed) += 1;
        }
    EXPECT_GT(checkedLit, 100);
    EXPECT_GT(checkedShadowed, 100);
}

// Blended items an order-independent transparency pass draws itself (RenderQueue::claimed) read
// the shadow map too: the pass declares what their effects sample, so the map is made and alive.
// A half-transparent white plane in a weighted-blended bin, with nothing opaque receiving, shows
// the box's shadow: v = pixel / (α·N·L).
TEST(ShadowReceivers, OrderIndependentTransparencyReceives) {
    const glm::dvec3 L = sunVector(250.0, 55.0);
    auto sun = Light::create(LightType::Directional);
    sun->direction = -glm::vec3(L);
    auto shadows = ShadowNode::create(sun);
    auto bin = TransparencyBin::create(TransparencyMode::WeightedBlended);
    auto pane = shapes::quad(12.0f, 12.0f);
    auto m = white();
    m->diffuse.a = 0.5f;
    pane->getOrCreateStateSet().material.set(m);
    pane->getOrCreateStateSet().blend.set(BlendMode::Alpha);
    bin->addChild(pane);
    shadows->addChild(bin);
    const glm::dmat4 at = glm::translate(glm::dmat4(1.0), glm::dvec3(0.2, 0.1, 1.2));
    shadows->addChild(placed(lambert(shapes::box({1.0f, 1.2f, 0.5f})), glm::mat4(at)));
    auto root = Group::create();
    root->addChild(sun);
    root->addChild(shadows);
    auto v = topViewer(kSize, kHalf);
    v->setSceneData(root);
    v->frame();
    expectNoGlErrors(*v);
    const std::vector<glm::dvec3> corners = boxCorners(at, {1.0, 1.2, 0.5});
    const Tally t = check(v->renderer().readPixelsLinear(), 0.5 * L.z,
                          hulls({projected(corners, L)}, {footprint(corners)}));
    EXPECT_EQ(t.wrong, 0);
    EXPECT_GT(t.shadowed, 150);
}

// A spot light's perspective map: the box's shadow is its corners projected from the light's
// position onto the plane, lp + (p − lp)·lp.z/(lp.z − p.z). v is the pixel over the same view
// without the ShadowNode (the spot's cone and falloff divide out); only pixels the spot lights
// count. With a sun as well, both shadows: the spot's light and the sun's each shadowed.
TEST(ShadowCasters, SpotLightCastsFromItsPosition) {
    const glm::dvec3 lp(0.5, -0.3, 4.0), size(0.8, 0.6, 0.5);
    const glm::dmat4 at = glm::translate(glm::dmat4(1.0), glm::dvec3(-0.2, 0.4, 1.0));
    for (const ShadowFilter filter : {ShadowFilter::Hard2x2, ShadowFilter::Pcf, ShadowFilter::Pcss}) {
        SCOPED_TRACE(int(filter));
        auto spot = Light::create(LightType::Spot);
        spot->position = glm::vec3(lp);
        spot->direction = {0, 0, -1};
        spot->outerConeAngle = glm::radians(50.0f);
        spot->innerConeAngle = glm::radians(40.0f);
        ShadowOptions o;
        o.filter = filter;
        auto shadows = ShadowNode::create(nullptr, o);
        shadows->addSpot(spot);
        shadows->addChild(lambert(shapes::quad(12.0f, 12.0f)));
        shadows->addChild(placed(lambert(shapes::box(glm::vec3(size))), glm::mat4(at)));
        auto root = Group::create();
        root->addChild(spot);
        root->addChild(shadows);
        auto v = topViewer(kSize, kHalf);
        v->setSceneData(root);
        v->frame();
        expectNoGlErrors(*v);
        const FloatImage shadowed = v->renderer().readPixelsLinear();
        shadows->enabled = false;
        v->frame();
        const FloatImage plain = v->renderer().readPixelsLinear();
        std::vector<glm::dvec2> projectedCorners;
        for (const glm::dvec3& p : boxCorners(at, size))
            projectedCorners.push_back(glm::dvec2(lp + (p - lp) * (lp.z / (lp.z - p.z))));
        const auto expect = hulls({convexHull(projectedCorners)}, {footprint(boxCorners(at, size))});
        int wrong = 0, dark = 0;
        for (int y = 0; y < kSize; ++y)
            for (int x = 0; x < kSize; ++x) {
                const Expect e = expect(worldOfPixel(x, y));
                const double p = red(plain, x, y);
                if (e == Expect::Unsure || p < 0.05) continue;
                const bool isDark = red(shadowed, x, y) / p < 0.5;
                dark += isDark;
                if (isDark != (e == Expect::Shadowed) && ++wrong <= 5)
                    ADD_FAILURE() << "pixel " << x << "," << y << ": v = " << red(shadowed, x, y) / p;
            }
        EXPECT_EQ(wrong, 0);
        EXPECT_GT(dark, 100); // the shadow beyond the box's footprint
    }
}

TEST(ShadowCasters, SpotsAreCheckedWhenAdded) {
    auto node = ShadowNode::create();
    node->name = "shadows";
    auto sun = Light::create(LightType::Directional);
    sun->name = "sun";
    try {
        node->addSpot(sun);
        FAIL() << "a directional light accepted as a spot";
    } catch (const std::invalid_argument& e) {
        EXPECT_STREQ(e.what(), "sgfx: ShadowNode 'shadows': addSpot needs a Spot light; 'sun' is not one");
    }
    for (int i = 0; i < 3; ++i)
        node->addSpot(Light::create(LightType::Spot));
    EXPECT_THROW(node->addSpot(Light::create(LightType::Spot)), std::invalid_argument);
    EXPECT_EQ(node->spots().size(), 3u);
    EXPECT_TRUE(node->removeSpot(node->spots()[1].get()));
    EXPECT_EQ(node->spots().size(), 2u);
}

// Particles are built on the built-in material, so they receive: a lit opaque sprite under a slab
// shows what the same sprite shows with the sun switched off (ambient light only), one beside the
// slab more than that.
TEST(ShadowReceivers, LitParticlesInTheShadowGetAmbientOnly) {
    const auto sprite = [](glm::vec3 at) {
        ParticleSettings s;
        s.capacity = 1;
        s.emitter.size = {0.0f, 0.0f};
        s.emitter.acceleration = glm::vec3(0.0f);
        s.emitter.lifetime = 1000.0f;
        s.start = particles::StartMode::Burst;
        s.shape = ParticleShape::Sprite;
        s.sizeStart = s.sizeEnd = 0.6f;
        auto p = ParticleSystemNode::create(s);
        auto st = ParticleSystemNode::defaultState();
        auto& m = **st->material.value;
        m.ambient = glm::vec3(1.0f);
        m.diffuse = glm::vec4(0.8f, 0.8f, 0.8f, 1.0f);
        m.emissive = glm::vec3(0.0f);
        st->blend.set(BlendMode::Off);
        p->setStateSet(st);
        return placed(p, glm::translate(glm::mat4(1.0f), at));
    };
    const auto render = [&](float sunColour) {
        auto sun = Light::create(LightType::Directional);
        sun->direction = {0, 0, -1};
        sun->color = glm::vec3(sunColour);
        auto ambient = Light::create(LightType::Ambient);
        ambient->color = glm::vec3(0.2f);
        auto shadows = ShadowNode::create(sun);
        shadows->addChild(sprite({-1.5f, 0.0f, 0.5f})); // under the slab
        shadows->addChild(sprite({1.5f, 0.0f, 0.5f}));  // in the sun
        shadows->addChild(placed(lambert(shapes::box({3.0f, 3.0f, 0.1f})),
                                 glm::translate(glm::mat4(1.0f), glm::vec3(-1.5f, 0.0f, 3.0f))));
        auto root = Group::create();
        root->addChild(sun);
        root->addChild(ambient);
        root->addChild(shadows);
        auto v = orthoTopViewer(kSize, float(kHalf));
        v->camera()->projectionMatrix =
            glm::ortho(-float(kHalf), float(kHalf), -float(kHalf), float(kHalf), 7.5f,
                       9.7f); // z from 0.3 to 2.5: the sprites, not the slab
        v->renderer().options().colorTarget = RendererOptions::ColorTarget::Rgba32F;
        v->setSceneData(root);
        v->frame(0.0);
        expectNoGlErrors(*v);
        return v->renderer().readPixelsLinear();
    };
    const FloatImage sunny = render(1.0f), dark = render(0.0f);
    // Pixel centres of the two sprites: world x = ∓1.5, y = 0.
    const int left = int((kHalf - 1.5) / kPixel), right = int((kHalf + 1.5) / kPixel), row = kSize / 2;
    const double ambientOnly = red(dark, left, row);
    ASSERT_GT(ambientOnly, 0.01);
    EXPECT_NEAR(red(sunny, left, row), ambientOnly, 0.02 * ambientOnly);
    EXPECT_NEAR(red(dark, right, row), ambientOnly, 0.02 * ambientOnly);
    EXPECT_GT(red(sunny, right, row), ambientOnly + 0.3);
}

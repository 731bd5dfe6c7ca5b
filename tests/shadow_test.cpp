// ShadowNode (issue 28): sun shadows against geometry computed here without the shadow code.
// Most scenes are a white Lambert plane seen from straight above (orthographic), lit by the sun
// alone with colour 1 and no ambient light, so a pixel is (N·L)·v and the visibility v is read off
// the float image. Expected shadows are the casters' corners projected along the light onto the
// plane (p − L·p.z/L.z), their convex hull mapped to pixels. Also, without GL: the core's pieces
// shadows build on (EffectNode::subtreeMask, FramePlan::places, FrameSetup::cullForLight).
#include "TestUtil.h"

#include <sgfx/CullVisitor.h>
#include <sgfx/FrameSetup.h>
#include <sgfx/Geometry.h>
#include <sgfx/Group.h>
#include <sgfx/LOD.h>
#include <sgfx/Shapes.h>
#include <sgfx/nodes/shadow/ShadowNode.h>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

using namespace sgfx;
using namespace sgfx::test;

namespace {

constexpr int kSize = 128;
constexpr double kHalf = 4.0; // the view shows [−4, 4]² metres: a pixel is 1/16 m

double deg(double d) {
    return d * std::numbers::pi / 180.0;
}

glm::dvec3 sunVector(double azimuthDeg, double elevationDeg) {
    const double a = deg(azimuthDeg), e = deg(elevationDeg);
    return {std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e)};
}

// The world point (z = 0) under pixel (x, y) of the float image (row 0 at the top).
glm::dvec2 worldOfPixel(int x, int y) {
    const double s = 2.0 * kHalf / kSize;
    return {-kHalf + (x + 0.5) * s, kHalf - (y + 0.5) * s};
}

double red(const FloatImage& img, int x, int y) {
    return img.rgba[(std::size_t(y) * std::size_t(img.width) + std::size_t(x)) * 4];
}

std::shared_ptr<Geometry> lambert(std::shared_ptr<Geometry> g, glm::vec3 albedo = glm::vec3(1.0f)) {
    auto m = Material::create();
    m->diffuse = glm::vec4(albedo, 1.0f);
    m->specular = glm::vec3(0.0f);
    g->getOrCreateStateSet().material.set(m);
    return g;
}

std::shared_ptr<Transform> placed(std::shared_ptr<Node> n, const glm::mat4& m) {
    auto t = Transform::create(m);
    t->addChild(std::move(n));
    return t;
}

std::shared_ptr<Light> sunLight(const glm::dvec3& towardsSun) {
    auto l = Light::create(LightType::Directional);
    l->direction = -glm::vec3(towardsSun); // the way the light travels
    l->color = glm::vec3(1.0f);
    return l;
}

// The top view: a float target, an orthographic camera 10 m up whose depth range [5, 15] keeps
// the cascade small (a texel ≈ 0.12 pixel), and no light but the scene's.
std::unique_ptr<Viewer> topViewer(int unrolledLights = 8) {
    auto v = orthoTopViewer(kSize, float(kHalf));
    v->camera()->projectionMatrix =
        glm::ortho(-float(kHalf), float(kHalf), -float(kHalf), float(kHalf), 5.0f, 15.0f);
    v->renderer().options().colorTarget = RendererOptions::ColorTarget::Rgba32F;
    v->renderer().options().maxUnrolledLights = unrolledLights;
    return v;
}

// ---- the expected shadow: a convex hull of projected points, and pixel classes against it

using Hull = std::vector<glm::dvec2>;

double cross(const glm::dvec2& o, const glm::dvec2& a, const glm::dvec2& b) {
    return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
}

// Andrew's monotone chain, counter-clockwise.
Hull convexHull(std::vector<glm::dvec2> p) {
    std::sort(p.begin(), p.end(), [](auto a, auto b) { return a.x < b.x || (a.x == b.x && a.y < b.y); });
    Hull h(2 * p.size());
    std::size_t k = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
        while (k >= 2 && cross(h[k - 2], h[k - 1], p[i]) <= 0)
            --k;
        h[k++] = p[i];
    }
    for (std::size_t i = p.size() - 1, t = k + 1; i-- > 0;) {
        while (k >= t && cross(h[k - 2], h[k - 1], p[i]) <= 0)
            --k;
        h[k++] = p[i];
    }
    h.resize(k - 1);
    return h;
}

// Signed distance to the hull's boundary: negative inside.
double signedDistance(const Hull& h, const glm::dvec2& q) {
    double inside = -1e30, edge = 1e30;
    for (std::size_t i = 0; i < h.size(); ++i) {
        const glm::dvec2 a = h[i], b = h[(i + 1) % h.size()], ab = b - a;
        const double t = std::clamp(glm::dot(q - a, ab) / glm::dot(ab, ab), 0.0, 1.0);
        edge = std::min(edge, glm::length(q - (a + t * ab)));
        inside = std::max(inside, cross(a, b, q) / glm::length(ab) * -1.0);
    }
    return inside <= 0.0 ? -edge : edge;
}

// The corners of an axis-aligned box, projected along L onto z = 0.
Hull boxShadow(const glm::dvec3& lo, const glm::dvec3& hi, const glm::dvec3& L) {
    std::vector<glm::dvec2> p;
    for (int c = 0; c < 8; ++c) {
        const glm::dvec3 q(c & 1 ? hi.x : lo.x, c & 2 ? hi.y : lo.y, c & 4 ? hi.z : lo.z);
        p.push_back(glm::dvec2(q - L * (q.z / L.z)));
    }
    return convexHull(p);
}

struct Classified {
    int shadowed = 0, lit = 0, wrong = 0;
};

// Pixels of the plane more than `margin` pixels from the hull's edge and outside the footprint
// `skip` (what covers the plane in the view): inside the hull v < 0.5, outside v > 0.5, where
// v = pixel / (N·L).
Classified classify(const FloatImage& img, const Hull& shadow, const Hull& skip, double cosSun,
                    double margin = 1.0) {
    Classified c;
    const double px = 2.0 * kHalf / kSize;
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) {
            const glm::dvec2 w = worldOfPixel(x, y);
            if (!skip.empty() && signedDistance(skip, w) < margin * px) continue;
            const double d = signedDistance(shadow, w);
            if (std::abs(d) < margin * px) continue;
            const double v = red(img, x, y) / cosSun;
            const bool dark = v < 0.5;
            (d < 0 ? c.shadowed : c.lit) += 1;
            if (dark != (d < 0) && ++c.wrong <= 5)
                ADD_FAILURE() << "pixel " << x << "," << y << " (" << w.x << ", " << w.y << "): v = " << v
                              << ", " << (d < 0 ? "inside" : "outside") << " the shadow by "
                              << std::abs(d) / px << " px";
        }
    return c;
}

// A white plane over the view, a box (lo..hi) above it, under a ShadowNode lit by a sun towards L.
struct BoxScene {
    std::shared_ptr<Group> root = Group::create();
    std::shared_ptr<ShadowNode> shadows;
    std::shared_ptr<Geometry> plane, box;

    BoxScene(const glm::dvec3& L, const glm::dvec3& lo, const glm::dvec3& hi, const ShadowOptions& o) {
        auto sun = sunLight(L);
        root->addChild(sun);
        shadows = ShadowNode::create(sun, o);
        plane = lambert(shapes::quad(12.0f, 12.0f));
        box = lambert(shapes::box(glm::vec3(hi - lo)));
        shadows->addChild(plane);
        shadows->addChild(placed(box, glm::translate(glm::mat4(1.0f), glm::vec3((lo + hi) * 0.5))));
        root->addChild(shadows);
    }
};

FloatImage render(Viewer& v, std::shared_ptr<Node> scene) {
    v.setSceneData(std::move(scene));
    v.frame();
    expectNoGlErrors(v);
    return v.renderer().readPixelsLinear();
}

Hull footprint(const glm::dvec3& lo, const glm::dvec3& hi) {
    return {{lo.x, lo.y}, {hi.x, lo.y}, {hi.x, hi.y}, {lo.x, hi.y}};
}

} // namespace

// ---------------------------------------------------------------------------- the core, no GL

namespace {

class MaskedEffect : public EffectNode {
public:
    explicit MaskedEffect(NodeMask mask)
        : mask_(mask) {
        snippet_.name = "masked";
    }
    std::string_view kind() const override { return "masked"; }
    const ShaderSnippet& snippet() const override { return snippet_; }
    NodeMask subtreeMask() const override { return mask_; }

private:
    NodeMask mask_;
    ShaderSnippet snippet_;
};

bool hasEffect(const RenderQueue& q, const RenderItem& item, const EffectNode* e) {
    const auto& set = q.effectSets[item.effectSet].effects;
    return std::find(set.begin(), set.end(), e) != set.end();
}

std::shared_ptr<Camera> lookingDownZ() {
    auto c = Camera::create();
    c->setViewport(0, 0, 100, 100);
    c->setPerspective(60.0f, 0.5f, 100.0f);
    c->viewMatrix = glm::lookAt(glm::vec3(0, 0, 20), glm::vec3(0), glm::vec3(0, 1, 0));
    return c;
}

} // namespace

TEST(ShadowCore, SubtreeMaskDropsTheEffectBelowANodeWithoutItsBit) {
    auto camera = lookingDownZ();
    auto effect = std::make_shared<MaskedEffect>(1u << 31);
    auto kept = shapes::box({1, 1, 1}), dropped = shapes::box({1, 1, 1}), below = shapes::box({1, 1, 1});
    kept->name = "kept", dropped->name = "dropped", below->name = "below";
    dropped->nodeMask = ~(1u << 31); // visible, but not a receiver
    auto group = Group::create();
    group->nodeMask = ~(1u << 31);
    group->addChild(below); // its own mask has the bit: the group's decides for the subtree
    effect->addChild(kept);
    effect->addChild(dropped);
    effect->addChild(group);
    camera->addChild(effect);
    RenderQueue q;
    CullVisitor cv(*camera, q);
    cv.run(*camera);
    ASSERT_EQ(q.opaque.size(), 3u);
    for (const RenderItem& item : q.opaque)
        EXPECT_EQ(hasEffect(q, item, effect.get()), item.geometry == kept.get()) << item.node().name;
}

TEST(ShadowCore, PlacesAndCullFromALightFindCastersOutsideTheView) {
    auto camera = lookingDownZ();
    auto effect = std::make_shared<MaskedEffect>(~0u);
    auto inView = shapes::box({1, 1, 1}), outside = shapes::box({1, 1, 1}), hidden = shapes::box({1, 1, 1});
    inView->name = "in view", outside->name = "outside", hidden->name = "not a caster";
    effect->addChild(inView);
    effect->addChild(placed(outside, glm::translate(glm::mat4(1.0f), glm::vec3(40, 0, 0))));
    hidden->nodeMask = ~(1u << 30);
    effect->addChild(hidden);
    auto shifted = placed(effect, glm::translate(glm::mat4(1.0f), glm::vec3(0, 0, 1)));
    camera->addChild(shifted);
    RenderQueue q;
    FramePlan plan;
    CullVisitor cv(*camera, q, &plan);
    cv.run(*camera);
    ASSERT_EQ(plan.places.size(), 1u);
    EXPECT_EQ(plan.places[0].node, effect.get());
    EXPECT_EQ(plan.places[0].model[3], glm::vec4(0, 0, 1, 1));
    EXPECT_EQ(q.opaque.size(), 2u); // the camera sees one box and the one under the mask

    ViewInfo info;
    info.viewSize = {100, 100};
    info.view = camera->viewMatrix;
    info.projection = camera->projectionMatrix;
    FrameSetup setup(info, q, &plan);
    // A light straight above, seeing x in [−50, 50]: both boxes; the mask keeps out the third.
    RenderQueue casters;
    setup.cullForLight(*effect,
                       {glm::lookAt(glm::vec3(0, 0, 50), glm::vec3(0), glm::vec3(0, 1, 0)),
                        glm::ortho(-50.0f, 50.0f, -10.0f, 10.0f, 1.0f, 100.0f), 1u << 30},
                       casters);
    std::vector<std::string> names;
    for (const RenderItem& item : casters.opaque)
        names.push_back(item.node().name);
    std::sort(names.begin(), names.end());
    EXPECT_EQ(names, (std::vector<std::string>{"in view", "outside"}));
    for (const RenderItem& item : casters.opaque)
        if (item.node().name == "in view") {
            EXPECT_EQ(item.model[3], glm::vec4(0, 0, 1, 1));
        }
    const BoundingSphere b = setup.worldBound(*effect);
    EXPECT_TRUE(b.valid());
    EXPECT_LE(glm::distance(glm::vec3(40, 0, 1), b.center), b.radius - 0.5f); // holds the far box
}

// A cull from a light picks LOD children by their size in the camera's view (the reference
// view), so the shadow is cast by what is drawn, not by what the light's scale would pick.
TEST(ShadowCore, LightCullPicksLevelsOfDetailAsTheCameraSeesThem) {
    auto camera = lookingDownZ();
    auto effect = std::make_shared<MaskedEffect>(~0u);
    auto lod = LOD::create();
    auto fine = shapes::box({1, 1, 1}), coarse = shapes::box({1, 1, 1});
    fine->name = "fine", coarse->name = "coarse";
    lod->addChild(fine, 5.0f, 1e9f); // the camera 20 m away sees the box at 7.5 px
    lod->addChild(coarse, 0.0f, 5.0f);
    effect->addChild(lod);
    camera->addChild(effect);
    RenderQueue q;
    FramePlan plan;
    CullVisitor cv(*camera, q, &plan);
    cv.run(*camera);
    ASSERT_EQ(q.opaque.size(), 1u);
    ASSERT_EQ(q.opaque[0].node().name, "fine");
    ViewInfo info;
    info.viewSize = {100, 100};
    info.view = camera->viewMatrix;
    info.projection = camera->projectionMatrix;
    FrameSetup setup(info, q, &plan);
    RenderQueue casters;
    // The light's own view (1 km across 100 px) would measure 0.2 px: coarse.
    setup.cullForLight(*effect,
                       {glm::lookAt(glm::vec3(0, 0, 5000), glm::vec3(0), glm::vec3(0, 1, 0)),
                        glm::ortho(-500.0f, 500.0f, -500.0f, 500.0f, 1.0f, 10000.0f)},
                       casters);
    ASSERT_EQ(casters.opaque.size(), 1u);
    EXPECT_EQ(casters.opaque[0].node().name, "fine");
}

// ---------------------------------------------------------------------------- options

TEST(ShadowOptions, ValidateNamesTheFieldAndKeepsTheOldOptions) {
    auto node = ShadowNode::create();
    ShadowOptions o;
    o.cascades = 5;
    try {
        node->setOptions(o);
        FAIL() << "cascades = 5 accepted";
    } catch (const std::invalid_argument& e) {
        EXPECT_STREQ(e.what(), "sgfx: ShadowOptions: cascades = 5 is outside [1, 4]");
    }
    EXPECT_EQ(node->options().cascades, 3);
    o = {};
    o.mapSize = 1000;
    EXPECT_THROW(node->setOptions(o), std::invalid_argument);
    o = {};
    o.pcfRadius = std::nanf("");
    EXPECT_THROW(node->setOptions(o), std::invalid_argument);
    o = {};
    o.receiveMask = 0;
    EXPECT_THROW(node->setOptions(o), std::invalid_argument);
    auto point = Light::create(LightType::Point);
    point->name = "lamp";
    EXPECT_THROW(node->setSun(point), std::invalid_argument);
    EXPECT_EQ(node->sun(), nullptr);
}

// ---------------------------------------------------------------------------- rendered

// Test 1 of the plan: a box over a plane under 12 suns (azimuth 0°..330°, elevations 25°, 45°,
// 70° in turn). Outside the box's footprint and 1 pixel of the expected hull's edge, a pixel is
// dark exactly where the hull says, for both filters and through the light list too.
TEST(ShadowRender, BoxOverPlaneCastsItsProjectionUnderTwelveSuns) {
    const glm::dvec3 lo(-0.6, -0.4, 0.5), hi(0.4, 0.6, 1.1);
    for (const ShadowFilter filter : {ShadowFilter::Hard2x2, ShadowFilter::Pcf})
        for (int unrolled : {8, 0})
            for (int k = 0; k < 12; ++k) {
                const double elevation = k % 3 == 0 ? 25.0 : k % 3 == 1 ? 45.0 : 70.0;
                const glm::dvec3 L = sunVector(30.0 * k, elevation);
                SCOPED_TRACE(::testing::Message() << "filter " << int(filter) << ", unrolled " << unrolled
                                                  << ", azimuth " << 30 * k << ", elevation " << elevation);
                ShadowOptions o;
                o.cascades = 1;
                o.filter = filter;
                BoxScene scene(L, lo, hi, o);
                auto v = topViewer(unrolled);
                const FloatImage img = render(*v, scene.root);
                const Classified c = classify(img, boxShadow(lo, hi, L), footprint(lo, hi), L.z);
                EXPECT_EQ(c.wrong, 0);
                EXPECT_GT(c.shadowed, 40); // the shadow is seen (at 70° mostly under the box)
                EXPECT_GT(c.lit, 5000);
                const ShadowFrameInfo info = scene.shadows->lastFrame();
                EXPECT_TRUE(info.active);
                ASSERT_EQ(info.casters.size(), 1u);
                EXPECT_EQ(info.casters[0], 2u); // plane and box
            }
}

// Masks: a box whose casts bit is cleared throws no shadow; a plane whose receives bit is cleared
// stays lit under a box that casts.
TEST(ShadowRender, CastAndReceiveBitsOptOut) {
    const glm::dvec3 lo(-0.5, -0.5, 0.5), hi(0.5, 0.5, 1.0), L = sunVector(40.0, 50.0);
    for (int which = 0; which < 2; ++which) {
        ShadowOptions o;
        o.cascades = 1;
        BoxScene scene(L, lo, hi, o);
        (which == 0 ? scene.box->nodeMask : scene.plane->nodeMask) &=
            ~(which == 0 ? shadow::kCasts : shadow::kReceives);
        auto v = topViewer();
        const FloatImage img = render(*v, scene.root);
        const Classified c =
            classify(img, Hull{{-100, -100}, {-99, -100}, {-99, -99}}, footprint(lo, hi), L.z);
        EXPECT_EQ(c.wrong, 0) << (which == 0 ? "box without kCasts" : "plane without kReceives");
    }
}

// Without a sun, or with one that is not in the view's graph, everything is lit and no map is
// drawn beyond the 1×1 placeholder the materials bind.
TEST(ShadowRender, NoSunMeansNoShadow) {
    const glm::dvec3 lo(-0.5, -0.5, 0.5), hi(0.5, 0.5, 1.0), L = sunVector(40.0, 50.0);
    BoxScene scene(L, lo, hi, ShadowOptions{});
    scene.shadows->setSun(sunLight(L)); // a light that is nowhere in the scene
    auto v = topViewer();
    const FloatImage img = render(*v, scene.root);
    const Classified c = classify(img, Hull{{-100, -100}, {-99, -100}, {-99, -99}}, footprint(lo, hi), L.z);
    EXPECT_EQ(c.wrong, 0);
    EXPECT_FALSE(scene.shadows->lastFrame().active);
}

// ShadowNode (issue 28): sun shadows against geometry computed here without the shadow code.
// Most scenes are a white Lambert plane seen from straight above (orthographic), lit by the sun
// alone with colour 1 and no ambient light, so a pixel is (N·L)·v and the visibility v is read off
// the float image. Expected shadows are the casters' corners projected along the light onto the
// plane (p − L·p.z/L.z), their convex hull mapped to pixels. Also, without GL: the core's pieces
// shadows build on (EffectNode::subtreeMask, FramePlan::places, FrameSetup::cullForLight).
#include "ShadowTestUtil.h"

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
using namespace sgfx::test::shadows;

namespace {

constexpr int kSize = 128;
constexpr double kHalf = 4.0; // the view shows [−4, 4]² metres: a pixel is 1/16 m

// The world point (z = 0) under pixel (x, y) of the float image (row 0 at the top).
glm::dvec2 worldOfPixel(int x, int y) {
    const double s = 2.0 * kHalf / kSize;
    return {-kHalf + (x + 0.5) * s, kHalf - (y + 0.5) * s};
}

std::shared_ptr<Light> sunLight(const glm::dvec3& towardsSun) {
    auto l = Light::create(LightType::Directional);
    l->direction = -glm::vec3(towardsSun); // the way the light travels
    l->color = glm::vec3(1.0f);
    return l;
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
    return shadows::footprint(boxCorners(lo, hi));
}

Hull boxShadow(const glm::dvec3& lo, const glm::dvec3& hi, const glm::dvec3& L) {
    return projected(boxCorners(lo, hi), L);
}

std::unique_ptr<Viewer> topViewer(int unrolledLights = 8) {
    return shadows::topViewer(kSize, kHalf, unrolledLights);
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

// What the renderer tells the setup of a 100×100 view from `camera`.
ViewInfo viewOf(const Camera& camera) {
    ViewInfo info;
    info.viewSize = {100, 100};
    info.view = camera.viewMatrix;
    info.projection = camera.projectionMatrix;
    return info;
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

    FrameSetup setup(viewOf(*camera), q, &plan);
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
    FrameSetup setup(viewOf(*camera), q, &plan);
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

// Test 2 of the plan: no acne. A lone plane, lit at 0°..87° from its normal, shadows nothing of
// itself: seen from above (one cascade) every pixel is cos θ within 2/255, and seen from a low
// camera over 4 cascades every pixel equals the same view without the ShadowNode within 2/255.
// Negative control: with no bias and no normal offset the same planes do show acne.
TEST(ShadowRender, PlaneLitAtAnyAngleHasNoAcne) {
    for (const bool unbiased : {false, true})
        for (const ShadowFilter filter : {ShadowFilter::Hard2x2, ShadowFilter::Pcf})
            for (const int tilt : unbiased ? std::vector<int>{40, 70}
                                           : std::vector<int>{0, 10, 20, 30, 40, 50, 60, 70, 80, 85, 87}) {
                SCOPED_TRACE(::testing::Message()
                             << "filter " << int(filter) << ", tilt " << tilt << ", unbiased " << unbiased);
                const glm::dvec3 L = sunVector(25.0 + tilt, 90.0 - tilt);
                auto sun = sunLight(L);
                ShadowOptions o;
                o.cascades = 1;
                o.filter = filter;
                if (unbiased) o.constantBias = o.slopeBias = o.normalOffset = 0.0f;
                auto shadows = ShadowNode::create(sun, o);
                shadows->addChild(lambert(shapes::quad(12.0f, 12.0f)));
                auto root = Group::create();
                root->addChild(sun);
                root->addChild(shadows);
                auto v = topViewer();
                const FloatImage img = render(*v, root);
                int acne = 0;
                for (int y = 0; y < kSize; ++y)
                    for (int x = 0; x < kSize; ++x)
                        if (std::abs(red(img, x, y) - L.z) > 2.0 / 255.0 && ++acne <= 3 && !unbiased)
                            ADD_FAILURE()
                                << "pixel " << x << "," << y << ": " << red(img, x, y) << ", want " << L.z;
                if (unbiased) {
                    EXPECT_GT(acne, kSize * kSize / 20);
                } else {
                    EXPECT_EQ(acne, 0);
                }
            }
}

namespace {

// A camera `height` metres over the plane looking along +Y, pitched down by `pitch` degrees.
void lowCamera(Viewer& v, double height, double pitchDeg, float fovy, float zFar) {
    Camera& c = *v.camera();
    const glm::vec3 eye(0.0f, 0.0f, float(height));
    const glm::vec3 dir(0.0f, float(std::cos(deg(pitchDeg))), -float(std::sin(deg(pitchDeg))));
    c.setLookAt(eye, eye + dir, {0, 0, 1});
    c.setPerspective(fovy, 0.1f, zFar);
}

// The red channels of a render with the shadow node and one with it disabled: v per pixel.
struct Pair {
    FloatImage shadowed, plain;
    double visibility(int x, int y) const {
        const double p = red(plain, x, y);
        return p > 1e-4 ? red(shadowed, x, y) / p : 1.0;
    }
};

Pair renderPair(Viewer& v, const std::shared_ptr<Group>& root, ShadowNode& node) {
    Pair p;
    p.shadowed = render(v, root);
    node.enabled = false;
    p.plain = render(v, root);
    node.enabled = true;
    return p;
}

} // namespace

TEST(ShadowRender, GrazingViewOverFourCascadesHasNoAcne) {
    for (const ShadowFilter filter : {ShadowFilter::Hard2x2, ShadowFilter::Pcf})
        for (int tilt : {0, 40, 70, 80}) {
            SCOPED_TRACE(::testing::Message() << "filter " << int(filter) << ", tilt " << tilt);
            const glm::dvec3 L = sunVector(60.0, 90.0 - tilt);
            auto sun = sunLight(L);
            ShadowOptions o;
            o.cascades = 4;
            o.filter = filter;
            o.maxDistance = 150.0f;
            auto shadows = ShadowNode::create(sun, o);
            shadows->addChild(lambert(shapes::quad(400.0f, 400.0f)));
            auto root = Group::create();
            root->addChild(sun);
            root->addChild(shadows);
            auto v = Viewer::createHeadless(160, 120);
            v->renderer().options().colorTarget = RendererOptions::ColorTarget::Rgba32F;
            lowCamera(*v, 1.7, 8.0, 50.0f, 300.0f);
            const Pair p = renderPair(*v, root, *shadows);
            int acne = 0;
            for (int y = 0; y < 120; ++y)
                for (int x = 0; x < 160; ++x)
                    if (red(p.plain, x, y) - red(p.shadowed, x, y) > 2.0 / 255.0 && ++acne <= 3)
                        ADD_FAILURE() << "pixel " << x << "," << y << ": " << red(p.shadowed, x, y)
                                      << " against " << red(p.plain, x, y);
            EXPECT_EQ(acne, 0);
            EXPECT_EQ(shadows->lastFrame().casters.size(), 4u);
        }
}

// Test 4 of the plan: a pole's long shadow runs away from a low camera across all 4 cascades
// with no gap (every point of its predicted centreline is dark) and no double (every image row
// that crosses it has one dark run), also at each split depth.
TEST(ShadowRender, PoleShadowIsContinuousAcrossCascades) {
    const glm::dvec3 L = glm::normalize(glm::dvec3(0.0, -std::cos(deg(10.0)), std::sin(deg(10.0))));
    for (const ShadowFilter filter : {ShadowFilter::Hard2x2, ShadowFilter::Pcf}) {
        SCOPED_TRACE(::testing::Message() << "filter " << int(filter));
        auto sun = sunLight(L);
        ShadowOptions o;
        o.cascades = 4;
        o.filter = filter;
        auto shadows = ShadowNode::create(sun, o);
        shadows->addChild(lambert(shapes::quad(400.0f, 400.0f)));
        const glm::dvec3 base(3.0, 12.0, 0.0);
        shadows->addChild(placed(lambert(shapes::box({1.5f, 1.5f, 30.0f})),
                                 glm::translate(glm::mat4(1.0f), glm::vec3(base) + glm::vec3(0, 0, 15))));
        auto root = Group::create();
        root->addChild(sun);
        root->addChild(shadows);
        constexpr int W = 256, H = 256;
        auto v = Viewer::createHeadless(W, H);
        v->renderer().options().colorTarget = RendererOptions::ColorTarget::Rgba32F;
        lowCamera(*v, 1.7, 3.0, 40.0f, 400.0f);
        const Pair p = renderPair(*v, root, *shadows);
        const glm::dmat4 vp = glm::dmat4(v->camera()->projectionMatrix) * glm::dmat4(v->camera()->viewMatrix);
        const auto toPixel = [&](const glm::dvec3& w) {
            const glm::dvec4 c = vp * glm::dvec4(w, 1.0);
            return glm::ivec2(int((c.x / c.w * 0.5 + 0.5) * W), int((0.5 - c.y / c.w * 0.5) * H));
        };
        // The centreline: the pole's axis projected along L, from where the pole stops hiding it
        // (4 m behind) to 150 m.
        int gaps = 0;
        for (double s = 6.0; s <= 150.0; s += 0.25) {
            const glm::ivec2 q = toPixel(base + glm::dvec3(0.0, s, 0.0));
            if (p.visibility(q.x, q.y) >= 0.5 && ++gaps <= 5)
                ADD_FAILURE() << "gap at " << s << " m behind the pole, pixel " << q.x << "," << q.y
                              << ": v = " << p.visibility(q.x, q.y);
        }
        EXPECT_EQ(gaps, 0);
        const int first = toPixel(base + glm::dvec3(0, 150.0, 0)).y,
                  last = toPixel(base + glm::dvec3(0, 6.0, 0)).y;
        ASSERT_LT(first + 20, last);
        int doubles = 0;
        for (int y = first; y <= last; ++y) {
            int runs = 0;
            for (int x = 1; x < W; ++x)
                runs += p.visibility(x, y) < 0.5 && !(p.visibility(x - 1, y) < 0.5);
            if (runs != 1 && ++doubles <= 5) ADD_FAILURE() << "row " << y << " has " << runs << " dark runs";
        }
        EXPECT_EQ(doubles, 0);
        const ShadowFrameInfo info = shadows->lastFrame();
        ASSERT_EQ(info.splits.size(), 5u);
        EXPECT_LT(info.splits[3], 150.0); // the checked stretch crosses every split
    }
}

namespace {

// A top view of a white plane at z = 0 under the sun straight above, with a slab that the camera
// does not see (above its near plane) casting a straight edge at x = edgeX: v(x) is read per
// column. The camera spans [−half, half]² over `size` pixels, depth [9, 11] from z = 10.
struct EdgeScene {
    std::shared_ptr<Group> root = Group::create();
    std::shared_ptr<ShadowNode> shadows;

    EdgeScene(double edgeX, const ShadowOptions& o, const glm::dvec3& L = {0, 0, 1}, double top = 2.1,
              double thickness = 0.2) {
        auto sun = sunLight(L);
        root->addChild(sun);
        shadows = ShadowNode::create(sun, o);
        shadows->addChild(lambert(shapes::quad(6.0f, 6.0f)));
        shadows->addChild(placed(lambert(shapes::box({5.0f, 6.0f, float(thickness)})),
                                 glm::translate(glm::mat4(1.0f), glm::vec3(float(edgeX) - 2.5f, 0.0f,
                                                                           float(top - thickness / 2)))));
        root->addChild(shadows);
    }
};

std::unique_ptr<Viewer> edgeViewer(int size, float half, const glm::vec2& shift = glm::vec2(0.0f),
                                   float depthHalf = 1.0f) {
    auto v = Viewer::createHeadless(size, size);
    v->renderer().options().colorTarget = RendererOptions::ColorTarget::Rgba32F;
    Camera& c = *v->camera();
    c.setLookAt(glm::vec3(shift, 10.0f), glm::vec3(shift, 0.0f), {0, 1, 0});
    c.projectionMatrix = glm::ortho(-half, half, -half, half, 10.0f - depthHalf, 10.0f + depthHalf);
    return v;
}

// Mean red over rows [y0, y1) per column.
std::vector<double> columnMeans(const FloatImage& img, int y0, int y1) {
    std::vector<double> m(std::size_t(img.width), 0.0);
    for (int x = 0; x < img.width; ++x) {
        for (int y = y0; y < y1; ++y)
            m[std::size_t(x)] += red(img, x, y);
        m[std::size_t(x)] /= (y1 - y0);
    }
    return m;
}

// Distance in pixels between where a rising profile crosses 0.1 and 0.9 (linear between columns).
double width1090(const std::vector<double>& v) {
    const auto cross = [&](double level) {
        for (std::size_t x = 1; x < v.size(); ++x)
            if (v[x - 1] < level && v[x] >= level)
                return double(x - 1) + (level - v[x - 1]) / (v[x] - v[x - 1]);
        return -1.0;
    };
    return cross(0.9) - cross(0.1);
}

// A shadow edge's profile (v per column, rising towards the lit side) against the quadrature of
// 16 Poisson taps at radius |p_k|·R texels, each turned by a uniformly random angle and read
// through the hardware's bilinear comparison (a one-texel ramp across the texel-quantised edge):
// E[v](x) = 1/16 Σ_k ⟨ramp(x − e + |p_k|·R·t·cos φ)⟩_φ. R = 0: the ramp alone. The edge e is
// fitted by least squares. `t`: a texel in pixels.
struct PenumbraFit {
    double edge = 0.0;                      ///< column of the fitted edge
    double worst = 0.0;                     ///< largest |measured − expected| over the columns
    double widthGot = 0.0, widthWant = 0.0; ///< 10–90 % widths, pixels
};

PenumbraFit fitPenumbra(const std::vector<double>& got, double t, double R) {
    const auto ramp = [&](double u) { return std::clamp(u / t + 0.5, 0.0, 1.0); };
    // Tabulated over [−60, 60] pixels every 1/50 pixel (the fit reads it thousands of times).
    std::vector<double> table(6001);
    for (std::size_t i = 0; i < table.size(); ++i) {
        const double x = -60.0 + double(i) / 50.0;
        double sum = 0.0;
        constexpr int kSteps = 256;
        for (const glm::dvec2& p : shadow::poissonDisc())
            for (int s = 0; s < kSteps; ++s)
                sum +=
                    ramp(x + glm::length(p) * R * t * std::cos(2.0 * std::numbers::pi * (s + 0.5) / kSteps));
        table[i] = R == 0.0 ? ramp(x) : sum / (16.0 * kSteps);
    }
    const auto expected = [&](double x) {
        const double i = std::clamp((x + 60.0) * 50.0, 0.0, 6000.0);
        const auto lo = std::size_t(i);
        const double f = i - double(lo);
        return lo >= 6000 ? table[6000] : table[lo] * (1.0 - f) + table[lo + 1] * f;
    };
    const int n = int(got.size());
    PenumbraFit fit;
    double bestErr = 1e30;
    for (double e = n / 2.0 - 8.0; e <= n / 2.0 + 8.0; e += 0.02) {
        double err = 0.0;
        for (int c = n / 2 - 50; c < n / 2 + 50; ++c)
            err += std::pow(got[std::size_t(c)] - expected(c + 0.5 - e), 2.0);
        if (err < bestErr) bestErr = err, fit.edge = e;
    }
    std::vector<double> want(got.size());
    for (int c = 0; c < n; ++c) {
        want[std::size_t(c)] = expected(c + 0.5 - fit.edge);
        fit.worst = std::max(fit.worst, std::abs(got[std::size_t(c)] - want[std::size_t(c)]));
    }
    fit.widthGot = width1090(got);
    fit.widthWant = width1090(want);
    return fit;
}

} // namespace

// Test 6 of the plan: the PCF penumbra of a straight edge, averaged over 64 rows, against an
// independent quadrature: each of the 16 taps at radius ρ_k = |p_k|·R·t turns with a uniformly
// random angle, and reads the hardware's bilinear comparison, a one-texel ramp across the
// texel-quantised edge. E[v](x) = 1/16 Σ_k ⟨ramp(x − e + ρ_k cos φ)⟩_φ. The edge e is fitted (the
// map quantises it to a texel boundary); the profile must then match within 0.03 per column and
// its 10–90 % width within a pixel. Hard2x2: the ramp alone, 10–90 % = 0.8 t.
TEST(ShadowRender, PcfPenumbraMatchesTheRotatedDiscQuadrature) {
    constexpr int kPx = 256;
    constexpr float kHalfView = 1.0f;
    const double px = 2.0 * kHalfView / kPx;
    for (const ShadowFilter filter : {ShadowFilter::Pcf, ShadowFilter::Hard2x2}) {
        SCOPED_TRACE(::testing::Message() << "filter " << int(filter));
        ShadowOptions o;
        o.cascades = 1;
        o.mapSize = 256;
        o.filter = filter;
        o.pcfRadius = 3.0f;
        o.pcfEarlyOut = false;
        EdgeScene scene(0.013, o);
        auto v = edgeViewer(kPx, kHalfView);
        const FloatImage img = render(*v, scene.root);
        const double t = scene.shadows->lastFrame().texels.at(0) / px; // texel in pixels
        ASSERT_GT(t, 1.0);
        const double R = filter == ShadowFilter::Pcf ? 3.0 : 0.0;
        const PenumbraFit fit = fitPenumbra(columnMeans(img, 96, 160), t, R);
        EXPECT_LE(fit.worst, 0.03) << "edge fitted at column " << fit.edge;
        EXPECT_NEAR(fit.widthGot, fit.widthWant, 1.0);
        if (R == 0.0) {
            EXPECT_NEAR(fit.widthGot, 0.8 * t, 0.5);
        }
        // The edge lies within a texel of the slab's (x = 0.013 m).
        EXPECT_NEAR(-kHalfView + fit.edge * px, 0.013, t * px);
    }
}

// Test 7 of the plan: PCSS penumbrae grow with the blocker's height as the similar triangles say.
// A slab's edge h = 0.5, 1, 2, 4 m over the plane, the sun overhead with α = 0.05 rad: the filter
// radius is ρ = h·tan α, so the profile is the rotated-disc quadrature of radius ρ (as for PCF),
// its 10–90 % width within 15 % + 1 pixel of it, and the widths grow in proportion to h.
TEST(ShadowRender, PcssPenumbraGrowsWithTheBlockersHeight) {
    constexpr int kPx = 256;
    constexpr float kHalfView = 1.0f;
    const double px = 2.0 * kHalfView / kPx, tanA = std::tan(0.05);
    std::vector<double> widths;
    for (const double h : {0.5, 1.0, 2.0, 4.0}) {
        SCOPED_TRACE(::testing::Message() << "height " << h);
        ShadowOptions o;
        o.cascades = 1;
        o.mapSize = 256;
        o.filter = ShadowFilter::Pcss;
        o.lightAngularRadius = 0.05f;
        o.maxPenumbraTexels = 32.0f;
        EdgeScene scene(0.013, o, {0, 0, 1}, h, 0.02);               // a thin slab, its top h up
        auto v = edgeViewer(kPx, kHalfView, glm::vec2(0.0f), 0.45f); // sees z in [−0.45, 0.45]
        const FloatImage img = render(*v, scene.root);
        const double t = scene.shadows->lastFrame().texels.at(0) / px;
        const double rho = h * tanA / (t * px); // texels
        ASSERT_LT(rho, 16.0);
        const PenumbraFit fit = fitPenumbra(columnMeans(img, 96, 160), t, rho);
        EXPECT_NEAR(fit.widthGot, fit.widthWant, 0.15 * fit.widthWant + 1.0);
        EXPECT_LE(fit.worst, 0.06) << "edge fitted at column " << fit.edge;
        std::printf("pcss: h = %.1f m, rho = %.2f texels, 10-90 %% width %.2f px (quadrature %.2f px)\n", h,
                    rho, fit.widthGot, fit.widthWant);
        widths.push_back(fit.widthGot);
    }
    for (std::size_t i = 1; i < widths.size(); ++i)
        EXPECT_NEAR(widths[i] / widths[i - 1], 2.0, 0.35)
            << "from " << widths[i - 1] << " to " << widths[i] << " px";
}

// Test 5 of the plan: stability. The camera moves by 1..7 pixels in x and y; each image, shifted
// back, equals the first wherever they overlap (within 1/255): the texel grid is fixed in the
// world. Negative control: without snapping the edges move by at least 64/255 for some move (16/255
// through the PCF disc, which spreads an edge over several texels).
TEST(ShadowRender, MovingTheCameraByPixelsLeavesShadowEdgesStill) {
    constexpr int kPx = 128;
    constexpr float kHalfView = 1.0f;
    const float px = 2.0f * kHalfView / kPx;
    const glm::dvec3 L = glm::normalize(glm::dvec3(0.3, 0.2, 1.0));
    for (const bool snap : {true, false})
        for (const ShadowFilter filter : {ShadowFilter::Hard2x2, ShadowFilter::Pcf}) {
            SCOPED_TRACE(::testing::Message() << "snap " << snap << ", filter " << int(filter));
            ShadowOptions o;
            o.cascades = 1;
            o.mapSize = 256;
            o.filter = filter;
            o.snapToTexels = snap;
            EdgeScene scene(0.013, o, L);
            const FloatImage first = render(*edgeViewer(kPx, kHalfView), scene.root);
            double worst = 0.0;
            for (int k = 1; k <= 7; ++k) {
                const int dx = k, dy = (k * 3) % 8;
                const FloatImage moved = render(*edgeViewer(kPx, kHalfView, {dx * px, dy * px}), scene.root);
                // The world point of pixel (x, y) of `moved` is that of (x + dx, y − dy) of `first`.
                for (int y = 8; y < kPx - 8; ++y)
                    for (int x = 8; x < kPx - 8; ++x) {
                        const int fx = x + dx, fy = y - dy;
                        if (fx >= kPx || fy < 0) continue;
                        worst = std::max(worst, std::abs(red(moved, x, y) - red(first, fx, fy)));
                    }
            }
            if (snap) {
                EXPECT_LE(worst, 1.0 / 255.0);
            } else { // a hard edge moves by its whole ramp; the PCF disc spreads it over 7 texels
                EXPECT_GE(worst, (filter == ShadowFilter::Hard2x2 ? 64.0 : 16.0) / 255.0);
            }
        }
}

// Test 3 of the plan: the contact gap. A wall of no thickness (a double-sided card: the worst case,
// as a solid box casts from its far, sunlit face) stands on the plane facing the sun; seen from
// above at about 5 mm a pixel, with a coarse map (a texel ≈ 2 cm), its shadow must start within
// 2 texels of its base at sun elevations from 3° to 85° (the goal), for both filters.
// The gaps are printed: docs/effects/shadows.md's bias table.
TEST(ShadowRender, ShadowsTouchTheirCasterWithinTwoTexels) {
    constexpr int kPx = 128;
    constexpr float kView = 0.3f; // half extent: pixels of 4.7 mm
    const double base = -0.5;     // the box's face away from the sun, x = −0.5
    for (const ShadowFilter filter : {ShadowFilter::Hard2x2, ShadowFilter::Pcf})
        for (const double e : {3.0, 5.0, 10.0, 20.0, 45.0, 70.0, 85.0}) {
            SCOPED_TRACE(::testing::Message() << "filter " << int(filter) << ", elevation " << e);
            const glm::dvec3 L = sunVector(0.0, e); // from +x: the shadow falls towards −x
            ShadowOptions o;
            o.cascades = 1;
            o.mapSize = 512;
            o.filter = filter;
            BoxScene scene(L, {-0.5, -0.5, 0.0}, {0.5, 0.5, 1.0}, o);
            // The box becomes a card in the plane x = −0.5, 1 m tall and wide.
            auto wall = lambert(shapes::quad(1.0f, 1.0f));
            wall->getOrCreateStateSet().cullFace.set(CullFace::None);
            scene.shadows->removeChild(scene.shadows->child(1).get());
            scene.shadows->addChild(
                placed(wall, glm::translate(glm::mat4(1.0f), glm::vec3(-0.5f, 0.0f, 0.5f)) *
                                 glm::rotate(glm::mat4(1.0f), glm::half_pi<float>(), glm::vec3(0, 1, 0))));
            auto v = Viewer::createHeadless(kPx, kPx);
            v->renderer().options().colorTarget = RendererOptions::ColorTarget::Rgba32F;
            Camera& c = *v->camera();
            c.setLookAt(glm::vec3(float(base), 0.0f, 10.0f), glm::vec3(float(base), 0.0f, 0.0f), {0, 1, 0});
            c.projectionMatrix = glm::ortho(-kView, kView, -kView, kView, 5.0f, 15.0f);
            const FloatImage img = render(*v, scene.root);
            const double px = 2.0 * kView / kPx, t = scene.shadows->lastFrame().texels.at(0);
            ASSERT_GT(t, 3.0 * px);
            // Columns left of the base (x < −0.5), from the base outwards; rows around y = 0.
            double gap = 1e9;
            for (int x = kPx / 2 - 1; x >= 0 && gap > 1e8; --x) {
                double sum = 0.0;
                for (int y = kPx / 2 - 8; y < kPx / 2 + 8; ++y)
                    sum += red(img, x, y) / L.z;
                if (sum / 16.0 < 0.5) gap = base - (base - kView + (x + 0.5) * px);
            }
            std::printf("contact gap: filter %s, elevation %4.0f°: %.2f texels (t = %.1f mm)\n",
                        filter == ShadowFilter::Pcf ? "pcf " : "hard", e, gap / t, t * 1000.0);
            EXPECT_LT(gap, 2.0 * t) << gap / t << " texels";
        }
}

// Metallic-roughness materials share the light loops: a rough dielectric plane shows the box's
// projected shadow too (v over the view without the node, as its shading is not cos θ).
TEST(ShadowRender, MetallicRoughnessMaterialsReceive) {
    const glm::dvec3 lo(-0.6, -0.4, 0.5), hi(0.4, 0.6, 1.1), L = sunVector(135.0, 50.0);
    BoxScene scene(L, lo, hi, ShadowOptions{});
    scene.plane->getOrCreateStateSet().material.set(metallicRoughness(glm::vec3(0.8f), 0.0f, 0.7f));
    auto v = topViewer();
    const FloatImage shadowed = render(*v, scene.root);
    scene.shadows->enabled = false;
    const FloatImage plain = render(*v, scene.root);
    const Hull hull = boxShadow(lo, hi, L), skip = footprint(lo, hi);
    const double px = 2.0 * kHalf / kSize;
    int wrong = 0, dark = 0;
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) {
            const glm::dvec2 w = worldOfPixel(x, y);
            const double d = signedDistance(hull, w);
            if (signedDistance(skip, w) < px || std::abs(d) < px) continue;
            const bool isDark = red(shadowed, x, y) < 0.5 * red(plain, x, y);
            dark += isDark;
            if (isDark != (d < 0) && ++wrong <= 5) ADD_FAILURE() << "pixel " << x << "," << y;
        }
    EXPECT_EQ(wrong, 0);
    EXPECT_GT(dark, 100);
}

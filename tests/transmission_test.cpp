// KHR_materials_transmission (+ _volume, _ior) rendered on OSMesa (96×96, linear float target)
// against the extensions' model written out here: the refracted ray by Snell's law in components
// (not GLSL's refract), the scene behind from the wall's closed-form colour ramp, Beer–Lambert
// attenuation, Schlick's Fresnel; the roughness blur against its documented mip level; the
// transmissive stage's place among opaque, blended and OIT glass; its frame-graph passes.
#include "TestUtil.h"

#include <sgfx/Geometry.h>
#include <sgfx/Group.h>
#include <sgfx/Shapes.h>
#include <sgfx/gl/Objects.h>
#include <sgfx/nodes/transparency/TransparencyBin.h>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

using namespace sgfx;
using namespace sgfx::test;

namespace {

constexpr int kSize = 96;
constexpr double kWallY = 20.0, kPaneY = 5.0;

std::unique_ptr<Viewer> viewer() {
    auto v = Viewer::createHeadless(kSize, kSize);
    auto& cam = *v->camera();
    cam.setPerspective(60.0f, 0.5f, 200.0f);
    cam.setLookAt({0, 0, 0}, {0, 10, 0}, {0, 0, 1});
    cam.computeNearFar = false;
    cam.clearColor = {0, 0, 0, 1};
    v->renderer().options().colorTarget = RendererOptions::ColorTarget::Rgba32F;
    return v;
}

// Vertical, facing the camera (−Y), centred at (x, y, 0); local x → world x, local y → world z.
glm::mat4 facing(double y, double x = 0.0, float scale = 1.0f) {
    return glm::scale(glm::rotate(glm::translate(glm::mat4(1.0f), {float(x), float(y), 0.0f}),
                                  glm::radians(90.0f), glm::vec3(1, 0, 0)),
                      glm::vec3(scale));
}

std::shared_ptr<Node> placed(const glm::mat4& m, std::shared_ptr<Node> child) {
    auto t = Transform::create(m);
    t->addChild(std::move(child));
    return t;
}

// The wall's colour at world (x, z): a ramp per channel, linear in the wall's plane.
glm::dvec3 ramp(double x, double z) {
    return {0.2 + 0.6 * (x + 30.0) / 60.0, 0.2 + 0.6 * (z + 30.0) / 60.0, 0.5};
}

// A 60 × 60 m unlit wall at y = 20 whose vertex colours make `ramp` (interpolated exactly:
// colours are linear in the plane, as the ramp is).
std::shared_ptr<Node> rampWall() {
    auto q = shapes::quad(60.0f, 60.0f);
    q->colors.clear();
    for (const glm::vec3& p : q->positions) {
        const glm::dvec3 c = ramp(p.x, p.y);
        q->colors.emplace_back(float(c.r), float(c.g), float(c.b), 1.0f);
    }
    auto m = Material::create();
    m->model = ShadingModel::Unlit;
    m->diffuse = glm::vec4(1.0f);
    q->getOrCreateStateSet().material.set(m);
    return placed(facing(kWallY), q);
}

// Unlit wall: black left of x = 0, white right of it.
std::shared_ptr<Node> edgeWall() {
    auto g = Group::create();
    for (int side = 0; side < 2; ++side) {
        auto q = shapes::quad(30.0f, 60.0f);
        auto m = Material::create();
        m->model = ShadingModel::Unlit;
        m->diffuse = glm::vec4(glm::vec3(float(side)), 1.0f);
        q->getOrCreateStateSet().material.set(m);
        g->addChild(placed(facing(kWallY, side ? 15.0 : -15.0), q));
    }
    return g;
}

std::shared_ptr<Material> glass(float ior, float thickness, float roughness = 0.0f) {
    auto m = metallicRoughness(glm::vec3(1.0f), 0.0f, roughness);
    m->transmission = 1.0f;
    m->ior = ior;
    m->thickness = thickness;
    return m;
}

// A 4 × 4 m pane (in world units: `scale` × a quad of 4 / scale) at y = 5.
std::shared_ptr<Node> pane(std::shared_ptr<Material> m, float scale = 1.0f, double y = kPaneY) {
    auto q = shapes::quad(4.0f / scale, 4.0f / scale);
    q->getOrCreateStateSet().material.set(std::move(m));
    q->getOrCreateStateSet().cullFace.set(CullFace::None);
    return placed(facing(y, 0.0, scale), q);
}

// The last viewer stays alive so a test can read its camera. It is released when the tests end,
// not by static destruction: the library's own function-local statics, made after it, are gone by
// then (that ordering crashed at exit).
std::unique_ptr<Viewer> last;

struct ReleaseLastViewer : ::testing::Environment {
    void TearDown() override { last.reset(); }
};
[[maybe_unused]] ::testing::Environment* const releaseLast =
    ::testing::AddGlobalTestEnvironment(new ReleaseLastViewer);

FloatImage render(const std::shared_ptr<Node>& scene, Viewer** keep = nullptr) {
    last = viewer();
    last->setSceneData(scene);
    last->frame();
    EXPECT_TRUE(last->renderer().takeGlErrors().empty());
    if (keep) *keep = last.get();
    return last->renderer().readPixelsLinear();
}

glm::dvec3 at(const FloatImage& img, int x, int y) {
    const float* p = &img.rgba[(std::size_t(y) * std::size_t(img.width) + std::size_t(x)) * 4];
    return {p[0], p[1], p[2]};
}

// The eye ray through the centre of pixel (x, y) (top row first): eye at the origin, looking +Y.
glm::dvec3 rayDir(const Camera& cam, int x, int y) {
    const glm::dmat4 inv = glm::inverse(glm::dmat4(cam.projectionMatrix) * glm::dmat4(cam.viewMatrix));
    const double nx = (x + 0.5) / kSize * 2 - 1, ny = 1 - (y + 0.5) / kSize * 2;
    glm::dvec4 a = inv * glm::dvec4(nx, ny, -1, 1), b = inv * glm::dvec4(nx, ny, 1, 1);
    return glm::normalize(glm::dvec3(b / b.w) - glm::dvec3(a / a.w));
}

struct Expected {
    glm::dvec3 colour;   // what the pane shows
    glm::dvec3 straight; // the wall straight behind the pixel
};

// The extensions' model for a pane facing −Y at y = 5, white, dielectric, smooth: the ray enters
// at P, bends by Snell's law (tangential part × 1/ior), runs thickness × scale, and the eye sees
// the wall behind that exit point; (1 − F) with Schlick's F at the angle of incidence; Beer–Lambert
// over the path inside.
Expected expected(const Camera& cam, int x, int y, double ior, double thickness, double scale,
                  glm::dvec3 attenuationColour = glm::dvec3(1.0), double attenuationDistance = 0.0) {
    const glm::dvec3 d = rayDir(cam, x, y);
    const glm::dvec3 P = d * (kPaneY / d.y);
    const glm::dvec3 tangential(d.x, 0.0, d.z);
    const glm::dvec3 bentT = tangential / ior; // sin θt = sin θi / ior
    const glm::dvec3 bent = bentT + glm::dvec3(0.0, std::sqrt(1.0 - glm::dot(bentT, bentT)), 0.0);
    const double inside = thickness * scale;
    const glm::dvec3 exit = P + bent * inside;
    const glm::dvec3 wall = exit * (kWallY / exit.y); // the eye's line through the exit point
    const double f0 = std::pow((ior - 1.0) / (ior + 1.0), 2.0);
    const double F = f0 + (1.0 - f0) * std::pow(1.0 - d.y, 5.0); // cos θi = d·(0, 1, 0)
    glm::dvec3 c = (1.0 - F) * ramp(wall.x, wall.z);
    if (attenuationDistance > 0.0)
        for (int k = 0; k < 3; ++k)
            c[k] *= std::pow(attenuationColour[k], inside / attenuationDistance);
    const glm::dvec3 straight = d * (kWallY / d.y);
    return {c, ramp(straight.x, straight.z)};
}

std::shared_ptr<Group> scene(std::initializer_list<std::shared_ptr<Node>> nodes) {
    auto g = Group::create();
    for (const auto& n : nodes)
        g->addChild(n);
    return g;
}

constexpr int kOffsets[] = {-24, -12, 0, 12, 24};

} // namespace

TEST(Transmission, RefractedRayThroughThicknessShowsTheWallWhereSnellsLawSays) {
    for (const double ior : {1.0, 1.5, 2.4}) {
        SCOPED_TRACE("ior " + std::to_string(ior));
        Viewer* v = nullptr;
        const FloatImage img = render(scene({rampWall(), pane(glass(float(ior), 2.0f))}), &v);
        double bentMost = 0.0;
        for (int ox : kOffsets)
            for (int oy : kOffsets) {
                const int x = kSize / 2 + ox, y = kSize / 2 + oy;
                const Expected e = expected(*v->camera(), x, y, ior, 2.0, 1.0);
                const glm::dvec3 got = at(img, x, y);
                for (int c = 0; c < 3; ++c)
                    EXPECT_NEAR(got[c], e.colour[c], 2e-3 + 5e-3 * e.colour[c]) << "pixel " << x << "," << y;
                bentMost = std::max(bentMost, glm::length(e.colour - e.straight));
            }
        // The test tells bent from straight: at ior 1 the wall shows straight through (less F).
        if (ior > 1.0)
            EXPECT_GT(bentMost, 0.03);
        else
            EXPECT_LT(bentMost, 0.02);
    }
}

TEST(Transmission, ThinWallShowsTheWallStraightThroughLessFresnel) {
    Viewer* v = nullptr;
    const FloatImage img = render(scene({rampWall(), pane(glass(1.5f, 0.0f))}), &v);
    for (int ox : kOffsets) {
        const int x = kSize / 2 + ox, y = kSize / 2 - ox / 2;
        const Expected e = expected(*v->camera(), x, y, 1.5, 0.0, 1.0);
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(at(img, x, y)[c], e.colour[c], 2e-3) << x << "," << y;
        EXPECT_LT(glm::length(e.colour - 0.96 * e.straight), 2e-3); // near normal incidence F ≈ F0
    }
}

TEST(Transmission, BeerLambertOverThePathInsideScaledByTheModel) {
    const glm::dvec3 tint(0.5, 0.8, 1.0);
    for (const float scale : {1.0f, 2.0f}) {
        SCOPED_TRACE("scale " + std::to_string(scale));
        auto m = glass(1.5f, 0.25f);
        m->attenuationColor = glm::vec3(tint);
        m->attenuationDistance = 0.25f;
        Viewer* v = nullptr;
        const FloatImage img = render(scene({rampWall(), pane(m, scale)}), &v);
        for (int ox : kOffsets) {
            const int x = kSize / 2 + ox, y = kSize / 2 + ox / 3;
            const Expected e = expected(*v->camera(), x, y, 1.5, 0.25, scale, tint, 0.25);
            for (int c = 0; c < 3; ++c)
                EXPECT_NEAR(at(img, x, y)[c], e.colour[c], 2e-3 + 5e-3 * e.colour[c]) << x << "," << y;
        }
        // Red through 0.25·scale m of a medium that keeps half of it per 0.25 m.
        const glm::dvec3 centre = at(img, kSize / 2, kSize / 2);
        const Expected e = expected(*v->camera(), kSize / 2, kSize / 2, 1.5, 0.25, scale);
        EXPECT_NEAR(centre.r / e.colour.r, std::pow(0.5, scale), 0.02);
    }
}

TEST(Transmission, TransmissionFactorMixesWithTheDiffuseSurface) {
    // Half transmissive, lit by an ambient light only: half the ambient-lit surface, half the wall.
    auto m = glass(1.5f, 0.0f);
    m->transmission = 0.5f;
    m->diffuse = glm::vec4(0.6f, 0.6f, 0.6f, 1.0f);
    auto amb = Light::create(LightType::Ambient);
    amb->color = glm::vec3(0.5f);
    Viewer* v = nullptr;
    const FloatImage img = render(scene({amb, rampWall(), pane(m)}), &v);
    const int x = kSize / 2, y = kSize / 2;
    const Expected e = expected(*v->camera(), x, y, 1.5, 0.0, 1.0);
    // Ambient light lights diffuse + F0 (the built-in material's documented ambient term).
    const glm::dvec3 surface = 0.5 * glm::dvec3(0.6 + 0.04);
    const glm::dvec3 want = 0.5 * surface + 0.5 * 0.6 * e.colour;
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(at(img, x, y)[c], want[c], 3e-3);
}

// Rough glass blurs what it shows by mip level log2(width)·roughness·clamp(2·ior − 2, 0, 1): at ior
// 1 not at all, whatever the roughness (TransmissionRoughnessTest's point).
TEST(Transmission, RoughnessBlursByTheDocumentedMipLevelAndNotAtIorOne) {
    auto edgeWidth = [](float ior, float roughness) {
        const FloatImage img = render(scene({edgeWall(), pane(glass(ior, 0.0f, roughness))}));
        const int y = kSize / 2;
        double lo = 1e9, hi = -1e9;
        for (int x = 30; x < 66; ++x) {
            lo = std::min(lo, at(img, x, y).g);
            hi = std::max(hi, at(img, x, y).g);
        }
        int between = 0;
        for (int x = 30; x < 66; ++x) {
            const double t = (at(img, x, y).g - lo) / (hi - lo);
            between += t > 0.1 && t < 0.9;
        }
        return between;
    };
    const double log2w = std::log2(double(kSize));
    EXPECT_LE(edgeWidth(1.0f, 0.6f), 1) << "ior 1 stays sharp";
    EXPECT_LE(edgeWidth(1.5f, 0.0f), 1) << "smooth glass stays sharp";
    const int narrow = edgeWidth(1.5f, 0.3f), wide = edgeWidth(1.5f, 0.6f);
    std::printf("edge 10-90%% width: roughness 0.3 %d px (level %.2f), 0.6 %d px (level %.2f)\n", narrow,
                0.3 * log2w, wide, 0.6 * log2w);
    // A box-filtered step at level L spans about 2^L texels, bilinear filtering adds some.
    EXPECT_GE(wide, int(std::exp2(0.6 * log2w - 2.0)));
    EXPECT_LE(wide, int(std::exp2(0.6 * log2w + 1.0)));
    EXPECT_GT(wide, narrow);
    EXPECT_GE(narrow, 2);
}

// The transmissive stage: after the opaque items, before the OIT passes and the blended items. Glass
// in front of a transmissive pane (blended or OIT) is composited over it; a transmissive pane shows
// only the opaque scene (glass behind it is not seen through it, and is hidden by it).
TEST(Transmission, BlendedAndOitGlassComposeOverItInFrontAndAreHiddenBehind) {
    const int x = kSize / 2, y = kSize / 2;
    auto tinted = [](double y0) {
        auto m = Material::create();
        m->ambient = glm::vec3(0.0f);
        m->diffuse = glm::vec4(0.0f, 0.0f, 0.0f, 0.5f);
        m->emissive = glm::vec3(0.9f, 0.1f, 0.1f);
        auto q = shapes::quad(2.0f, 2.0f);
        q->getOrCreateStateSet().material.set(m);
        q->getOrCreateStateSet().blend.set(BlendMode::Alpha);
        return placed(facing(y0), q);
    };
    const glm::dvec3 alone = at(render(scene({rampWall(), pane(glass(1.5f, 0.0f))})), x, y);
    const glm::dvec3 red(0.9, 0.1, 0.1);
    const glm::dvec3 over = 0.5 * red + 0.5 * alone;
    // Blended, sorted: in front composites over the pane, behind is hidden.
    const glm::dvec3 front = at(render(scene({rampWall(), pane(glass(1.5f, 0.0f)), tinted(3.0)})), x, y);
    const glm::dvec3 behind = at(render(scene({rampWall(), pane(glass(1.5f, 0.0f)), tinted(10.0)})), x, y);
    // Weighted blended OIT: one layer composites as the over operator does.
    auto bin = TransparencyBin::create(TransparencyMode::WeightedBlended);
    bin->addChild(tinted(3.0));
    const glm::dvec3 oit = at(render(scene({rampWall(), pane(glass(1.5f, 0.0f)), bin})), x, y);
    auto binBehind = TransparencyBin::create(TransparencyMode::WeightedBlended);
    binBehind->addChild(tinted(10.0));
    const glm::dvec3 oitBehind = at(render(scene({rampWall(), pane(glass(1.5f, 0.0f)), binBehind})), x, y);
    for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(front[c], over[c], 3e-3) << "blended in front";
        EXPECT_NEAR(oit[c], over[c], 5e-3) << "OIT in front";
        EXPECT_NEAR(behind[c], alone[c], 2e-3) << "blended behind";
        EXPECT_NEAR(oitBehind[c], alone[c], 2e-3) << "OIT behind";
    }
    EXPECT_GT(glm::length(over - alone), 0.1); // the cases differ
}

// A transmissive material that is also blended (under a TransparencyBin: sorted, or drawn by the
// bin's OIT pass) samples the same copy; opaque alpha composites to what the unblended pane shows.
TEST(Transmission, BlendedTransmissiveMaterialsSampleTheCopyInTheSortedAndOitStages) {
    const int x = kSize / 2 + 10, y = kSize / 2 - 7;
    const glm::dvec3 alone = at(render(scene({rampWall(), pane(glass(1.5f, 1.0f))})), x, y);
    for (const TransparencyMode mode : {TransparencyMode::Sorted, TransparencyMode::WeightedBlended}) {
        auto bin = TransparencyBin::create(mode);
        bin->addChild(pane(glass(1.5f, 1.0f)));
        const glm::dvec3 got = at(render(scene({rampWall(), bin})), x, y);
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(got[c], alone[c], 5e-3) << (mode == TransparencyMode::Sorted ? "sorted" : "OIT");
    }
}

// The default target (sRGB, 8 bits) under 4× MSAA: the copy is resolved from the multisample
// draw target and decoded when sampled; the pane still shows the wall where Snell's law says.
TEST(Transmission, MultisampledSrgbTargetResolvesTheCopy) {
    auto v = viewer();
    v->renderer().options().colorTarget = RendererOptions::ColorTarget::Srgb8;
    v->camera()->setAntiAliasing(AntiAliasing::msaa(4));
    v->setSceneData(scene({rampWall(), pane(glass(1.5f, 2.0f))}));
    v->frame();
    EXPECT_TRUE(v->renderer().takeGlErrors().empty());
    const Image img = v->capture();
    for (int ox : kOffsets) {
        const int px = kSize / 2 + ox, py = kSize / 2 + ox / 2;
        const Expected e = expected(*v->camera(), px, py, 1.5, 2.0, 1.0);
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(pixelAt(img, px, py)[c], srgbByte(e.colour[c]), 2) << px << "," << py;
    }
}

TEST(Transmission, CopyAndStageExistOnlyWhenSomethingTransmits) {
    Viewer* v = nullptr;
    render(scene({rampWall(), pane(glass(1.5f, 0.1f))}), &v);
    std::string dot = v->renderer().lastFrameGraphDot();
    EXPECT_NE(dot.find("transmission copy"), std::string::npos) << dot;
    EXPECT_NE(dot.find("main: transmissive"), std::string::npos) << dot;
    // The copy (RGBA32F like the target) with its mip chain: a third more than one level.
    EXPECT_EQ(v->renderer().renderTargetBytes(), std::size_t(kSize) * kSize * 16 * 4 / 3);
    auto opaque = metallicRoughness(glm::vec3(1.0f), 0.0f, 0.5f);
    render(scene({rampWall(), pane(opaque)}), &v);
    dot = v->renderer().lastFrameGraphDot();
    EXPECT_EQ(dot.find("transmission"), std::string::npos) << dot;
    EXPECT_EQ(v->renderer().renderTargetBytes(), 0u);
}

TEST(Transmission, NothingLeaksAndBadFieldsAreRefusedAtDraw) {
    const long before = gl::liveObjects().total();
    {
        auto v = viewer();
        v->setSceneData(scene({rampWall(), pane(glass(1.5f, 0.5f, 0.4f))}));
        for (int i = 0; i < 3; ++i)
            v->frame();
        EXPECT_TRUE(v->renderer().takeGlErrors().empty());
    }
    EXPECT_EQ(gl::liveObjects().total(), before);
    auto m = glass(1.5f, 0.0f);
    m->ior = 0.5f;
    auto v = viewer();
    v->setSceneData(scene({rampWall(), pane(m)}));
    try {
        v->frame();
        ADD_FAILURE() << "drew ior 0.5";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("ior"), std::string::npos) << e.what();
    }
}

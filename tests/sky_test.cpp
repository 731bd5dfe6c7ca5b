// SkyNode against its CPU mirror (SkyMath.h): sky pixels along known directions, the sun's
// disc, the blue noon and red sunset, geometry hiding the sky, the fog taking the horizon colour.
// Then against what shares none of their steps: the closed form of the zenith's optical depth and
// an independent double-precision reference (SkyReference.h) for the radiance, the sun's disc and
// the fog's horizon colour; and every pixel finite looking and lit from the poles.
#include "SkyReference.h"
#include "TestUtil.h"

#include <cstdio>
#include <sstream>

#include <sgfx/Group.h>
#include <sgfx/Material.h>
#include <sgfx/Shapes.h>
#include <sgfx/StateSet.h>
#include <sgfx/Visitors.h>
#include <sgfx/nodes/fog/FogNode.h>
#include <sgfx/nodes/shadow/ShadowNode.h>
#include <sgfx/nodes/sky/SkyNode.h>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

using namespace sgfx;
using namespace sgfx::test;

namespace {
constexpr int kSize = 64;

std::unique_ptr<Viewer> skyViewer(glm::vec3 look, int size = kSize, float fovDegrees = 60.0f) {
    auto v = Viewer::createHeadless(size, size);
    v->renderer().options().colorTarget = RendererOptions::ColorTarget::Rgba32F;
    auto& cam = *v->camera();
    cam.setPerspective(fovDegrees, 0.1f, 1000.0f);
    cam.setLookAt({0, 0, 2}, glm::vec3(0, 0, 2) + look,
                  std::abs(look.z) > 0.99f ? glm::vec3(0, 1, 0) : glm::vec3(0, 0, 1));
    cam.clearColor = {0, 0, 0, 1};
    return v;
}

// Pixel (x, y) (top row first) and its view ray.
glm::vec3 pixel(const FloatImage& img, int x, int y) {
    const float* p = &img.rgba[(std::size_t(y) * std::size_t(img.width) + std::size_t(x)) * 4];
    return {p[0], p[1], p[2]};
}
glm::vec3 pixel(Viewer& v, int x, int y) {
    return pixel(v.renderer().readPixelsLinear(), x, y);
}
glm::vec3 rayOf(Viewer& v, int x, int y) {
    const Camera& c = *v.camera();
    const glm::mat4 inv = glm::inverse(c.projectionMatrix * c.viewMatrix);
    const float w = float(c.viewport.width), h = float(c.viewport.height);
    const glm::vec4 ndc((x + 0.5f) / w * 2 - 1, 1 - (y + 0.5f) / h * 2, 1, 1);
    const glm::vec4 p = inv * ndc;
    return glm::normalize(glm::vec3(p) / p.w - glm::vec3(0, 0, 2));
}

// The unit vector at `elevation` above the horizon and `azimuth` clockwise from north (+y), degrees.
glm::dvec3 towards(double elevation, double azimuth) {
    const double e = glm::radians(elevation), a = glm::radians(azimuth);
    return {std::cos(e) * std::sin(a), std::cos(e) * std::cos(a), std::sin(e)};
}
double elevationOf(glm::dvec3 d) {
    return glm::degrees(std::asin(std::clamp(glm::normalize(d).z, -1.0, 1.0)));
}

// Tolerances against the reference (SkyReference.h; its own error is below 1e-4).
//
// Transmittance, compared as optical depth τ = −ln T: the march (marchStep, the midpoint rule in
// u = √(t/L)) integrates g(u) = 2L·u·e^(−L·u²/H) over [0, 1] for a layer of scale height H along a
// vertical ray of length L; by Euler–Maclaurin it errs by g′(0)/(24n²) = L/(12n²), a fraction
// L/(12n²H) of the layer's depth H: with n = 16 and L = 60 km, 1.6 % for the Mie layer
// (H = 1.2 km) and 0.24 % for Rayleigh's; a slanted ray's is no larger (L·sin(elevation), at most
// 60 km, takes L's place).
// Measured: at most 0.79 % of τ over sun elevations of 0.25–90° (red near the zenith, where Mie's
// share is largest). Bound: 2 %. Uniform steps, as before, missed 31 % of the Mie depth at the
// zenith and 12 % of τ.
constexpr double kOpticalDepthTolerance = 0.02;

// Radiance: the error of 16 view and 8 sun steps is second order (doubling both quarters it), so
// the reference's 1,024 are converged and the error at 16/8 is the leading term. It is worst
// where the integrands are least like the march's assumption of density falling fastest near the
// ray's start: at the horizon (an 880 km ray whose density falls as a Gaussian in distance) with
// the sun low (sun rays from it graze the ground). Measured by the CPU mirror over sun elevations
// −5 to 90° (every 0.5° below 6°), views 0–90° at 17 elevations and 7 azimuths: at most 3.6 %
// below 5° of elevation (horizon, sun 1° ahead), 1.4 % above; the rendered pixels follow the CPU
// within 0.2 % per pixel, and the 256 × 128 table adds at most 0.8 % (measured on this grid). Bounds:
// 5 % and 2.5 %, 1.5 % more through the table, plus 1e-3 absolute: twilight skies below 1e-2
// (the sun below the horizon lights only air high enough to see it, and a step's sample decides
// alone whether it is lit) are held to a thousandth of the daylit sky's ~1. Before this change
// (uniform steps, each sample attenuated to its step's end) the error reached 28 % at the zenith
// and 83 % at the horizon.
struct SkyTolerance {
    double relative, absolute;
};
SkyTolerance radianceTolerance(double viewElevation, bool table) {
    return {(viewElevation < 5.0 ? 0.05 : 0.025) + (table ? 0.015 : 0.0), 1e-3};
}

// Expects the transmittance `got` to have the optical depth of `want`, within the tolerance.
void expectOpticalDepth(const glm::dvec3& got, const glm::dvec3& want, const std::string& where) {
    for (int c = 0; c < 3; ++c) {
        const double depth = -std::log(want[c]);
        EXPECT_NEAR(-std::log(got[c]), depth, kOpticalDepthTolerance * depth) << where << ", channel " << c;
    }
}

// In a 100° view: the pixels of the middle column whose elevations are nearest −5, 0, 2, 5, 10,
// 20, 45 and 90°, and those of the outer columns nearest 2, 10 and 45°.
std::vector<glm::ivec2> pixelsAtElevations(Viewer& v) {
    std::vector<glm::ivec2> out;
    const auto nearest = [&](int x, double elevation) {
        int best = 0;
        for (int y = 1; y < kSize; ++y)
            if (std::abs(elevationOf(glm::dvec3(rayOf(v, x, y))) - elevation) <
                std::abs(elevationOf(glm::dvec3(rayOf(v, x, best))) - elevation))
                best = y;
        out.push_back({x, best});
    };
    for (const double e : {-5.0, 0.0, 2.0, 5.0, 10.0, 20.0, 45.0, 90.0})
        nearest(kSize / 2, e);
    for (const int x : {4, kSize - 5})
        for (const double e : {2.0, 10.0, 45.0})
            nearest(x, e);
    return out;
}

// Expects rendered sky pixels to match the reference; returns the largest error relative to the
// tolerance (≤ 1 passes).
double expectRadiance(const glm::vec3& got, const glm::dvec3& want, const SkyTolerance& tol,
                      const std::string& where) {
    double worst = 0.0;
    for (int c = 0; c < 3; ++c) {
        const double allowed = tol.relative * want[c] + tol.absolute;
        worst = std::max(worst, std::abs(got[c] - want[c]) / allowed);
        EXPECT_NEAR(got[c], want[c], allowed) << where << ", channel " << c;
    }
    return worst;
}
} // namespace

TEST(Sky, PixelsMatchTheCpuIntegral) {
    // Integrated per pixel: within 0.2 %; through the 256 × 128 sky-view table: within 3 %.
    for (const bool table : {false, true})
        for (const float hours : {7.0f, 12.0f, 19.5f}) {
            SkyParameters p = SkyParameters::atTime(hours);
            p.lookupTable = table;
            auto v = skyViewer(glm::normalize(glm::vec3(p.sunDirection.x, p.sunDirection.y, 0.3f)));
            v->setSceneData(SkyNode::create(p));
            v->frame();
            for (const glm::ivec2 at : {glm::ivec2(5, 5), glm::ivec2(32, 20), glm::ivec2(50, 60)}) {
                const glm::vec3 expected = sky::skyRadiance(p.atmosphere, rayOf(*v, at.x, at.y),
                                                            p.sunDirection, p.sunIntensity, 2.0f);
                const glm::vec3 got = pixel(*v, at.x, at.y);
                for (int c = 0; c < 3; ++c)
                    EXPECT_NEAR(got[c], expected[c], (table ? 3e-2f : 2e-3f) * expected[c] + 1e-5f)
                        << (table ? "table " : "direct ") << hours << "h pixel " << at.x << "," << at.y
                        << " channel " << c;
            }
        }
}

TEST(Sky, NoonIsBlueOverheadAndTheSunsetHorizonIsRed) {
    sky::Atmosphere a;
    const glm::vec3 noonSun = glm::normalize(glm::vec3(0, 0.3f, 1));
    const glm::vec3 zenith = sky::skyRadiance(a, {0, 0, 1}, noonSun, 20.0f, 0.0f);
    EXPECT_GT(zenith.b, 1.5f * zenith.r);
    const glm::vec3 lowSun = glm::normalize(glm::vec3(0, 1, 0.02f));
    const glm::vec3 horizon =
        sky::skyRadiance(a, glm::normalize(glm::vec3(0, 1, 0.03f)), lowSun, 20.0f, 0.0f);
    EXPECT_GT(horizon.r, horizon.b);
    // Night: the sun below the horizon leaves the sky far darker.
    const glm::vec3 night =
        sky::skyRadiance(a, {0, 0, 1}, glm::normalize(glm::vec3(0, 1, -0.3f)), 20.0f, 0.0f);
    EXPECT_LT(night.b, 0.05f * zenith.b);
}

TEST(Sky, SunDiscAndGeometryInFront) {
    SkyParameters p;
    p.sunDirection = glm::normalize(glm::vec3(0, 1, 0.2f));
    p.sunAngularRadius = 0.05f; // large enough to cover pixels at 60° over 64 px
    auto v = skyViewer(p.sunDirection);
    auto root = Group::create();
    root->addChild(SkyNode::create(p));
    // An opaque black quad over the left part of the view, 20 m away.
    auto t = Transform::create(glm::translate(glm::mat4(1.0f), {-14.0f, 20.0f, 4.0f}) *
                               glm::rotate(glm::mat4(1.0f), glm::radians(90.0f), glm::vec3(1, 0, 0)));
    auto q = shapes::quad(20, 40);
    auto m = Material::create();
    m->ambient = glm::vec3(0);
    m->diffuse = glm::vec4(0, 0, 0, 1);
    q->getOrCreateStateSet().material.set(m);
    q->getOrCreateStateSet().cullFace.set(CullFace::None);
    t->addChild(q);
    root->addChild(t);
    v->setSceneData(root);
    v->frame();
    EXPECT_GT(pixel(*v, 32, 32).r, 10.0f * pixel(*v, 50, 10).r) << "the disc is far brighter than the sky";
    EXPECT_EQ(pixel(*v, 2, 32), glm::vec3(0.0f)) << "the quad hides the sky";
    EXPECT_GT(pixel(*v, 62, 32).b, 0.0f);
}

TEST(Sky, DrivesTheFogColourAndFogLeavesTheSkyAlone) {
    auto v = skyViewer({0, 1, 0.1f});
    auto fog = FogNode::create(FogParameters::ground());
    auto sky = SkyNode::create(SkyParameters::atTime(18.0f));
    sky->attachFog(fog);
    fog->addChild(sky);
    v->setSceneData(fog);
    v->frame();
    const glm::vec3 h = sky->horizonColor();
    EXPECT_NEAR(fog->parameters().color.r, h.r, 1e-6f);
    EXPECT_NEAR(fog->parameters().color.b, h.b, 1e-6f);
    EXPECT_EQ(fog->parameters().sky, FogSky::Off);
    // The sky pixels are the sky's own (not fogged a second time).
    const glm::vec3 expected = sky::skyRadiance(sky->parameters().atmosphere, rayOf(*v, 32, 10),
                                                sky->parameters().sunDirection, 20.0f, 2.0f);
    EXPECT_NEAR(pixel(*v, 32, 10).g, expected.g, 3e-2 * expected.g + 1e-5);
}

TEST(Sky, ViewTableCoordinatesCrowdTowardsTheHorizon) {
    // u: azimuth from −π (0) to π (1); v: √(elevation / 90°), so the lowest 10° take a third.
    EXPECT_NEAR(sky::lutCoordinates({1, 0, 0}).x, 0.5f, 1e-6f);
    EXPECT_NEAR(sky::lutCoordinates({0, 0, 1}).y, 1.0f, 1e-6f);
    const float el10 = glm::radians(10.0f);
    EXPECT_NEAR(sky::lutCoordinates({std::cos(el10), 0, std::sin(el10)}).y, std::sqrt(1.0f / 9.0f), 1e-5f);
    EXPECT_NEAR(sky::lutCoordinates({1, 0, -0.5f}).y, 0.0f, 1e-6f); // below: the horizon row
}

TEST(Sky, BadParametersAreRefused) {
    auto sky = SkyNode::create();
    SkyParameters p;
    p.sunDirection = glm::vec3(0.0f);
    EXPECT_THROW(sky->setParameters(p), std::invalid_argument);
    p = {};
    p.atmosphere.atmosphereRadius = p.atmosphere.planetRadius;
    EXPECT_THROW(sky->setParameters(p), std::invalid_argument);
    p = {};
    p.steps = 0;
    EXPECT_THROW(sky->setParameters(p), std::invalid_argument);
    p = {};
    p.atmosphere.mieG = std::numeric_limits<float>::quiet_NaN();
    EXPECT_THROW(sky->setParameters(p), std::invalid_argument);
    EXPECT_EQ(sky->parameters().steps, 16);
}

TEST(Sky, EveryPixelIsFiniteLookingAndLitFromAnyPole) {
    // Straight down the horizon's azimuth is undefined: normalising (dir.xy, 0) gave NaN, which
    // the `tEnd > 0` test turned into black (CPU mirror and per-pixel shader alike), and the
    // table was sampled at NaN coordinates.
    const sky::Atmosphere a;
    for (const glm::vec3 sun : {glm::vec3(0, 0, 1), glm::vec3(0, 1, 0)}) {
        const glm::vec3 down = sky::skyRadiance(a, {0, 0, -1}, sun, 20.0f, 2.0f);
        const glm::vec3 east = sky::skyRadiance(a, {1, 0, 0}, sun, 20.0f, 2.0f);
        for (int c = 0; c < 3; ++c) {
            EXPECT_TRUE(std::isfinite(down[c]));
            EXPECT_EQ(down[c], east[c]) << "straight down shows the horizon towards +x";
        }
    }
    // An odd viewport puts the middle pixel's ray on the view axis: straight up or straight down
    // exactly, where the horizon's azimuth is undefined and |level| may round above 1.
    constexpr int kOdd = 33;
    const glm::vec3 poles[] = {{0, 0, 1}, {0, 0, -1}, {1, 0, 0}};
    int checked = 0;
    for (const bool table : {false, true})
        for (const glm::vec3 look : poles)
            for (const glm::vec3 sun : {glm::vec3(0, 0, 1), glm::vec3(0, 0, -1), glm::vec3(0, 1, 0)}) {
                SkyParameters p;
                p.sunDirection = sun;
                p.sunAngularRadius = 0.05f; // the disc covers the middle pixel when looking at the sun
                p.lookupTable = table;
                auto v = skyViewer(look, kOdd);
                v->setSceneData(SkyNode::create(p));
                v->frame();
                const FloatImage img = v->renderer().readPixelsLinear();
                int bad = 0, black = 0;
                for (std::size_t i = 0; i < img.rgba.size(); ++i) {
                    bad += !std::isfinite(img.rgba[i]);
                    black += i % 4 < 3 && !(img.rgba[i] > 0.0f);
                }
                std::ostringstream where;
                where << (table ? "table" : "direct") << ", looking " << look.x << "," << look.y << ","
                      << look.z << ", sun " << sun.x << "," << sun.y << "," << sun.z;
                EXPECT_EQ(bad, 0) << where.str();
                // While the sun is up every direction has some sky light (below the horizon, the
                // horizon's), straight down too.
                if (sun.z >= 0.0f) {
                    EXPECT_EQ(black, 0) << where.str();
                }
                checked += int(img.rgba.size());
            }
    EXPECT_EQ(checked, 18 * kOdd * kOdd * 4);
}

// The transmittance towards the sun at the zenith against the closed form of the optical depth
// through the two exponential layers, β·H·(e^(−h0/H) − e^(−top/H)) each; then the sun's disc, which
// shows the transmittance alone when the scattered light is switched off: at the zenith against
// the closed form, along slanted rays against the reference's numeric column (itself checked
// against the closed form first).
TEST(Sky, SunTransmittanceMatchesTheClosedForm) {
    const sky::Atmosphere atmosphere;
    const skyref::Medium m = skyref::medium(atmosphere);
    for (const double h : {1.0, 2.0, 500.0, 5000.0}) {
        const glm::dvec3 exact = skyref::zenithTransmittance(m, h);
        const glm::dvec3 numeric = skyref::sunTransmittance(m, {0, 0, 1}, h);
        const glm::vec3 cpu = sky::sunTransmittance(atmosphere, {0, 0, 1}, float(h));
        for (int c = 0; c < 3; ++c) {
            EXPECT_NEAR(numeric[c], exact[c], 1e-7 * exact[c]) << "the reference at " << h << " m";
        }
        expectOpticalDepth(glm::dvec3(cpu), exact, "sky::sunTransmittance at " + std::to_string(h) + " m");
    }
    // An odd viewport: the middle pixel looks exactly along the axis, at the sun.
    constexpr int kOdd = 33, kMiddle = kOdd / 2;
    for (const bool table : {false, true})
        for (const double elevation : {90.0, 30.0, 10.0, 3.0}) {
            SkyParameters p;
            p.sunDirection = glm::vec3(towards(elevation, 30.0));
            p.sunIntensity = 0.0f; // no scattered light: the disc's pixels are its transmittance
            p.sunDiscRadiance = 1.0f;
            p.sunAngularRadius = 0.05f;
            p.lookupTable = table;
            auto v = skyViewer(p.sunDirection, kOdd);
            v->setSceneData(SkyNode::create(p));
            v->frame();
            // Per pixel the view ray's own column; through the table the CPU's along the sun.
            const glm::dvec3 along =
                table ? glm::dvec3(p.sunDirection) : glm::dvec3(rayOf(*v, kMiddle, kMiddle));
            const glm::dvec3 want = elevation == 90.0 ? skyref::zenithTransmittance(m, 2.0)
                                                      : skyref::sunTransmittance(m, along, 2.0);
            expectOpticalDepth(glm::dvec3(pixel(*v, kMiddle, kMiddle)), want,
                               std::string(table ? "table" : "direct") + ", the disc at " +
                                   std::to_string(elevation) + "°");
        }
}

// Single-scattered radiance against the reference: view elevations from −5° to 90° (the rows of
// a 100° view nearest −5, 0, 2, 5, 10, 20, 45 and 90°, and three of them 40–50° to either side in
// azimuth), the sun at −5 to 90°, the view towards and away from the sun, per pixel and through
// the table.
TEST(Sky, RadianceMatchesADoublePrecisionReference) {
    const skyref::Medium m = skyref::medium(sky::Atmosphere{});
    double worst[2] = {0.0, 0.0};
    for (const double sunElevation : {-5.0, 0.0, 3.0, 10.0, 30.0, 60.0, 90.0})
        for (const double yaw : {0.0, 180.0}) {
            SkyParameters p;
            p.sunDirection = glm::vec3(towards(sunElevation, 30.0));
            const glm::vec3 look(towards(42.5, 30.0 + yaw));
            std::vector<glm::ivec2> at;
            std::vector<glm::dvec3> want;
            for (const bool table : {false, true}) {
                p.lookupTable = table;
                auto v = skyViewer(look, kSize, 100.0f);
                v->setSceneData(SkyNode::create(p));
                v->frame();
                if (at.empty()) {
                    at = pixelsAtElevations(*v);
                    for (const glm::ivec2 xy : at)
                        want.push_back(skyref::radiance(m, glm::dvec3(rayOf(*v, xy.x, xy.y)),
                                                        glm::dvec3(p.sunDirection), p.sunIntensity, 2.0));
                }
                const FloatImage img = v->renderer().readPixelsLinear();
                for (std::size_t i = 0; i < at.size(); ++i) {
                    const double viewElevation = elevationOf(glm::dvec3(rayOf(*v, at[i].x, at[i].y)));
                    std::ostringstream where;
                    where << (table ? "table" : "direct") << ": sun at " << sunElevation << "°, view at "
                          << viewElevation << "° (pixel " << at[i].x << "," << at[i].y << ", yaw " << yaw
                          << ")";
                    worst[table] = std::max(
                        worst[table], expectRadiance(pixel(img, at[i].x, at[i].y), want[i],
                                                     radianceTolerance(viewElevation, table), where.str()));
                }
            }
        }
    std::printf("largest error / tolerance: direct %.2f, table %.2f\n", worst[0], worst[1]);
}

// The fog's colour (SkyNode::horizonColor: 1° above the horizon, 8 azimuths) against the
// reference's mean of the same 8 directions.
TEST(Sky, HorizonColourForTheFogMatchesTheReference) {
    const skyref::Medium m = skyref::medium(sky::Atmosphere{});
    struct Case {
        double sunElevation, altitude;
    };
    for (const Case k :
         {Case{-5, 0}, Case{0, 0}, Case{3, 0}, Case{10, 0}, Case{30, 0}, Case{90, 0}, Case{10, 1500}}) {
        SkyParameters p;
        p.sunDirection = glm::vec3(towards(k.sunElevation, 30.0));
        p.altitude = float(k.altitude);
        auto fog = FogNode::create(FogParameters::ground());
        auto sky = SkyNode::create(p);
        sky->attachFog(fog);
        UpdateVisitor uv;
        sky->update(uv);
        glm::dvec3 want(0.0);
        for (int i = 0; i < 8; ++i)
            want += skyref::radiance(m, towards(1.0, 45.0 * i), glm::dvec3(p.sunDirection), p.sunIntensity,
                                     k.altitude) /
                    8.0;
        std::ostringstream where;
        where << "sun at " << k.sunElevation << "°, altitude " << k.altitude << " m";
        expectRadiance(fog->parameters().color, want, radianceTolerance(1.0, false), where.str());
    }
}

// attachShadow: the shadow node's sun follows the sky's (direction and transmittance) every
// frame; at night its colour is 0 and no shadow map is planned.
TEST(Sky, DrivesTheShadowSun) {
    for (const float hours : {10.0f, 23.0f}) {
        SCOPED_TRACE(hours);
        auto v = skyViewer({0, 1, 0.1f});
        auto sky = SkyNode::create(SkyParameters::atTime(hours));
        auto sun = Light::create(LightType::Directional);
        auto shadows = ShadowNode::create(sun);
        shadows->addChild(shapes::quad(20.0f, 20.0f));
        shadows->addChild(shapes::box({1.0f, 1.0f, 1.0f}));
        sky->attachShadow(shadows);
        auto root = Group::create();
        root->addChild(sun);
        root->addChild(sky);
        root->addChild(shadows);
        v->setSceneData(root);
        v->frame();
        const SkyParameters& p = sky->parameters();
        EXPECT_EQ(sun->direction, -p.sunDirection);
        const glm::vec3 t = sky::sunTransmittance(p.atmosphere, p.sunDirection, p.altitude);
        EXPECT_EQ(sun->color, t);
        EXPECT_EQ(shadows->lastFrame().active, p.sunDirection.z > 0.0f);
        EXPECT_EQ(t == glm::vec3(0.0f), p.sunDirection.z < 0.0f);
    }
}

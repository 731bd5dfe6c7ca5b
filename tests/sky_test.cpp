// SkyNode against its CPU mirror (SkyMath.h): sky pixels along known directions, the sun's
// disc, the blue noon and red sunset, geometry hiding the sky, the fog taking the horizon colour.
#include "TestUtil.h"

#include <sstream>

#include <fog/FogNode.h>
#include <sgfx/Group.h>
#include <sgfx/Material.h>
#include <sgfx/Shapes.h>
#include <sgfx/StateSet.h>
#include <sky/SkyNode.h>

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

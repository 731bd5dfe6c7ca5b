// VolumeNode against closed forms (lecture 12): Beer–Lambert transmittance, absorption +
// emission, the k_a → 0 limit, the camera inside, an opaque wall inside the medium, single
// scattering in a homogeneous box, early termination's bound, empty-space skipping and jitter
// leaving the image as it was, phase functions' normalisation; bad input; splatting's footprint
// and its convergence to the march as the kernel spacing shrinks. Linear float targets, 64×64.
#include "TestUtil.h"

#include <sgfx/Group.h>
#include <sgfx/Image.h>
#include <sgfx/Material.h>
#include <sgfx/Shapes.h>
#include <sgfx/StateSet.h>
#include <sgfx/nodes/fog/FogNode.h>
#include <sgfx/nodes/volume/VolumeNode.h>

#include <sgfx/gl/Objects.h>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>

using namespace sgfx;
using namespace sgfx::test;

namespace {

constexpr int kSize = 64;

// Looking along +Y from (0, −eyeDistance, 0) at the origin; linear float colour target.
std::unique_ptr<Viewer> floatViewer(float eyeY = -5.0f) {
    auto v = Viewer::createHeadless(kSize, kSize);
    v->renderer().options().colorTarget = RendererOptions::ColorTarget::Rgba32F;
    auto& cam = *v->camera();
    cam.setPerspective(40.0f, 0.1f, 100.0f);
    cam.setLookAt({0, eyeY, 0}, {0, eyeY + 1.0f, 0}, {0, 0, 1});
    cam.computeNearFar = false;
    cam.clearColor = {0, 0, 0, 1};
    return v;
}

// An emissive wall facing the camera at y = `y` (exact colour: no lights).
std::shared_ptr<Node> wall(float y, glm::vec3 color) {
    auto t = Transform::create(
        glm::rotate(glm::translate(glm::mat4(1.0f), {0, y, 0}), glm::radians(90.0f), glm::vec3(1, 0, 0)));
    auto q = shapes::quad(40, 40);
    auto m = Material::create();
    m->ambient = glm::vec3(0);
    m->diffuse = glm::vec4(0, 0, 0, 1);
    m->emissive = color;
    q->getOrCreateStateSet().material.set(m);
    q->getOrCreateStateSet().cullFace.set(CullFace::None);
    t->addChild(q);
    return t;
}

glm::vec3 centrePixel(Viewer& v) {
    const FloatImage img = v.renderer().readPixelsLinear();
    // The four pixels around the image centre: their rays leave the axis by half a pixel.
    glm::vec3 sum(0.0f);
    for (int y = kSize / 2 - 1; y <= kSize / 2; ++y)
        for (int x = kSize / 2 - 1; x <= kSize / 2; ++x) {
            const float* p = &img.rgba[(std::size_t(y) * kSize + x) * 4];
            sum += glm::vec3(p[0], p[1], p[2]);
        }
    return sum / 4.0f;
}

VolumeParameters homogeneous(float ka, glm::vec3 ke = glm::vec3(0.0f)) {
    VolumeParameters p;
    p.size = glm::vec3(2.0f);
    p.absorption = ka;
    p.emission = ke;
    p.earlyTermination = 1.0f;
    return p;
}

// The volume alone in floatViewer's view, read back linear.
FloatImage renderAlone(const VolumeParameters& p, VolumeGrid grid) {
    auto v = floatViewer();
    v->setSceneData(VolumeNode::create(p, std::move(grid)));
    v->frame();
    return v->renderer().readPixelsLinear();
}

} // namespace

TEST(VolumeMath, PhaseFunctionsIntegrateToOneOverTheSphere) {
    auto integrate = [](const std::function<double(double)>& f) {
        // ∫ p(cos θ) dω = 2π ∫_{-1}^{1} p(μ) dμ (Simpson, 20000 intervals)
        const int n = 20000;
        double s = f(-1.0) + f(1.0);
        for (int i = 1; i < n; ++i)
            s += f(-1.0 + 2.0 * i / n) * (i % 2 ? 4.0 : 2.0);
        return 2.0 * volume::kPi * s * (2.0 / n) / 3.0;
    };
    for (double g : {-0.7, 0.0, 0.3, 0.8})
        EXPECT_NEAR(integrate([g](double mu) { return volume::henyeyGreensteinPhase(mu, g); }), 1.0, 1e-4)
            << g;
    EXPECT_NEAR(integrate([](double mu) { return volume::rayleighPhase(mu); }), 1.0, 1e-9);
    EXPECT_NEAR(integrate([](double mu) { return volume::isotropicPhase(mu); }), 1.0, 1e-12);
    for (double mu : {-1.0, -0.2, 0.0, 0.6, 1.0})
        EXPECT_DOUBLE_EQ(volume::henyeyGreensteinPhase(mu, 0.0), 1.0 / (4.0 * volume::kPi));
}

TEST(VolumeMath, MarchMatchesTheClosedFormAndTheLecturesSumDoesLess) {
    const double ka = 1.3, ke = 0.7, L = 2.0;
    auto sigma = [&](double) { return ka; };
    auto src = [&](double) { return glm::dvec3(ke); };
    const auto exact = volume::march(L, 64, sigma, src, volume::Integration::Exact);
    const auto lecture = volume::march(L, 64, sigma, src, volume::Integration::Riemann);
    EXPECT_NEAR(exact.radiance.x, volume::emitted(ka, ke, L), 1e-12);
    EXPECT_NEAR(exact.transmittance, volume::transmittance(ka, L), 1e-12);
    const double lectureError = std::abs(lecture.radiance.x - volume::emitted(ka, ke, L));
    // The lecture's sum lets each sample dim its own emission: biased low by about ka·Δx/2, which
    // for these values is already past the 1e-2 the exact steps meet with room to spare.
    EXPECT_GT(lectureError, 5e-3);
    EXPECT_GT(lectureError, 1e6 * std::abs(exact.radiance.x - volume::emitted(ka, ke, L)));
    EXPECT_NEAR(volume::emitted(0.0, ke, L), ke * L, 1e-15); // the k_a → 0 limit
}

TEST(Volume, AbsorptionOnlyTransmitsBeerLambert) {
    for (const float ka : {0.2f, 0.8f, 2.0f}) {
        auto v = floatViewer();
        auto root = Group::create();
        root->addChild(wall(3.0f, glm::vec3(1.0f)));
        root->addChild(VolumeNode::create(homogeneous(ka)));
        v->setSceneData(root);
        v->frame();
        EXPECT_NEAR(centrePixel(*v).g, std::exp(-ka * 2.0), 1e-3) << "k_a " << ka;
    }
}

TEST(Volume, AbsorptionAndEmissionMatchTheClosedFormAndTheZeroAbsorptionLimit) {
    const glm::vec3 ke(0.1f, 0.3f, 0.5f);
    for (const float ka : {0.0f, 1e-4f, 0.5f, 1.5f}) {
        auto v = floatViewer();
        auto root = Group::create();
        root->addChild(VolumeNode::create(homogeneous(ka, ke)));
        v->setSceneData(root);
        v->frame();
        const glm::vec3 px = centrePixel(*v);
        for (int c = 0; c < 3; ++c) {
            ASSERT_TRUE(std::isfinite(px[c]));
            EXPECT_NEAR(px[c], volume::emitted(ka, ke[c], 2.0),
                        1e-2 * std::max(1.0, volume::emitted(ka, ke[c], 2.0)))
                << "k_a " << ka << " channel " << c;
        }
    }
}

TEST(Volume, CameraInsideMeasuresThePathFromTheCamera) {
    const float ka = 0.9f;
    const glm::vec3 ke(0.4f);
    auto v = floatViewer(0.0f); // at the box's centre, looking along +Y: 1 m to the face
    auto root = Group::create();
    root->addChild(wall(3.0f, glm::vec3(1.0f)));
    root->addChild(VolumeNode::create(homogeneous(ka, ke)));
    v->setSceneData(root);
    v->frame();
    EXPECT_NEAR(centrePixel(*v).r, std::exp(-ka * 1.0) + volume::emitted(ka, ke.r, 1.0), 2e-3);
}

TEST(Volume, AnOpaqueWallInsideStopsTheMarch) {
    const float ka = 0.7f;
    const glm::vec3 ke(0.2f), wallColor(0.9f, 0.5f, 0.1f);
    auto v = floatViewer();
    auto root = Group::create();
    root->addChild(wall(0.25f, wallColor)); // inside the box (y from −1 to 1): 1.25 m of medium
    root->addChild(VolumeNode::create(homogeneous(ka, ke)));
    v->setSceneData(root);
    v->frame();
    const glm::vec3 px = centrePixel(*v);
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(px[c], wallColor[c] * std::exp(-ka * 1.25) + volume::emitted(ka, ke[c], 1.25), 2e-3) << c;
}

TEST(Volume, SingleScatteringOfAHomogeneousBox) {
    // Light falls straight down; the centre ray runs 2 m through the box at mid height, where
    // every point has 1 m of medium above it: L = E·p·e^(−ks·1)·(1 − e^(−ks·2)), isotropic p.
    const float ks = 0.6f;
    VolumeParameters p = homogeneous(0.0f);
    p.scattering = ks;
    p.phase = VolumePhase::Isotropic;
    p.lightColor = glm::vec3(3.0f);
    p.lightDirection = {0, 0, -1};
    auto v = floatViewer();
    v->setSceneData(VolumeNode::create(p));
    v->frame();
    const double expected = 3.0 / (4.0 * volume::kPi) * std::exp(-ks * 1.0) * (1.0 - std::exp(-ks * 2.0));
    EXPECT_NEAR(centrePixel(*v).r, expected, 2e-3 * expected + 1e-4);
}

TEST(Volume, EarlyTerminationChangesThePixelByLessThanItsThreshold) {
    for (const float threshold : {0.9f, 0.99f}) {
        auto render = [&](float t) {
            auto v = floatViewer();
            auto root = Group::create();
            root->addChild(wall(3.0f, glm::vec3(1.0f)));
            VolumeParameters p = homogeneous(3.0f, glm::vec3(0.5f));
            p.earlyTermination = t;
            root->addChild(VolumeNode::create(p));
            v->setSceneData(root);
            v->frame();
            return centrePixel(*v);
        };
        const glm::vec3 full = render(1.0f), early = render(threshold);
        // What is left out is at most the remaining transmittance times what lies behind.
        EXPECT_LE(std::abs(full.r - early.r), (1.0f - threshold) * std::max(1.0f, 0.5f / 3.0f) + 1e-4f);
        EXPECT_GT(std::abs(full.r - early.r), 0.0f) << "it did stop early";
    }
}

TEST(Volume, EmptySpaceSkippingSkipsSamplesAndKeepsTheImage) {
    // A ball of radius 0.25 in the box: the coarse cells (8³ voxels) around it are empty, so
    // skipping must take measurably fewer density samples (counted per pixel by the march's
    // diagnostic output) and give the same image.
    auto render = [](bool skip, bool count) {
        VolumeParameters p = homogeneous(1.2f, glm::vec3(0.6f, 0.4f, 0.2f));
        p.emptySpaceSkipping = skip;
        p.debugSampleCount = count;
        return renderAlone(p, VolumeGrid::sphere(64, 0.25f, 0.05f));
    };
    const FloatImage a = render(false, false), b = render(true, false);
    double maxDiff = 0;
    for (std::size_t i = 0; i < a.rgba.size(); ++i)
        maxDiff = std::max(maxDiff, double(std::abs(a.rgba[i] - b.rgba[i])));
    EXPECT_LT(maxDiff, 1e-5) << "skipping jumps only over exact zeros";
    const FloatImage all = render(false, true), skipped = render(true, true);
    double taken = 0, withSkipping = 0;
    for (std::size_t i = 0; i < all.rgba.size(); i += 4) {
        taken += all.rgba[i];
        withSkipping += skipped.rgba[i];
    }
    std::printf("density samples: %.0f marching every step, %.0f with empty-space skipping (%.1f %%)\n",
                taken, withSkipping, 100.0 * withSkipping / taken);
    EXPECT_GT(taken, 64.0 * 64.0) << "the box covers the view and every ray samples";
    EXPECT_LT(withSkipping, 0.8 * taken) << "skipping leaves out at least a fifth of the samples";
}

TEST(Volume, JitterTurnsBandingIntoNoise) {
    // Four steps through a ball with a hard edge: each pixel's sum misses the integral (a
    // 256-step march) by an error that, without jitter, is nearly the same for neighbouring
    // pixels (rings: the samples of neighbouring rays sit at the same depths); with jitter each
    // pixel starts at its own random offset and the error changes from pixel to pixel. Measured
    // as the correlation of the errors of horizontally adjacent pixels over the ball.
    auto render = [](int steps, bool jitter) {
        VolumeParameters p = homogeneous(2.0f, glm::vec3(1.0f, 0.7f, 0.4f));
        p.steps = steps;
        p.jitter = jitter;
        return renderAlone(p, VolumeGrid::sphere(64, 0.4f, 0.01f));
    };
    const FloatImage reference = render(256, false);
    auto neighbourCorrelation = [&](const FloatImage& img, double& rms) {
        std::vector<std::pair<double, double>> pairs;
        for (int y = 0; y < kSize; ++y)
            for (int x = 0; x + 1 < kSize; ++x) {
                const std::size_t i = (std::size_t(y) * kSize + x) * 4, j = i + 4;
                if (reference.rgba[i + 3] < 0.05f || reference.rgba[j + 3] < 0.05f) continue; // off the ball
                pairs.emplace_back(img.rgba[i] - reference.rgba[i], img.rgba[j] - reference.rgba[j]);
            }
        double ma = 0, mb = 0;
        for (const auto& [a, b] : pairs)
            ma += a, mb += b;
        ma /= double(pairs.size()), mb /= double(pairs.size());
        double sab = 0, saa = 0, sbb = 0;
        for (const auto& [a, b] : pairs)
            sab += (a - ma) * (b - mb), saa += (a - ma) * (a - ma), sbb += (b - mb) * (b - mb);
        rms = std::sqrt(saa / double(pairs.size()));
        return sab / std::sqrt(saa * sbb);
    };
    double rmsBanded = 0, rmsJittered = 0;
    const double banded = neighbourCorrelation(render(4, false), rmsBanded);
    const double jittered = neighbourCorrelation(render(4, true), rmsJittered);
    std::printf("4 steps against 256: neighbour correlation of the error %.3f without jitter (rms %.4f), "
                "%.3f with (rms %.4f)\n",
                banded, rmsBanded, jittered, rmsJittered);
    EXPECT_GT(rmsBanded, 1e-3) << "4 steps are far enough off for the test to mean something";
    EXPECT_GT(banded, 0.5) << "without jitter the error comes in bands";
    EXPECT_LT(jittered, 0.2) << "with jitter it is noise";
}

TEST(Volume, HalfResolutionMatchesFullInsideAndRespectsAWallInFront) {
    auto render = [](bool half) {
        auto v = floatViewer();
        auto root = Group::create();
        root->addChild(wall(3.0f, glm::vec3(1.0f)));
        // A narrow opaque post in front of the box's left half: its pixels must stay its colour.
        auto post = Transform::create(glm::translate(glm::mat4(1.0f), {-0.6f, -2.0f, 0.0f}) *
                                      glm::rotate(glm::mat4(1.0f), glm::radians(90.0f), glm::vec3(1, 0, 0)));
        auto q = shapes::quad(0.4f, 4.0f);
        auto m = Material::create();
        m->ambient = glm::vec3(0);
        m->diffuse = glm::vec4(0, 0, 0, 1);
        m->emissive = glm::vec3(0.0f, 1.0f, 0.0f);
        q->getOrCreateStateSet().material.set(m);
        q->getOrCreateStateSet().cullFace.set(CullFace::None);
        post->addChild(q);
        root->addChild(post);
        VolumeParameters p = homogeneous(0.8f, glm::vec3(0.5f, 0.2f, 0.1f));
        p.halfResolution = half;
        root->addChild(VolumeNode::create(p));
        v->setSceneData(root);
        v->frame();
        return v->renderer().readPixelsLinear();
    };
    const FloatImage full = render(false), half = render(true);
    auto at = [](const FloatImage& img, int x, int y, int c) {
        return img.rgba[(std::size_t(y) * kSize + x) * 4 + c];
    };
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(at(half, kSize / 2 + 4, kSize / 2, c), at(full, kSize / 2 + 4, kSize / 2, c), 2e-3) << c;
    // Every pixel of the post (pure green in the full image) stays green: no smoke bleeds onto it.
    int postPixels = 0;
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x)
            if (at(full, x, y, 1) > 0.99f && at(full, x, y, 0) < 0.01f) {
                ++postPixels;
                EXPECT_LT(at(half, x, y, 0), 0.02f) << x << "," << y;
            }
    EXPECT_GT(postPixels, 50);
}

TEST(Volume, SlicingApproachesTheClosedForms) {
    const float ka = 0.8f;
    const glm::vec3 ke(0.3f);
    auto v = floatViewer();
    auto root = Group::create();
    root->addChild(wall(3.0f, glm::vec3(1.0f)));
    VolumeParameters p = homogeneous(ka, ke);
    p.method = VolumeMethod::Slicing;
    p.slices = 256;
    root->addChild(VolumeNode::create(p));
    v->setSceneData(root);
    v->frame();
    // Slices cut at most one spacing off each end of the path: about σ·spacing of relative error.
    const double expected = std::exp(-ka * 2.0) + volume::emitted(ka, ke.r, 2.0);
    EXPECT_NEAR(centrePixel(*v).r, expected, 3e-2 * expected);
}

TEST(Volume, FogAppliesUpToWhereTheMediumStarts) {
    const float ka = 0.5f, rho = 0.05f;
    const glm::vec3 ke(0.4f), fogColor(0.2f, 0.4f, 0.8f);
    auto v = floatViewer();
    FogParameters fp;
    fp.density = rho;
    fp.falloff = 0.0f;
    fp.color = fogColor;
    fp.sky = FogSky::Off;
    auto fog = FogNode::create(fp);
    fog->addChild(VolumeNode::create(homogeneous(ka, ke)));
    v->setSceneData(fog);
    v->frame();
    // Premultiplied: c·(1 − k) + fog·α·k with k = 1 − e^(−ρ·4) (the medium starts 4 m away).
    const double k = 1.0 - std::exp(-rho * 4.0), alpha = 1.0 - std::exp(-ka * 2.0);
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(centrePixel(*v)[c], volume::emitted(ka, ke[c], 2.0) * (1 - k) + fogColor[c] * alpha * k,
                    3e-3)
            << c;
}

TEST(Volume, TransferFunctionColoursTheEmissionByDensity) {
    // A ramp that is pure red at density 0.5 (sRGB 255 → linear 1): only the red emission stays.
    auto ramp = Image::create(3, 1, 3);
    for (int x = 0; x < 3; ++x) {
        ramp->pixel(x, 0)[0] = 255;
        ramp->pixel(x, 0)[1] = ramp->pixel(x, 0)[2] = 0;
    }
    VolumeParameters p = homogeneous(0.6f, glm::vec3(0.5f));
    auto node = VolumeNode::create(p, VolumeGrid::constant(0.5f));
    node->setTransferFunction(ramp);
    auto v = floatViewer();
    v->setSceneData(node);
    v->frame();
    const glm::vec3 px = centrePixel(*v);
    EXPECT_NEAR(px.r, volume::emitted(0.3, 0.25, 2.0), 1e-3);
    EXPECT_NEAR(px.g, 0.0f, 1e-5f);
}

TEST(Volume, DensityFunctionEqualsTheSameGrid) {
    VolumeParameters p = homogeneous(0.8f, glm::vec3(0.3f));
    auto a = floatViewer();
    a->setSceneData(VolumeNode::create(p, VolumeGrid::constant(0.5f)));
    a->frame();
    auto b = floatViewer();
    b->setSceneData(VolumeNode::createFunction(p, "return 0.5;"));
    b->frame();
    EXPECT_NEAR(centrePixel(*a).r, centrePixel(*b).r, 1e-5);
    EXPECT_NEAR(centrePixel(*a).r, volume::emitted(0.4, 0.15, 2.0), 1e-3);
}

TEST(Volume, BadInputIsRefusedWithItsReason) {
    auto node = VolumeNode::create();
    auto expectRefused = [&](const std::function<void()>& f, const std::string& needle) {
        try {
            f();
            ADD_FAILURE() << "accepted: " << needle;
        } catch (const std::exception& e) {
            EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
        }
    };
    VolumeParameters p;
    p.absorption = -1.0f;
    expectRefused([&] { node->setParameters(p); }, "absorption");
    p = {};
    p.g = 1.0f;
    expectRefused([&] { node->setParameters(p); }, "g");
    p = {};
    p.steps = 0;
    expectRefused([&] { node->setParameters(p); }, "steps");
    p = {};
    p.size.y = std::numeric_limits<float>::quiet_NaN();
    expectRefused([&] { node->setParameters(p); }, "size");
    p = {};
    p.lightDirection = glm::vec3(0.0f);
    expectRefused([&] { node->setParameters(p); }, "lightDirection");
    VolumeGrid g = VolumeGrid::constant(1.0f);
    g.values[3] = -2.0f;
    expectRefused([&] { node->setGrid(g); }, "voxel 3");
    g = VolumeGrid::constant(1.0f);
    g.values.pop_back();
    expectRefused([&] { node->setGrid(g); }, "7 values for 8 voxels");
    const auto raw = std::filesystem::temp_directory_path() / "sgfx_volume_short.raw";
    {
        std::ofstream f(raw, std::ios::binary);
        f << "abc";
    }
    expectRefused(
        [&] {
            (void)VolumeGrid::loadRaw(raw, {2, 2, 2}, VolumeGrid::Format::R8);
        },
        "the file has 3");
    expectRefused(
        [&] {
            (void)VolumeGrid::loadRaw("/nonexistent.raw", {2, 2, 2}, VolumeGrid::Format::R8);
        },
        "cannot open");
    std::filesystem::remove(raw);
    expectRefused([&] { (void)VolumeNode::createFunction({}, "  "); }, "empty");
    EXPECT_EQ(node->parameters().absorption, 1.0f); // kept
}

TEST(Volume, RawFileLoadsEachFormat) {
    const auto raw = std::filesystem::temp_directory_path() / "sgfx_volume.raw";
    {
        std::ofstream f(raw, std::ios::binary);
        const float v[8] = {0, 0.5f, 1, 2, 0, 0, 0, 3};
        f.write(reinterpret_cast<const char*>(v), sizeof v);
    }
    const VolumeGrid g = VolumeGrid::loadRaw(raw, {2, 2, 2}, VolumeGrid::Format::R32F);
    EXPECT_EQ(g.values[3], 2.0f);
    EXPECT_EQ(g.values[7], 3.0f);
    {
        std::ofstream f(raw, std::ios::binary);
        const unsigned char b[8] = {0, 51, 255, 0, 0, 0, 0, 102};
        f.write(reinterpret_cast<const char*>(b), sizeof b);
    }
    EXPECT_FLOAT_EQ(VolumeGrid::loadRaw(raw, {2, 2, 2}, VolumeGrid::Format::R8).values[1], 0.2f);
    {
        std::ofstream f(raw, std::ios::binary);
        const std::uint16_t h[8] = {0x3c00, 0x3800, 0, 0, 0, 0, 0, 0x4000}; // 1, 0.5, ..., 2
        f.write(reinterpret_cast<const char*>(h), sizeof h);
    }
    const VolumeGrid half = VolumeGrid::loadRaw(raw, {2, 2, 2}, VolumeGrid::Format::R16F);
    EXPECT_EQ(half.values[0], 1.0f);
    EXPECT_EQ(half.values[1], 0.5f);
    EXPECT_EQ(half.values[7], 2.0f);
    std::filesystem::remove(raw);
}

// ---------------------------------------------------------------- splatting
TEST(VolumeMath, SplatFootprintIsTheKernelsLineIntegralAndTheLatticeSumsToThePath) {
    // ∫ h³·G3 along a line at distance r (Simpson over ±8 s) against the footprint h³·G2(r) the
    // shader uses (the footprint's disc renormalisation divided out).
    const volume::SplatLattice l = volume::splatLattice({1.0, 1.0, 1.0}, 0.1);
    const double s = l.sigma, h3 = l.spacing.x * l.spacing.y * l.spacing.z;
    const double disc = 1.0 - std::exp(-0.5 * volume::kSplatRadiusSigmas * volume::kSplatRadiusSigmas);
    for (double r : {0.0, 0.5 * s, 1.3 * s, 2.5 * s}) {
        const int n = 4000;
        const double a = -8.0 * s, dt = 16.0 * s / n;
        double sum = 0.0;
        for (int i = 0; i <= n; ++i) {
            const double t = a + i * dt;
            const double g3 =
                std::exp(-(r * r + t * t) / (2 * s * s)) / std::pow(2 * volume::kPi * s * s, 1.5);
            sum += g3 * (i == 0 || i == n ? 1.0 : i % 2 ? 4.0 : 2.0);
        }
        EXPECT_NEAR(h3 * sum * dt / 3.0, volume::splatFootprint(r, l) * disc, 1e-9) << r;
    }
    // A ray through a uniform box's lattice, anywhere between kernels, crosses Σ ℓ_i = the box's
    // depth (the partition of unity, within the truncation's and ripple's 1%).
    for (double x : {0.0, 0.013, 0.05})
        for (double spacing : {0.2, 0.1, 0.05}) {
            const volume::SplatLattice b = volume::splatLattice({1.0, 1.0, 1.0}, spacing);
            double path = 0.0;
            for (int k = 0; k < b.count.z; ++k)
                for (int j = 0; j < b.count.y; ++j)
                    for (int i = 0; i < b.count.x; ++i) {
                        const glm::dvec3 c = b.centre({i, j, k}, {1.0, 1.0, 1.0});
                        path += volume::splatFootprint(glm::length(glm::dvec2(c.x - x, c.z)), b);
                    }
            EXPECT_NEAR(path, 1.0, 1e-2) << "x " << x << " spacing " << spacing;
        }
}

namespace {
// A Gaussian ball ρ = e^(−|p|²/2w²), w = 0.4 m, in floatViewer's 2 m box; its optical depth
// through the centre is ka·w·√(2π)·erf(1/(√2·w)).
constexpr float kBallWidth = 0.4f;
const char* kGaussianBall = "vec3 p = (uvw - 0.5) * 2.0; return exp(-dot(p, p) / (2.0 * 0.16));";

// The medium in front of a white wall in floatViewer's view; `bytes`: the renderer's default
// 8-bit sRGB target read back as its bytes, else the float target read back linear.
std::unique_ptr<Viewer> renderMediumIn(const VolumeParameters& p, bool ball, bool bytes) {
    auto v = floatViewer();
    if (bytes) v->renderer().options().colorTarget = RendererOptions{}.colorTarget;
    auto root = Group::create();
    root->addChild(wall(3.0f, glm::vec3(1.0f)));
    root->addChild(ball ? VolumeNode::createFunction(p, kGaussianBall) : VolumeNode::create(p));
    v->setSceneData(root);
    v->frame();
    EXPECT_TRUE(v->renderer().takeGlErrors().empty());
    return v;
}

FloatImage renderMedium(const VolumeParameters& p, bool ball) {
    return renderMediumIn(p, ball, false)->renderer().readPixelsLinear();
}

// Mean |sRGB(a) − sRGB(reference)| over the colour channels, in 8-bit steps (a: bytes or linear).
double byteError(const Image& a, const FloatImage& reference) {
    double sum = 0.0;
    for (std::size_t i = 0; i < reference.rgba.size(); ++i)
        if (i % 4 != 3) sum += std::abs(double(a.pixels[i]) - 255.0 * srgbEncode(reference.rgba[i]));
    return sum / double(reference.rgba.size() / 4 * 3);
}
double byteError(const FloatImage& a, const FloatImage& reference) {
    double sum = 0.0;
    for (std::size_t i = 0; i < reference.rgba.size(); ++i)
        if (i % 4 != 3) sum += 255.0 * std::abs(srgbEncode(a.rgba[i]) - srgbEncode(reference.rgba[i]));
    return sum / double(reference.rgba.size() / 4 * 3);
}

double meanError(const FloatImage& a, const FloatImage& b) {
    double sum = 0.0;
    for (std::size_t i = 0; i < a.rgba.size(); ++i)
        if (i % 4 != 3) sum += std::abs(double(a.rgba[i]) - double(b.rgba[i]));
    return sum / double(a.rgba.size() / 4 * 3);
}

glm::vec3 centreOf(const FloatImage& img) {
    glm::vec3 sum(0.0f);
    for (int y = kSize / 2 - 1; y <= kSize / 2; ++y)
        for (int x = kSize / 2 - 1; x <= kSize / 2; ++x)
            sum += glm::make_vec3(&img.rgba[(std::size_t(y) * kSize + x) * 4]);
    return sum / 4.0f;
}
} // namespace

namespace {
// Both analytic media with absorption and emission in front of a white wall (the ball's
// optical depth through its centre 1.2·w·√(2π)·erf(1/(√2·w))): `error` measures splats at three
// spacings (64, 512, 4096 or 32768 kernels) against a 256-step march; the errors are checked to
// fall with the spacing and returned.
std::vector<double>
splatErrors(bool ball, const std::function<double(const VolumeParameters&, const FloatImage&)>& error) {
    VolumeParameters p = homogeneous(ball ? 1.2f : 0.8f, glm::vec3(0.3f, 0.2f, 0.1f));
    p.steps = 256;
    const FloatImage reference = renderMedium(p, ball);
    p.method = VolumeMethod::Splatting;
    std::vector<double> errors;
    for (const float spacing : {0.5f, 0.25f, 0.0625f}) {
        p.splatSpacing = spacing;
        errors.push_back(error(p, reference));
    }
    for (std::size_t i = 0; i + 1 < errors.size(); ++i)
        EXPECT_LT(errors[i + 1], errors[i]) << (ball ? "ball" : "box") << " spacing step " << i;
    return errors;
}
} // namespace

TEST(Volume, SplattingConvergesToTheRaymarchedReferenceAsTheSpacingShrinks) {
    // The image's mean error in a float target, and the ball's centre pixel against the closed form.
    for (const bool ball : {false, true}) {
        const std::vector<double> errors =
            splatErrors(ball, [&](const VolumeParameters& p, const FloatImage& ref) {
                const FloatImage splats = renderMedium(p, ball);
                if (p.splatSpacing == 0.0625f && ball) {
                    // The ray passes within 0.03 m of the centre: e^(−0.03²/2w²) costs 0.3% of the depth.
                    const double depth = 1.2 * kBallWidth * std::sqrt(2.0 * volume::kPi) *
                                         std::erf(1.0 / (std::sqrt(2.0) * kBallWidth));
                    const double expected = std::exp(-depth) + 0.3 / 1.2 * (1.0 - std::exp(-depth));
                    EXPECT_NEAR(centreOf(splats).r, expected, 0.01);
                }
                return meanError(splats, ref);
            });
        EXPECT_LT(errors.back(), ball ? 2e-3 : 5e-3) << (ball ? "ball" : "box");
        std::printf("splatting %s: mean error %.4f %.4f %.4f\n", ball ? "ball" : "box", errors[0], errors[1],
                    errors[2]);
    }
}

TEST(Volume, SplattingConvergesInTheDefault8BitSrgbTargetToo) {
    // The splats accumulate in a float target of their own and are composited once, so the 8-bit
    // sRGB target rounds once per pixel, not once per kernel. Against the float march encoded to
    // sRGB on the CPU, the mean error falls with the spacing and ends within half a step of the
    // float target's (drawn straight into 8 bits, the finest lattice's faint layers rounded
    // away: box 1.3 steps, ball 3.3 and rising, against 0.3 and 0.06).
    for (const bool ball : {false, true}) {
        double floatError = 0.0;
        const std::vector<double> errors =
            splatErrors(ball, [&](const VolumeParameters& p, const FloatImage& ref) {
                if (p.splatSpacing == 0.0625f) floatError = byteError(renderMedium(p, ball), ref);
                return byteError(renderMediumIn(p, ball, true)->renderer().readPixels(), ref);
            });
        EXPECT_LT(errors.back(), floatError + 0.5) << (ball ? "ball" : "box");
        std::printf("splatting %s, 8-bit steps: %.2f %.2f %.2f (float target %.2f)\n", ball ? "ball" : "box",
                    errors[0], errors[1], errors[2], floatError);
    }
}

TEST(Volume, SplatsBehindAnOpaqueWallAreHiddenAndNothingLeaks) {
    const long before = gl::liveObjects().total();
    {
        const float ka = 0.8f;
        auto v = floatViewer();
        auto root = Group::create();
        root->addChild(wall(0.0f, glm::vec3(1.0f))); // through the box's middle
        VolumeParameters p = homogeneous(ka);
        p.method = VolumeMethod::Splatting;
        p.splatSpacing = 0.0625f;
        root->addChild(VolumeNode::create(p));
        v->setSceneData(root);
        v->frame();
        v->frame(); // and sorted again
        // The front metre only; kernels whose centre is within their blur of the wall are cut
        // whole, about σ·s of optical depth.
        EXPECT_NEAR(centrePixel(*v).g, std::exp(-ka * 1.0), 0.03);
        EXPECT_TRUE(v->renderer().takeGlErrors().empty());
    }
    EXPECT_EQ(gl::liveObjects().total(), before);
}

TEST(Volume, BadSplatSpacingIsRefusedNamingIt) {
    auto node = VolumeNode::create();
    for (const float spacing : {0.0f, -1.0f, std::numeric_limits<float>::infinity(), 1e-3f}) {
        VolumeParameters p;
        p.size = glm::vec3(2.0f);
        p.method = VolumeMethod::Splatting;
        p.splatSpacing = spacing; // 1e-3: 8·10⁹ kernels
        try {
            node->setParameters(p);
            ADD_FAILURE() << "accepted splatSpacing " << spacing;
        } catch (const std::invalid_argument& e) {
            EXPECT_NE(std::string(e.what()).find("splatSpacing"), std::string::npos) << e.what();
        }
    }
    EXPECT_EQ(node->parameters().method, VolumeMethod::Raymarch); // kept
}

TEST(Volume, SplatsAreSortedBackToFrontEachFrame) {
    // Red emission in the half of the box nearer y = −1 (density 0.75), green in the other (0.25),
    // through a two-texel ramp; seen from −y and then, in the same viewer, from +y. The over
    // operator in the wrong order would put the far half's colour on top.
    auto ramp = Image::create(2, 1, 3);
    const unsigned char colours[2][3] = {{0, 255, 0}, {255, 0, 0}}; // texel centres at ρ 0.25, 0.75
    for (int x = 0; x < 2; ++x)
        for (int c = 0; c < 3; ++c)
            ramp->pixel(x, 0)[c] = colours[x][c];
    const float ka = 2.0f;
    VolumeParameters p = homogeneous(ka, glm::vec3(1.0f));
    p.method = VolumeMethod::Splatting;
    p.splatSpacing = 0.0625f;
    auto node = VolumeNode::createFunction(p, "return uvw.y < 0.5 ? 0.75 : 0.25;");
    node->setTransferFunction(ramp);
    auto v = floatViewer();
    v->setSceneData(node);
    // Each half is 1 m deep and its source over its extinction is ke/ka: near half first.
    const double tRed = std::exp(-ka * 0.75), tGreen = std::exp(-ka * 0.25);
    const double near = (1.0 - tRed) / ka, far = (1.0 - tGreen) / ka;
    v->frame();
    EXPECT_NEAR(centrePixel(*v).r, near, 0.02);
    EXPECT_NEAR(centrePixel(*v).g, tRed * far, 0.02);
    v->camera()->setLookAt({0, 5, 0}, {0, 0, 0}, {0, 0, 1});
    v->frame();
    EXPECT_NEAR(centrePixel(*v).g, (1.0 - tGreen) / ka, 0.02);
    EXPECT_NEAR(centrePixel(*v).r, tGreen * near, 0.02);
}

// Gaussian splatting (Kerbl et al. 2023): the PLY reader and its refusals, spherical harmonics
// against the real SH definition (associated Legendre functions), one splat's footprint against a
// closed form computed here in double (quaternion rotation of the axes, a numerical Jacobian of the
// projection), a 10^4-splat scene against a CPU renderer of the same equations, fog on splats,
// the depth test against opaque geometry, the sort, and no leaked GL objects. 64×64 float targets.
#include "TestUtil.h"

#include <sgfx/Group.h>
#include <sgfx/LoadError.h>
#include <sgfx/Material.h>
#include <sgfx/Shapes.h>
#include <sgfx/StateSet.h>
#include <sgfx/gl/Objects.h>
#include <sgfx/nodes/fog/FogNode.h>
#include <sgfx/nodes/splat/GaussianSplatNode.h>
#include <sgfx/nodes/splat/SplatMath.h>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <numeric>
#include <random>
#include <unistd.h>

using namespace sgfx;
using namespace sgfx::test;

namespace {

constexpr int kSize = 64;
constexpr double kPi = 3.14159265358979323846;

std::filesystem::path tempFile(const std::string& name) {
    return std::filesystem::temp_directory_path() / ("sgfx_splat_" + std::to_string(::getpid()) + "_" + name);
}

// ---- real spherical harmonics from their definition, independent of the constants table
double factorial(int n) {
    return n <= 1 ? 1.0 : n * factorial(n - 1);
}

// Y_l^m (real, with the Condon–Shortley phase (−1)^m that the reference's basis carries) of the
// unit direction d: √2 K P_l^|m|(cos θ) cos(mφ) or sin(|m|φ), K P_l^0 for m = 0.
double realSh(int l, int m, glm::dvec3 d) {
    const double theta = std::acos(std::clamp(d.z, -1.0, 1.0)), phi = std::atan2(d.y, d.x);
    const int am = std::abs(m);
    const double k = std::sqrt((2 * l + 1) / (4 * kPi) * factorial(l - am) / factorial(l + am));
    const double p = (am % 2 ? -1.0 : 1.0) * std::assoc_legendre(unsigned(l), unsigned(am), std::cos(theta));
    if (m == 0) return k * p;
    return std::sqrt(2.0) * k * p * (m > 0 ? std::cos(am * phi) : std::sin(am * phi));
}

glm::dvec3 referenceColour(int degree, const glm::vec3* sh, glm::dvec3 dir) {
    glm::dvec3 c(0.5);
    int i = 0;
    for (int l = 0; l <= degree; ++l)
        for (int m = -l; m <= l; ++m, ++i)
            c += glm::dvec3(sh[i]) * realSh(l, m, dir);
    return glm::max(c, glm::dvec3(0.0));
}

// ---- a viewer looking along +Y from (0, eyeY, 0), perspective, linear float colour
std::unique_ptr<Viewer> floatViewer(float eyeY = -5.0f, int size = kSize) {
    auto v = Viewer::createHeadless(size, size);
    v->renderer().options().colorTarget = RendererOptions::ColorTarget::Rgba32F;
    auto& cam = *v->camera();
    cam.setLookAt({0, eyeY, 0}, {0, eyeY + 1.0f, 0}, {0, 0, 1});
    cam.projectionMatrix = glm::perspective(glm::radians(40.0f), 1.0f, 0.1f, 100.0f);
    cam.computeNearFar = false;
    cam.clearColor = {0, 0, 0, 1};
    return v;
}

// Window pixel (x, y), y up as gl_FragCoord (readPixelsLinear's rows are top first).
glm::dvec3 pixel(const FloatImage& img, int x, int y) {
    const float* p = &img.rgba[(std::size_t(img.height - 1 - y) * img.width + std::size_t(x)) * 4];
    return {p[0], p[1], p[2]};
}

SplatCloud oneSplat(glm::vec3 pos, glm::vec3 scale, glm::vec4 rot, float opacity, int degree,
                    std::uint32_t seed) {
    SplatCloud c;
    c.shDegree = degree;
    c.positions = {pos};
    c.scales = {scale};
    c.rotations = {glm::normalize(rot)};
    c.opacities = {opacity};
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-0.3f, 0.3f);
    c.sh.push_back(glm::vec3(0.9f, 0.4f, -0.2f));
    for (int k = 1; k < c.coefficients(); ++k)
        c.sh.push_back({u(rng), u(rng), u(rng)});
    return c;
}

// Window pixel of world point p (double): the GL transform chain, written out.
glm::dvec2 toWindow(const glm::dmat4& viewProj, glm::dvec3 p, double size) {
    const glm::dvec4 c = viewProj * glm::dvec4(p, 1.0);
    return (glm::dvec2(c) / c.w * 0.5 + 0.5) * size;
}

// Rotates v by unit quaternion q = (w, x, y, z): q v q*.
glm::dvec3 rotate(glm::dvec4 q, glm::dvec3 v) {
    const glm::dvec3 u(q.y, q.z, q.w);
    const double w = q.x;
    return 2.0 * glm::dot(u, v) * u + (w * w - glm::dot(u, u)) * v + 2.0 * w * glm::cross(u, v);
}

// The splat's expected premultiplied colour at every pixel, or −1 where the 3σ square's edge is
// within 1.5 px (the reference's radius rule and ours may differ by a fraction of a pixel there).
std::vector<glm::dvec4> expectedFootprint(const SplatCloud& c, const Camera& cam, glm::dvec3 eye) {
    const glm::dmat4 vp = glm::dmat4(cam.projectionMatrix) * glm::dmat4(cam.viewMatrix);
    const glm::dvec3 mu(c.positions[0]);
    // Σ = Σ_i s_i² (R e_i)(R e_i)ᵀ.
    glm::dmat3 sigma(0.0);
    for (int i = 0; i < 3; ++i) {
        glm::dvec3 e(0.0);
        e[i] = 1.0;
        const glm::dvec3 a = rotate(glm::dvec4(c.rotations[0]), e);
        sigma += double(c.scales[0][i]) * double(c.scales[0][i]) * glm::outerProduct(a, a);
    }
    // J: central differences of the projection at the centre (the first-order EWA approximation).
    glm::dmat3x2 j(0.0);
    for (int i = 0; i < 3; ++i) {
        glm::dvec3 h(0.0);
        h[i] = 1e-5;
        j[i] = (toWindow(vp, mu + h, kSize) - toWindow(vp, mu - h, kSize)) / 2e-5;
    }
    glm::dmat2 s2 = j * sigma * glm::transpose(j);
    s2[0][0] += 0.3;
    s2[1][1] += 0.3;
    const glm::dmat2 inv = glm::inverse(s2);
    const double mid = 0.5 * (s2[0][0] + s2[1][1]), det = glm::determinant(s2);
    const double radius = 3.0 * std::sqrt(mid + std::sqrt(mid * mid - det));
    const glm::dvec2 centre = toWindow(vp, mu, kSize);
    const glm::dvec3 colour = referenceColour(c.shDegree, c.sh.data(), glm::normalize(mu - eye));
    std::vector<glm::dvec4> out(std::size_t(kSize) * kSize);
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) {
            const glm::dvec2 d = glm::dvec2(x + 0.5, y + 0.5) - centre;
            const double edge = std::max(std::abs(d.x), std::abs(d.y));
            glm::dvec4& e = out[std::size_t(y) * kSize + std::size_t(x)];
            if (std::abs(edge - radius) < 1.5) {
                e = glm::dvec4(-1.0);
                continue;
            }
            double a = c.opacities[0] * std::exp(-0.5 * glm::dot(d, inv * d));
            if (edge > radius || a < 1.0 / 255.0) a = 0.0;
            e = glm::dvec4(colour * a, a);
        }
    return out;
}

void expectRefused(const std::function<void()>& f, const std::vector<std::string>& needles) {
    try {
        f();
        ADD_FAILURE() << "accepted: " << needles.front();
    } catch (const LoadError& e) {
        for (const auto& n : needles)
            EXPECT_NE(std::string(e.what()).find(n), std::string::npos) << e.what() << " lacks " << n;
    }
}

void writeText(const std::filesystem::path& p, const std::string& text) {
    std::ofstream(p, std::ios::binary) << text;
}

} // namespace

TEST(SplatMath, ShColourMatchesTheRealSphericalHarmonics) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (int degree = 0; degree <= 3; ++degree)
        for (int trial = 0; trial < 50; ++trial) {
            std::vector<glm::vec3> sh(std::size_t(splat::coefficientCount(degree)));
            for (auto& c : sh)
                c = {u(rng), u(rng), u(rng)};
            sh[0] += 1.5f; // keep the colour above the clamp at 0 mostly
            const glm::dvec3 dir = glm::normalize(glm::dvec3(u(rng), u(rng), u(rng)));
            const glm::vec3 got = splat::shColour(degree, sh.data(), glm::vec3(dir));
            const glm::dvec3 want = referenceColour(degree, sh.data(), dir);
            for (int ch = 0; ch < 3; ++ch)
                EXPECT_NEAR(got[ch], want[ch], 2e-5) << "degree " << degree << " trial " << trial;
        }
}

TEST(SplatLoader, RoundTripsBinaryAndReadsAscii) {
    const SplatCloud c = SplatCloud::random(50, 3, 1.0f, 0.05f, 3);
    const auto file = tempFile("round.ply");
    splat::savePly(c, file);
    EXPECT_TRUE(splat::isSplatPly(file));
    const SplatCloud r = splat::loadPly(file);
    ASSERT_EQ(r.size(), 50u);
    EXPECT_EQ(r.shDegree, 3);
    for (std::size_t i = 0; i < c.size(); ++i) {
        EXPECT_NEAR(glm::length(r.positions[i] - c.positions[i]), 0.0f, 1e-6f);
        EXPECT_NEAR(glm::length(r.scales[i] - c.scales[i]), 0.0f, 1e-5f * glm::length(c.scales[i]));
        EXPECT_NEAR(r.opacities[i], c.opacities[i], 1e-5f);
        EXPECT_NEAR(std::abs(glm::dot(r.rotations[i], c.rotations[i])), 1.0f, 1e-5f);
        for (int k = 0; k < 16; ++k)
            EXPECT_NEAR(glm::length(r.sh[i * 16 + std::size_t(k)] - c.sh[i * 16 + std::size_t(k)]), 0.0f,
                        1e-6f);
    }
    std::filesystem::remove(file);
    // Ascii, degree 0: opacity 0 is the logit of 0.5, log scales, a quaternion of length 2.
    const auto text = tempFile("ascii.ply");
    writeText(text,
              "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
              "property float z\nproperty float f_dc_0\nproperty float f_dc_1\nproperty float f_dc_2\n"
              "property float opacity\nproperty float scale_0\nproperty float scale_1\n"
              "property float scale_2\nproperty float rot_0\nproperty float rot_1\nproperty float rot_2\n"
              "property float rot_3\nend_header\n1 2 3 0.1 0.2 0.3 0 0 -1 0.5 2 0 0 0\n");
    const SplatCloud a = splat::loadPly(text);
    ASSERT_EQ(a.size(), 1u);
    EXPECT_EQ(a.positions[0], glm::vec3(1, 2, 3));
    EXPECT_NEAR(a.opacities[0], 0.5f, 1e-6f);
    EXPECT_NEAR(a.scales[0].y, std::exp(-1.0f), 1e-6f);
    EXPECT_EQ(a.rotations[0], glm::vec4(1, 0, 0, 0));
    EXPECT_EQ(a.sh[0], glm::vec3(0.1f, 0.2f, 0.3f));
    std::filesystem::remove(text);
}

TEST(SplatLoader, RefusesBadFilesNamingWhatIsWrong) {
    const auto file = tempFile("bad.ply");
    splat::savePly(SplatCloud::random(10, 1, 1.0f, 0.05f, 1), file);
    std::string good;
    {
        std::ifstream in(file, std::ios::binary);
        good.assign(std::istreambuf_iterator<char>(in), {});
    }
    // Truncated: half the body gone (the declared count needs more bytes than follow the header).
    writeText(file, good.substr(0, good.size() - 300));
    expectRefused([&] { splat::loadPly(file); }, {"bad.ply", "element vertex declares 10 splats"});
    // A count larger than the file, refused before allocating.
    std::string s = good;
    s.replace(s.find("element vertex 10"), 17, "element vertex 900000000");
    writeText(file, s);
    expectRefused([&] { splat::loadPly(file); }, {"declares 900000000 splats"});
    // A missing property.
    s = good;
    s.replace(s.find("property float opacity"), 22, "property float opacitx");
    writeText(file, s);
    expectRefused([&] { splat::loadPly(file); }, {"'opacity' is missing"});
    // A property of the wrong type (double is 8 bytes: the count check or the type check refuses).
    s = good;
    s.replace(s.find("property float scale_1"), 22, "property uchar scale_1");
    writeText(file, s);
    expectRefused([&] { splat::loadPly(file); }, {"'scale_1' has type 'uchar'"});
    // An f_rest count that is no SH degree.
    s = good;
    s.replace(s.find("property float f_rest_8\n"), 24, "");
    writeText(file, s);
    expectRefused([&] { splat::loadPly(file); }, {"f_rest_8 is missing", "not 0, 9, 24 or 45"});
    // A NaN.
    s = good;
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const std::size_t body = s.find("end_header\n") + 11;
    const std::size_t stride = (3 + 3 + 3 + 9 + 1 + 3 + 4) * 4;
    std::memcpy(&s[body + 4 * stride + 4], &nan, 4); // splat 4, y
    writeText(file, s);
    expectRefused([&] { splat::loadPly(file); }, {"element vertex 4", "'y' is not finite"});
    // Not a splat file at all, and a mesh PLY.
    writeText(file, "ply\nformat binary_big_endian 1.0\nelement vertex 0\nend_header\n");
    expectRefused([&] { splat::loadPly(file); }, {"binary_big_endian"});
    writeText(file, "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                    "property float z\nend_header\n0 0 0\n");
    EXPECT_FALSE(splat::isSplatPly(file));
    expectRefused([&] { splat::loadPly(file); }, {"'f_dc_0' is missing"});
    std::filesystem::remove(file);
    expectRefused([&] { splat::loadPly(file); }, {"cannot open"});
}

TEST(SplatRender, OneSplatMatchesTheAnalyticFootprint) {
    struct Case {
        glm::vec3 pos, scale;
        glm::vec4 rot;
        float eyeY;
        int degree;
    };
    const Case cases[] = {
        {{0, 0, 0}, {0.3f, 0.1f, 0.05f}, {1, 0, 0, 0}, -5.0f, 0},
        {{0.3f, 0.5f, -0.2f}, {0.25f, 0.06f, 0.12f}, {0.9f, 0.3f, -0.2f, 0.4f}, -5.0f, 1},
        {{-0.2f, 2.0f, 0.3f}, {0.4f, 0.1f, 0.02f}, {0.3f, -0.5f, 0.7f, 0.2f}, -3.0f, 2},
        {{0.1f, 4.0f, -0.1f}, {0.6f, 0.3f, 0.1f}, {0.5f, 0.5f, 0.5f, 0.5f}, -4.0f, 3},
    };
    int n = 0;
    for (const Case& k : cases) {
        const SplatCloud c = oneSplat(k.pos, k.scale, k.rot, 0.8f, k.degree, std::uint32_t(11 + n++));
        auto v = floatViewer(k.eyeY);
        v->setSceneData(GaussianSplatNode::create(c));
        v->frame();
        const FloatImage img = v->renderer().readPixelsLinear();
        const auto want = expectedFootprint(c, *v->camera(), glm::dvec3(0, k.eyeY, 0));
        double maxErr = 0.0, covered = 0.0;
        for (int y = 0; y < kSize; ++y)
            for (int x = 0; x < kSize; ++x) {
                const glm::dvec4& e = want[std::size_t(y) * kSize + std::size_t(x)];
                if (e.a < 0.0) continue;
                covered += e.a > 0.0;
                const glm::dvec3 d = glm::abs(pixel(img, x, y) - glm::dvec3(e));
                maxErr = std::max({maxErr, d.x, d.y, d.z});
            }
        EXPECT_GT(covered, 20.0) << "case " << n;
        EXPECT_LT(maxErr, 1e-4) << "case " << n;
        std::printf("splat footprint case %d: %g pixels covered, max |error| %.2e\n", n, covered, maxErr);
    }
}

TEST(SplatRender, FogOnSplatsFollowsTheFogFormula) {
    const float rho = 0.08f;
    const glm::vec3 fogColor(0.2f, 0.4f, 0.8f);
    FogParameters fp;
    fp.density = rho;
    fp.falloff = 0.0f;
    fp.color = fogColor;
    fp.sky = FogSky::Off;
    auto fog = FogNode::create(fp);
    const SplatCloud c = oneSplat({0, 1, 0}, {0.4f, 0.4f, 0.4f}, {1, 0, 0, 0}, 0.9f, 0, 5);
    fog->addChild(GaussianSplatNode::create(c));
    auto v = floatViewer();
    v->setSceneData(fog);
    v->frame();
    const FloatImage img = v->renderer().readPixelsLinear();
    // Premultiplied (fog's eq. 7 for premultiplied colour): c·α·(1 − k) + fog·α·k, k = 1 − e^(−ρ·6),
    // at the splat's centre (6 m from the eye); α at the pixel from the footprint.
    const auto want = expectedFootprint(c, *v->camera(), glm::dvec3(0, -5, 0));
    const double k = 1.0 - std::exp(-rho * 6.0);
    for (auto [x, y] : {std::pair{32, 32}, std::pair{36, 30}, std::pair{27, 33}}) {
        const glm::dvec4 e = want[std::size_t(y) * kSize + std::size_t(x)];
        ASSERT_GT(e.a, 0.05);
        for (int ch = 0; ch < 3; ++ch)
            EXPECT_NEAR(pixel(img, x, y)[ch], e[ch] * (1 - k) + fogColor[ch] * e.a * k, 3e-3)
                << x << "," << y;
    }
}

TEST(SplatRender, OpaqueGeometryInFrontHidesSplatsBehindItOnly) {
    // An emissive wall at y = 0 covering the left half of the view; splats at y = 2 behind it.
    auto root = Group::create();
    auto q = shapes::quad(4, 8);
    auto m = Material::create();
    m->ambient = glm::vec3(0);
    m->diffuse = glm::vec4(0, 0, 0, 1);
    m->emissive = glm::vec3(0.0f, 1.0f, 0.0f);
    q->getOrCreateStateSet().material.set(m);
    q->getOrCreateStateSet().cullFace.set(CullFace::None);
    auto t = Transform::create(
        glm::rotate(glm::translate(glm::mat4(1.0f), {-2.0f, 0, 0}), glm::radians(90.0f), glm::vec3(1, 0, 0)));
    t->addChild(q);
    root->addChild(t);
    SplatCloud c = oneSplat({-0.8f, 2, 0}, glm::vec3(0.3f), {1, 0, 0, 0}, 1.0f, 0, 1);
    const SplatCloud right = oneSplat({0.8f, 2, 0}, glm::vec3(0.3f), {1, 0, 0, 0}, 1.0f, 0, 1);
    c.positions.push_back(right.positions[0]);
    c.scales.push_back(right.scales[0]);
    c.rotations.push_back(right.rotations[0]);
    c.opacities.push_back(1.0f);
    c.sh.push_back(right.sh[0]);
    root->addChild(GaussianSplatNode::create(c));
    auto v = floatViewer();
    v->setSceneData(root);
    v->frame();
    const FloatImage img = v->renderer().readPixelsLinear();
    const glm::vec4 clip = v->camera()->projectionMatrix * v->camera()->viewMatrix * glm::vec4(0.8f, 2, 0, 1);
    const int px = int((clip.x / clip.w * 0.5f + 0.5f) * kSize);
    EXPECT_NEAR(pixel(img, kSize - 1 - px, 32).g, 1.0, 1e-4); // the wall, unchanged by the splat behind it
    EXPECT_NEAR(pixel(img, kSize - 1 - px, 32).r, 0.0, 1e-4);
    EXPECT_GT(pixel(img, px, 32).r, 0.5); // the right splat, in front of nothing
}

TEST(SplatRender, SceneOfTenThousandSplatsMatchesACpuRenderer) {
    const SplatCloud c = SplatCloud::random(10000, 21, 1.2f, 0.03f, 2);
    auto node = GaussianSplatNode::create(c);
    node->setSort(SplatSort::Cpu);
    auto v = floatViewer(-4.0f);
    v->setSceneData(node);
    v->frame();
    const FloatImage img = v->renderer().readPixelsLinear();
    node->setSort(SplatSort::Gpu);
    v->frame();
    const FloatImage gpuSorted = v->renderer().readPixelsLinear();
    EXPECT_EQ(gpuSorted.rgba, img.rgba); // the same order, so the same image
    const Camera& cam = *v->camera();
    const glm::mat4 mv = cam.viewMatrix;
    // Back to front by view depth, then "over" in double: C = c·α + C·(1 − α).
    std::vector<std::size_t> order(c.size());
    std::iota(order.begin(), order.end(), 0);
    std::vector<splat::Footprint> fp(c.size());
    for (std::size_t i = 0; i < c.size(); ++i)
        fp[i] = splat::project(c.positions[i], splat::covariance(c.scales[i], c.rotations[i]), mv,
                               cam.projectionMatrix, glm::vec2(kSize));
    std::stable_sort(order.begin(), order.end(), [&](auto a, auto b) { return fp[a].depth > fp[b].depth; });
    std::vector<glm::dvec3> ref(std::size_t(kSize) * kSize, glm::dvec3(0.0));
    const glm::vec3 eye(0, -4, 0);
    for (std::size_t i : order) {
        if (!fp[i].visible) continue;
        const glm::dvec3 colour(splat::shColour(2, &c.sh[i * 9], glm::normalize(c.positions[i] - eye)));
        const int x0 = std::max(0, int(fp[i].centre.x - fp[i].radius) - 1),
                  x1 = std::min(kSize - 1, int(fp[i].centre.x + fp[i].radius) + 1);
        const int y0 = std::max(0, int(fp[i].centre.y - fp[i].radius) - 1),
                  y1 = std::min(kSize - 1, int(fp[i].centre.y + fp[i].radius) + 1);
        for (int y = y0; y <= y1; ++y)
            for (int x = x0; x <= x1; ++x) {
                const double a = splat::alphaAt(fp[i], c.opacities[i], glm::vec2(x + 0.5f, y + 0.5f));
                glm::dvec3& p = ref[std::size_t(y) * kSize + std::size_t(x)];
                p = colour * a + p * (1.0 - a);
            }
    }
    double sum = 0.0, maxErr = 0.0;
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) {
            const glm::dvec3 d = glm::abs(pixel(img, x, y) - ref[std::size_t(y) * kSize + std::size_t(x)]);
            sum += d.x + d.y + d.z;
            maxErr = std::max({maxErr, d.x, d.y, d.z});
        }
    const double mean = sum / (3.0 * kSize * kSize);
    std::printf("splat scene: mean |error| %.2e, max %.2e\n", mean, maxErr);
    EXPECT_LT(mean, 1e-4);
    EXPECT_LT(maxErr, 1e-2);
}

TEST(SplatRender, CpuSortIsBackToFront) {
    const SplatCloud c = SplatCloud::random(1000, 4, 1.0f, 0.02f, 0);
    auto node = GaussianSplatNode::create(c);
    node->setSort(SplatSort::Cpu);
    auto v = floatViewer();
    v->setSceneData(node);
    v->frame();
    const std::vector<std::uint32_t> order = node->lastOrder();
    ASSERT_EQ(order.size(), c.size());
    std::vector<std::uint32_t> want(c.size());
    std::iota(want.begin(), want.end(), 0u);
    std::stable_sort(want.begin(), want.end(),
                     [&](auto a, auto b) { return c.positions[a].y > c.positions[b].y; });
    EXPECT_EQ(order, want);
}

TEST(SplatRender, LeavesNoGlObjectsBehind) {
    const long before = gl::liveObjects().total();
    {
        auto v = floatViewer();
        v->setSceneData(GaussianSplatNode::create(SplatCloud::random(100, 2)));
        v->frame();
        v->frame();
    }
    EXPECT_EQ(gl::liveObjects().total(), before);
}

TEST(SplatNode, RefusesABadCloudAndKeepsTheOld) {
    auto node = GaussianSplatNode::create(SplatCloud::random(3, 1));
    SplatCloud bad = SplatCloud::random(3, 1);
    bad.scales[2].x = -1.0f;
    EXPECT_THROW(node->setCloud(bad), std::invalid_argument);
    EXPECT_EQ(node->cloud().size(), 3u);
    bad = SplatCloud::random(3, 1);
    bad.opacities.pop_back();
    try {
        node->setCloud(bad);
        ADD_FAILURE();
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("2 opacities"), std::string::npos) << e.what();
    }
}

TEST(SplatRender, GpuRadixSortEqualsStdSortOnRandomDepths) {
    // 10^5 splats at random depths (a few exact ties, negative depths behind the eye too): the
    // GPU's order must be std::sort's of (depth descending, index ascending).
    SplatCloud c = SplatCloud::random(100000, 9, 1.0f, 0.01f, 0);
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(-10.0f, 40.0f);
    for (std::size_t i = 0; i < c.size(); ++i)
        c.positions[i].y = i % 97 == 0 ? 3.0f : u(rng);
    auto node = GaussianSplatNode::create(c);
    auto v = floatViewer(-5.0f, 16);
    v->setSceneData(node);
    v->frame();
    const std::vector<std::uint32_t> got = node->lastOrder();
    ASSERT_EQ(got.size(), c.size());
    std::vector<std::uint32_t> want(c.size());
    std::iota(want.begin(), want.end(), 0u);
    // View depth along +Y from y = −5 is y + 5 (computed as the shader does, in float).
    const glm::mat4 mv = v->camera()->viewMatrix;
    auto depth = [&](std::uint32_t i) { return -(mv * glm::vec4(c.positions[i], 1.0f)).z; };
    std::sort(want.begin(), want.end(), [&](auto a, auto b) {
        const float da = depth(a), db = depth(b);
        return da != db ? da > db : a < b;
    });
    EXPECT_EQ(got, want);
}

TEST(SplatRender, GlassIsOrderedWithTheCloudByItsCentre) {
    // A red pane, straight alpha 0.5, in front of (y = 0) or behind (y = 4) a splat at y = 2: the
    // transparent stage sorts the pane and the cloud (one item, its bound's centre) back to front.
    const SplatCloud c = oneSplat({0, 2, 0}, glm::vec3(0.4f), {1, 0, 0, 0}, 0.9f, 0, 3);
    for (float paneY : {0.0f, 4.0f}) {
        auto root = Group::create();
        auto q = shapes::quad(6, 6);
        auto m = Material::create();
        m->ambient = glm::vec3(0);
        m->diffuse = glm::vec4(0, 0, 0, 0.5f);
        m->emissive = glm::vec3(1, 0, 0);
        q->getOrCreateStateSet().material.set(m);
        q->getOrCreateStateSet().blend.set(BlendMode::Alpha);
        q->getOrCreateStateSet().cullFace.set(CullFace::None);
        auto t = Transform::create(glm::rotate(glm::translate(glm::mat4(1.0f), {0, paneY, 0}),
                                               glm::radians(90.0f), glm::vec3(1, 0, 0)));
        t->addChild(q);
        root->addChild(t);
        root->addChild(GaussianSplatNode::create(c));
        auto v = floatViewer();
        v->setSceneData(root);
        v->frame();
        const FloatImage img = v->renderer().readPixelsLinear();
        const glm::dvec4 s = expectedFootprint(c, *v->camera(), glm::dvec3(0, -5, 0))[32 * kSize + 32];
        const glm::dvec3 red(1, 0, 0);
        const glm::dvec3 want = paneY < 2.0f ? red * 0.5 + glm::dvec3(s) * 0.5          // pane over splat
                                             : glm::dvec3(s) + red * 0.5 * (1.0 - s.a); // splat over pane
        for (int ch = 0; ch < 3; ++ch)
            EXPECT_NEAR(pixel(img, 32, 32)[ch], want[ch], 2e-3) << "pane at y = " << paneY;
    }
}

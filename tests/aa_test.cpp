// Anti-aliasing per camera (OSMesa, 64×64): a black half-plane on white, whose straight edge
// covers each pixel by an area computed here exactly; every mode's edge pixels are compared with
// that coverage, in linear colour (the resolves average in linear space).
#include "TestUtil.h"

#include <sgfx/Geometry.h>
#include <sgfx/Group.h>
#include <sgfx/Shapes.h>
#include <sgfx/nodes/ao/AmbientOcclusionNode.h>
#include <sgfx/nodes/fog/FogNode.h>
#include <sgfx/nodes/transparency/TransparencyBin.h>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>
#include <sgfx_glad/gl.h>

#include <array>
#include <cstdio>

using namespace sgfx;
using namespace sgfx::test;

namespace {

constexpr int kSize = 64;
constexpr float kHalf = 2.0f;
const float kAngle = glm::radians(23.0f); // the edge's tilt from the vertical
// The tilt the helpers below draw and measure: kAngle, except where a test turns it (EdgeTilt).
float edgeAngle = kAngle;

double srgbDecode(int byte) {
    const double c = byte / 255.0;
    return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

// The black region: points with dot(n, p) < 0.13 (an edge through the view near its centre).
glm::dvec2 edgeNormal() {
    return {std::cos(double(edgeAngle)), std::sin(double(edgeAngle))};
}
constexpr double kOffset = 0.13;

// Exact area fraction of pixel (x, y) (top row first) inside the black half-plane (the one
// through `offset` instead of kOffset when given).
double coverage(int x, int y, double offset = kOffset) {
    const double s = 2.0 * kHalf / kSize;
    const double x0 = -kHalf + x * s, y1 = kHalf - y * s;
    std::vector<glm::dvec2> poly = {{x0, y1 - s}, {x0 + s, y1 - s}, {x0 + s, y1}, {x0, y1}};
    const glm::dvec2 n = edgeNormal();
    auto inside = [&](glm::dvec2 p) { return glm::dot(n, p) - offset; }; // < 0: black
    std::vector<glm::dvec2> out;
    for (std::size_t i = 0; i < poly.size(); ++i) {
        const glm::dvec2 a = poly[i], b = poly[(i + 1) % poly.size()];
        const double da = inside(a), db = inside(b);
        if (da <= 0) out.push_back(a);
        if ((da < 0) != (db < 0) && da != db) out.push_back(a + (b - a) * (da / (da - db)));
    }
    double area = 0;
    for (std::size_t i = 0; i < out.size(); ++i) {
        const glm::dvec2 a = out[i], b = out[(i + 1) % out.size()];
        area += a.x * b.y - b.x * a.y;
    }
    return std::abs(area) / 2.0 / (s * s);
}

// Fraction of the given sample positions of pixel (x, y) inside the black half-plane; positions
// in [0, 1]² from the pixel's lower left corner (GL window convention).
double sampleCoverage(int x, int y, const std::vector<glm::dvec2>& positions) {
    const double s = 2.0 * kHalf / kSize;
    const int yGl = kSize - 1 - y;
    int inside = 0;
    for (const glm::dvec2& q : positions) {
        const glm::dvec2 p(-kHalf + (x + q.x) * s, -kHalf + (yGl + q.y) * s);
        inside += glm::dot(edgeNormal(), p) < kOffset;
    }
    return double(inside) / double(positions.size());
}

double linearValue(const Image& img, int x, int y) {
    return srgbDecode(pixelAt(img, x, y).r);
}

std::shared_ptr<Node> halfPlane() {
    auto q = shapes::quad(40, 40);
    auto m = Material::create();
    m->ambient = glm::vec3(0);
    m->diffuse = glm::vec4(0, 0, 0, 1);
    m->emissive = glm::vec3(0);
    q->getOrCreateStateSet().material.set(m);
    // Its right edge (x = 20 in the quad's frame) onto the line dot(n, p) = kOffset.
    const glm::dvec2 n = edgeNormal();
    auto t =
        Transform::create(glm::translate(glm::mat4(1.0f), glm::vec3(glm::vec2(n * (kOffset - 20.0)), 0)) *
                          glm::rotate(glm::mat4(1.0f), edgeAngle, glm::vec3(0, 0, 1)));
    t->addChild(q);
    return t;
}

std::unique_ptr<Viewer> edgeViewer(const AntiAliasing& aa) {
    auto v = orthoTopViewer(kSize, kHalf);
    v->camera()->clearColor = {1, 1, 1, 1};
    v->camera()->setAntiAliasing(aa);
    v->setSceneData(halfPlane());
    return v;
}

Image renderFrames(Viewer& v, int frames = 1) {
    for (int i = 0; i < frames; ++i)
        v.frame();
    for (const auto& e : v.renderer().takeGlErrors())
        ADD_FAILURE() << "GL: " << e;
    return v.capture();
}

struct EdgeError {
    double worst = 0, mean = 0;
    double worstVsSamples = 0; // against the coverage of the given sample points
    int edgePixels = 0;
};

// |linear value − (1 − coverage)| over the pixels the edge crosses (away from the border).
EdgeError edgeError(const Image& img, const std::vector<glm::dvec2>& samples = {}) {
    EdgeError e;
    for (int y = 2; y < kSize - 2; ++y)
        for (int x = 2; x < kSize - 2; ++x) {
            const double c = coverage(x, y);
            if (c <= 0.0 || c >= 1.0) continue;
            ++e.edgePixels;
            const double err = std::abs(linearValue(img, x, y) - (1.0 - c));
            e.worst = std::max(e.worst, err);
            e.mean += err;
            if (!samples.empty())
                e.worstVsSamples =
                    std::max(e.worstVsSamples,
                             std::abs(linearValue(img, x, y) - (1.0 - sampleCoverage(x, y, samples))));
        }
    e.mean /= std::max(e.edgePixels, 1);
    return e;
}

// The driver's MSAA sample positions for `n` samples.
std::vector<glm::dvec2> msaaPositions(int n) {
    GLuint tex = 0, fbo = 0;
    glCreateTextures(GL_TEXTURE_2D_MULTISAMPLE, 1, &tex);
    glTextureStorage2DMultisample(tex, n, GL_RGBA8, 1, 1, GL_TRUE);
    glCreateFramebuffers(1, &fbo);
    glNamedFramebufferTexture(fbo, GL_COLOR_ATTACHMENT0, tex, 0);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    std::vector<glm::dvec2> p;
    for (int i = 0; i < n; ++i) {
        float xy[2] = {0, 0};
        glGetMultisamplefv(GL_SAMPLE_POSITION, GLuint(i), xy);
        p.emplace_back(xy[0], xy[1]);
    }
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glDeleteFramebuffers(1, &fbo);
    glDeleteTextures(1, &tex);
    return p;
}

// Grid positions of SSAA factor f.
std::vector<glm::dvec2> gridPositions(int f) {
    std::vector<glm::dvec2> p;
    for (int j = 0; j < f; ++j)
        for (int i = 0; i < f; ++i)
            p.emplace_back((i + 0.5) / f, (j + 0.5) / f);
    return p;
}

// Sets edgeAngle for one scope.
struct EdgeTilt {
    explicit EdgeTilt(float degrees) { edgeAngle = glm::radians(degrees); }
    ~EdgeTilt() { edgeAngle = kAngle; }
    EdgeTilt(const EdgeTilt&) = delete;
    EdgeTilt& operator=(const EdgeTilt&) = delete;
};

// TAA's first 16 jitter positions, Halton(2, 3).
std::vector<glm::dvec2> haltonPositions() {
    auto halton = [](int i, int b) {
        double f = 1, r = 0;
        for (; i > 0; i /= b) {
            f /= b;
            r += f * (i % b);
        }
        return r;
    };
    std::vector<glm::dvec2> p;
    for (int i = 1; i <= 16; ++i)
        p.emplace_back(halton(i, 2), halton(i, 3));
    return p;
}

} // namespace

TEST(AntiAliasing, WithoutItEveryEdgePixelIsBlackOrWhite) {
    auto v = edgeViewer(AntiAliasing::none());
    const Image img = renderFrames(*v);
    int edge = 0;
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) {
            const int r = pixelAt(img, x, y).r;
            EXPECT_TRUE(r == 0 || r == 255) << x << "," << y << ": " << r;
            const double c = coverage(x, y);
            edge += c > 0 && c < 1;
        }
    EXPECT_GT(edge, kSize - 4);
}

TEST(AntiAliasing, MsaaAndSsaaMatchTheAnalyticCoverage) {
    // Each mode resolves the exact fraction of its sample points that the polygon covers (1/255
    // rounding); against the area coverage the error of a few point samples remains. SSAA 4x
    // holds every pixel within 1/8 and SSAA 2x within 1/4; MSAA 4x's four rotated-grid samples
    // cannot hold 1/8 on every pixel at every angle (a pixel 0.28 covered may hold no sample),
    // so its bound is on the mean, and its worst pixel is reported.
    struct Case {
        AntiAliasing aa;
        std::vector<glm::dvec2> samples;
        double worstBound, meanBound;
        const char* name;
    };
    auto probe = orthoTopViewer(4, 1.0f); // a context for the sample-position query
    const std::vector<Case> cases = {{AntiAliasing::msaa(4), msaaPositions(4), 0.3, 1.0 / 8, "MSAA 4x"},
                                     {AntiAliasing::ssaa(4), gridPositions(4), 1.0 / 8, 1.0 / 16, "SSAA 4x"},
                                     {AntiAliasing::ssaa(2), gridPositions(2), 1.0 / 4, 1.0 / 8, "SSAA 2x"}};
    for (const Case& c : cases) {
        auto v = edgeViewer(c.aa);
        const EdgeError e = edgeError(renderFrames(*v), c.samples);
        std::printf("%s: %d edge pixels, |value - area coverage| worst %.3f mean %.3f; "
                    "|value - sample coverage| worst %.4f\n",
                    c.name, e.edgePixels, e.worst, e.mean, e.worstVsSamples);
        EXPECT_GT(e.edgePixels, kSize - 8);
        EXPECT_LE(e.worstVsSamples, 1.5 / 255) << c.name;
        EXPECT_LE(e.worst, c.worstBound) << c.name;
        EXPECT_LE(e.mean, c.meanBound) << c.name;
    }
}

TEST(AntiAliasing, FxaaSmoothsTheStaircaseWithoutMovingTheEdge) {
    // Along lines parallel to the edge the staircase alternates black and white; an ideal AA
    // image is constant there. Sum |Δ| of bilinear samples every half pixel along such lines
    // crossing the edge zone, and estimate the edge position per row from the black it holds.
    auto measure = [](const Image& img, double& variation, double& worstShift) {
        auto at = [&](double fx, double fy) { // bilinear in linear colour, pixel-centre coordinates
            const int x0 = int(std::floor(fx)), y0 = int(std::floor(fy));
            const double tx = fx - x0, ty = fy - y0;
            auto v = [&](int x, int y) {
                return linearValue(img, std::clamp(x, 0, kSize - 1), std::clamp(y, 0, kSize - 1));
            };
            return (v(x0, y0) * (1 - tx) + v(x0 + 1, y0) * tx) * (1 - ty) +
                   (v(x0, y0 + 1) * (1 - tx) + v(x0 + 1, y0 + 1) * tx) * ty;
        };
        const double s = 2.0 * kHalf / kSize;
        const glm::dvec2 n = edgeNormal(), onEdge = n * kOffset;
        const glm::dvec2 centre((onEdge.x + kHalf) / s - 0.5, (kHalf - onEdge.y) / s - 0.5);
        const glm::dvec2 along(-n.y, -n.x), across(n.x, -n.y); // pixel coordinates (y down)
        variation = 0;
        for (double d = -1.5; d <= 1.5; d += 0.25) {
            double last = at(centre.x + across.x * d - along.x * 24, centre.y + across.y * d - along.y * 24);
            for (double t = -23.5; t <= 24.0; t += 0.5) {
                const double v =
                    at(centre.x + across.x * d + along.x * t, centre.y + across.y * d + along.y * t);
                variation += std::abs(v - last);
                last = v;
            }
        }
        worstShift = 0;
        for (int y = 4; y < kSize - 4; ++y) {
            double black = 0, expected = 0;
            for (int x = 2; x < kSize - 2; ++x) {
                black += 1.0 - linearValue(img, x, y);
                expected += coverage(x, y);
            }
            worstShift = std::max(worstShift, std::abs(black - expected)); // edge position, pixels
        }
    };
    double tvNone, shiftNone, tvFxaa, shiftFxaa;
    auto none = edgeViewer(AntiAliasing::none());
    measure(renderFrames(*none), tvNone, shiftNone);
    for (auto q : {AntiAliasing::FxaaQuality::Low, AntiAliasing::FxaaQuality::Medium,
                   AntiAliasing::FxaaQuality::High}) {
        auto v = edgeViewer(AntiAliasing::fxaa(q));
        measure(renderFrames(*v), tvFxaa, shiftFxaa);
        std::printf(
            "FXAA quality %d: variation along the edge %.2f (no AA %.2f), edge shift %.2f px (no AA %.2f)\n",
            int(q), tvFxaa, tvNone, shiftFxaa, shiftNone);
        EXPECT_LT(tvFxaa, 0.8 * tvNone);
        EXPECT_LE(shiftFxaa, 0.5);
    }
}

TEST(AntiAliasing, FxaaPresetsRankLowMediumHighInEdgeError) {
    // The presets differ in how far FXAA walks along an edge (5, 8 and 12 steps: about 5, 10 and
    // 26 pixels) and in their thresholds. An edge 2.5° off the vertical has steps 23 px long,
    // which only the longer walks reach the ends of: the mean error against the exact area
    // coverage must fall from Low to Medium to High, each below no AA.
    const EdgeTilt tilt(2.5f);
    auto none = edgeViewer(AntiAliasing::none());
    const double noAa = edgeError(renderFrames(*none)).mean;
    double previous = noAa;
    for (auto q : {AntiAliasing::FxaaQuality::Low, AntiAliasing::FxaaQuality::Medium,
                   AntiAliasing::FxaaQuality::High}) {
        auto v = edgeViewer(AntiAliasing::fxaa(q));
        const EdgeError e = edgeError(renderFrames(*v));
        std::printf("FXAA quality %d on a 2.5 deg edge: mean error %.4f worst %.3f (no AA %.4f)\n", int(q),
                    e.mean, e.worst, noAa);
        EXPECT_LT(e.mean, 0.9 * previous) << "quality " << int(q) << " is not better than the one below it";
        previous = e.mean;
    }
}

TEST(AntiAliasing, TaaUnderSlowCameraMotionConvergesToSupersampling) {
    // A static edge, the camera sliding across it by 0.05 px a frame (1.55 px in 32 frames): the
    // reprojected history must follow, so the image stays close to what SSAA 4x draws at the
    // final camera. Measured on llvmpipe: mean error 0.056 on a still camera (16 Halton samples
    // against a 4×4 grid), 0.105 sliding (the history is resampled off its texel centres every
    // frame and clamped to the 3×3 neighbourhood), 0.27 when the history is not reprojected
    // (it lags 0.4 px behind). Bounds: mean 0.15 over the pixels the edge crosses; no ghost of
    // the old edge 1 px and more away (off by at most 0.1).
    const double s = 2.0 * kHalf / kSize;
    const glm::dvec2 n = edgeNormal();
    auto place = [&](Viewer& v, int frame) {
        const glm::vec3 shift(glm::vec2(n * (0.05 * s * frame)), 0.0f);
        v.camera()->setLookAt(shift + glm::vec3(0, 0, 10), shift, {0, 1, 0});
    };
    constexpr int kFrames = 32;
    auto taa = edgeViewer(AntiAliasing::taa());
    for (int i = 0; i < kFrames; ++i) {
        place(*taa, i);
        renderFrames(*taa, 1);
    }
    const Image moving = taa->capture();
    auto ssaa = edgeViewer(AntiAliasing::ssaa(4));
    place(*ssaa, kFrames - 1);
    const Image reference = renderFrames(*ssaa, 1);
    // Coverage at the final camera: the edge moved by −1.55 px along n on screen.
    double mean = 0, ghost = 0;
    int edgePixels = 0;
    for (int y = 2; y < kSize - 2; ++y)
        for (int x = 2; x < kSize - 2; ++x) {
            const double err = std::abs(linearValue(moving, x, y) - linearValue(reference, x, y));
            const glm::dvec2 centre(-kHalf + (x + 0.5) * s, kHalf - (y + 0.5) * s);
            const double distancePx =
                std::abs(glm::dot(n, centre) - (kOffset - 0.05 * s * (kFrames - 1))) / s;
            if (distancePx < 1.0) {
                mean += err;
                ++edgePixels;
            } else {
                ghost = std::max(ghost, err);
            }
        }
    mean /= std::max(edgePixels, 1);
    std::printf("TAA, camera sliding 0.05 px/frame: mean error to SSAA 4x %.4f over %d edge pixels, worst "
                "off the edge %.4f\n",
                mean, edgePixels, ghost);
    EXPECT_GT(edgePixels, kSize);
    EXPECT_LE(mean, 0.15);
    EXPECT_LE(ghost, 0.1);
}

TEST(AntiAliasing, TaaConvergesOnAStaticScene) {
    // After 16 frames each pixel holds the mean of its 16 Halton(2,3) jittered samples: their
    // point coverage, up to one sample lying on the edge within float precision; against the
    // area coverage, within 1/16 on average (16 points cannot hold 1/16 on every pixel).
    auto v = edgeViewer(AntiAliasing::taa());
    const Image taaImage = renderFrames(*v, 16);
    const EdgeError e = edgeError(taaImage, haltonPositions());
    std::printf(
        "TAA after 16 frames: |value - area coverage| worst %.3f mean %.3f; |value - sample coverage| "
        "worst %.4f\n",
        e.worst, e.mean, e.worstVsSamples);
    EXPECT_LE(e.worstVsSamples, 1.0 / 16 + 2.5 / 255);
    EXPECT_LE(e.mean, 1.0 / 16);
    EXPECT_LE(e.worst, 0.15);
    // A camera cut starts again: one frame is one jittered sample, no better than no AA.
    v->camera()->resetHistory();
    const EdgeError cut = edgeError(renderFrames(*v, 1));
    EXPECT_GT(cut.worst, 0.3);
}

namespace {

// The camera moved 5 m along the edge (over the 2 m a frame TAA follows; the edge stays where it
// was on screen).
void jumpAlongTheEdge(Viewer& v) {
    const glm::vec3 along(-std::sin(kAngle) * 5.0f, std::cos(kAngle) * 5.0f, 0.0f);
    v.camera()->setLookAt(along + glm::vec3(0, 0, 10), along, {0, 1, 0});
}

// A TAA view's 17th frame: 16 frames from one place, then the jump.
Image jumpedSeventeenthFrame() {
    auto v = edgeViewer(AntiAliasing::taa());
    renderFrames(*v, 16);
    jumpAlongTheEdge(*v);
    return renderFrames(*v, 1);
}

} // namespace

TEST(AntiAliasing, TaaDropsItsHistoryWhenTheCameraJumps) {
    // After the jump the image is a single jittered sample per pixel, the same as a reset
    // history gives.
    const auto moved = jumpAlongTheEdge;
    const Image jumped = jumpedSeventeenthFrame();
    auto fresh = edgeViewer(AntiAliasing::taa());
    moved(*fresh);
    renderFrames(*fresh, 16); // the jitter sequence continues: frame 17 uses the same offset below
    moved(*fresh);
    fresh->camera()->resetHistory();
    const Image reference = renderFrames(*fresh, 1);
    EXPECT_EQ(channelsDiffering(jumped, reference, 0), 0);
    EXPECT_GT(edgeError(jumped).worst, 0.3) << "one jittered sample, no history";
}

TEST(AntiAliasing, TaaJitterFollowsTheFrameNumber) {
    // Display channels and cluster ranks must jitter alike: a view that has drawn 16 frames and
    // then cuts equals a brand-new view drawn once as frame 17, and not one drawn as frame 18.
    const Image jumped = jumpedSeventeenthFrame();
    auto firstDrawnAs = [&](std::uint64_t frameNumber) {
        auto fresh = edgeViewer(AntiAliasing::taa());
        jumpAlongTheEdge(*fresh);
        fresh->renderer().render(*fresh->camera(), 0.0, frameNumber);
        return fresh->capture();
    };
    EXPECT_EQ(channelsDiffering(jumped, firstDrawnAs(17), 0), 0);
    EXPECT_GT(channelsDiffering(jumped, firstDrawnAs(18), 0), 0) << "the jitter must depend on the frame";
}

TEST(AntiAliasing, SixteenSamplesOnLlvmpipeGiveTheDriversMaximumAndAWarning) {
    auto v = edgeViewer(AntiAliasing::msaa(16));
    const EdgeError e = edgeError(renderFrames(*v));
    GLint maxSamples = 0;
    glGetIntegerv(GL_MAX_SAMPLES, &maxSamples);
    const auto warnings = v->renderer().takeWarnings();
    if (maxSamples < 16) {
        ASSERT_EQ(warnings.size(), 1u);
        EXPECT_NE(warnings[0].find("16 samples asked"), std::string::npos) << warnings[0];
        EXPECT_NE(warnings[0].find("using " + std::to_string(maxSamples)), std::string::npos) << warnings[0];
    }
    EXPECT_LE(e.mean, 1.0 / 8) << "an anti-aliased image, not an error or a black one";
    v->frame();
    EXPECT_TRUE(v->renderer().takeWarnings().empty()) << "said once";
}

// Interior pixels (no edge within a pixel) of a scene under post-process fog and AO: how many,
// and how many change by more than 2/255 when `aa` is on.
std::pair<int, int> interiorChangedBy(const AntiAliasing& aa) {
    auto scene = [] {
        auto world = Group::create();
        world->addChild(Light::create(LightType::Ambient));
        auto plane = shapes::quad(200, 200);
        auto m = Material::create();
        m->ambient = glm::vec3(0.8f);
        m->diffuse = glm::vec4(0, 0, 0, 1);
        plane->getOrCreateStateSet().material.set(m);
        world->addChild(plane);
        auto box = shapes::box({1, 1, 1});
        box->getOrCreateStateSet().material.set(m);
        auto t = Transform::create(glm::translate(glm::mat4(1.0f), {0, 0, 0.5f}));
        t->addChild(box);
        world->addChild(t);
        auto ao = AmbientOcclusionNode::create();
        ao->addChild(world);
        FogParameters fp;
        fp.density = 0.03f;
        fp.falloff = 0.0f;
        auto fog = FogNode::create(fp, FogMode::PostProcess);
        fog->addChild(ao);
        return fog;
    };
    Image img[2];
    for (int ms = 0; ms < 2; ++ms) {
        auto v = Viewer::createHeadless(96, 96);
        v->camera()->setPerspective(60, 0.5f, 500);
        v->camera()->setLookAt({2.5f, -4, 3}, {0, 0, 0.4f});
        v->camera()->clearColor = {0.3f, 0.4f, 0.6f, 1};
        v->camera()->setAntiAliasing(ms ? aa : AntiAliasing::none());
        v->setSceneData(scene());
        img[ms] = renderFrames(*v);
    }
    int interior = 0, differing = 0;
    for (int y = 1; y < 95; ++y)
        for (int x = 1; x < 95; ++x) {
            // Interior: the no-AA image is flat within 3/255 around the pixel.
            bool flat = true;
            for (int dy = -1; dy <= 1 && flat; ++dy)
                for (int dx = -1; dx <= 1 && flat; ++dx)
                    for (int c = 0; c < 3; ++c)
                        flat = flat &&
                               std::abs(pixelAt(img[0], x + dx, y + dy)[c] - pixelAt(img[0], x, y)[c]) <= 3;
            if (!flat) continue;
            ++interior;
            for (int c = 0; c < 3; ++c)
                if (std::abs(pixelAt(img[1], x, y)[c] - pixelAt(img[0], x, y)[c]) > 2) {
                    ++differing;
                    break;
                }
        }
    std::printf("fog post + AO with %s: %d interior pixels, %d differ by more than 2/255\n",
                aa.name().c_str(), interior, differing);
    return {interior, differing};
}

TEST(AntiAliasing, FogPostProcessAndAoGiveTheSameInteriorWithMsaa) {
    const auto [interior, differing] = interiorChangedBy(AntiAliasing::msaa(4));
    EXPECT_GT(interior, 96 * 96 / 2);
    EXPECT_EQ(differing, 0);
}

// A weighted blended pane over the half-plane, drawn without AA and with `aa`.
std::array<Image, 2> paneOverHalfPlane(const AntiAliasing& aa) {
    std::array<Image, 2> img;
    for (int ms = 0; ms < 2; ++ms) {
        auto root = Group::create();
        root->addChild(halfPlane());
        auto bin = TransparencyBin::create(TransparencyMode::WeightedBlended);
        auto pane = shapes::quad(2, 2);
        auto m = Material::create();
        m->ambient = glm::vec3(0);
        m->diffuse = glm::vec4(0, 0, 0, 0.5f);
        m->emissive = glm::vec3(0.2f, 0.5f, 0.9f);
        pane->getOrCreateStateSet().material.set(m);
        auto t = Transform::create(glm::translate(glm::mat4(1.0f), {0.8f, 0.5f, 1}));
        t->addChild(pane);
        bin->addChild(t);
        root->addChild(bin);
        auto v = orthoTopViewer(kSize, kHalf);
        v->camera()->clearColor = {1, 1, 1, 1};
        v->camera()->setAntiAliasing(ms ? aa : AntiAliasing::none());
        v->setSceneData(root);
        img[ms] = renderFrames(*v);
    }
    return img;
}

TEST(AntiAliasing, OitAndSkyFogWorkOnAMultisampledView) {
    // The pane accumulated per sample, with MSAA: its interior equals the same pane without AA.
    const auto img = paneOverHalfPlane(AntiAliasing::msaa(4));
    const int x = kSize / 2 + 14, y = kSize / 2 - 8; // inside the pane, white below
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(pixelAt(img[1], x, y)[c], pixelAt(img[0], x, y)[c], 1);
    EXPECT_NE(pixelAt(img[1], x, y).r, 255) << "the pane is there";
}

TEST(AntiAliasing, ResizingReallocatesEveryModesTargets) {
    for (const AntiAliasing& aa : {AntiAliasing::msaa(4), AntiAliasing::ssaa(3), AntiAliasing::fxaa(),
                                   AntiAliasing::taa(), AntiAliasing::smaa(), AntiAliasing::smaaT2x()}) {
        auto v = edgeViewer(aa);
        for (auto [w, h] : {std::pair{17, 9}, std::pair{1, 1}, std::pair{40, 70}, std::pair{kSize, kSize}}) {
            v->camera()->setViewport(0, 0, w, h);
            ASSERT_NO_THROW(v->frame()) << w << "x" << h;
        }
        v->camera()->projectionMatrix = glm::ortho(-kHalf, kHalf, -kHalf, kHalf, 0.1f, 100.0f);
        const Image img = renderFrames(*v, aa.mode == AntiAliasing::Mode::Taa ? 16 : 1);
        ASSERT_EQ(img.width, kSize);
        EXPECT_LE(edgeError(img).worst, 0.3) << int(aa.mode);
    }
}

TEST(AntiAliasing, BadSettingsAreRefused) {
    auto cam = Camera::create();
    auto bad = [&](AntiAliasing a, const char* field) {
        try {
            cam->setAntiAliasing(a);
            ADD_FAILURE() << field << " accepted";
        } catch (const std::invalid_argument& e) {
            EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
        }
    };
    bad(AntiAliasing::msaa(0), "samples");
    bad(AntiAliasing::msaa(1000), "samples");
    bad(AntiAliasing::ssaa(5), "factor");
    bad(AntiAliasing::ssaa(0), "factor");
    bad(AntiAliasing::taa(1.0f), "taaFeedback");
    bad(AntiAliasing::taa(std::numeric_limits<float>::quiet_NaN()), "taaFeedback");
    AntiAliasing m;
    m.mode = AntiAliasing::Mode(9);
    bad(m, "mode");
    EXPECT_EQ(cam->antiAliasing().mode, AntiAliasing::Mode::None);
}

TEST(AntiAliasing, SupersamplingBeyondTheTextureLimitSaysSo) {
    GLint maxSize = 0;
    auto v = edgeViewer(AntiAliasing::ssaa(4));
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &maxSize);
    v->camera()->setViewport(0, 0, maxSize / 2, 4);
    try {
        v->frame();
        ADD_FAILURE() << "no error";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("SSAA 4x"), std::string::npos) << e.what();
    }
    v->camera()->setViewport(0, 0, kSize, kSize);
    EXPECT_NO_THROW(v->frame());
}

// A black strip one pixel wide through the view's centre, tilted like the edge.
std::unique_ptr<Viewer> lineViewer(const AntiAliasing& aa) {
    auto q = shapes::quad(2.0f * kHalf / kSize, 40);
    auto m = Material::create();
    m->ambient = glm::vec3(0);
    m->diffuse = glm::vec4(0, 0, 0, 1);
    m->emissive = glm::vec3(0);
    q->getOrCreateStateSet().material.set(m);
    auto t = Transform::create(glm::rotate(glm::mat4(1.0f), edgeAngle, glm::vec3(0, 0, 1)));
    t->addChild(q);
    auto v = orthoTopViewer(kSize, kHalf);
    v->camera()->clearColor = {1, 1, 1, 1};
    v->camera()->setAntiAliasing(aa);
    v->setSceneData(t);
    return v;
}

struct LineError {
    double rowMean = 0;   // mean over rows of |black in the row − the strip's exact area in it|, pixels
    double pixelMean = 0; // mean |value − (1 − coverage)| over the pixels the strip touches
};

LineError lineError(const Image& img) {
    const double half = kHalf / kSize; // half the strip's width
    LineError e;
    int rows = 0, pixels = 0;
    for (int y = 4; y < kSize - 4; ++y, ++rows) {
        double black = 0, exact = 0;
        for (int x = 2; x < kSize - 2; ++x) {
            const double c = coverage(x, y, half) - coverage(x, y, -half);
            black += 1.0 - linearValue(img, x, y);
            exact += c;
            if (c > 0.0) {
                e.pixelMean += std::abs(linearValue(img, x, y) - (1.0 - c));
                ++pixels;
            }
        }
        e.rowMean += std::abs(black - exact);
    }
    e.rowMean /= rows;
    e.pixelMean /= std::max(pixels, 1);
    return e;
}

TEST(Smaa, EdgeErrorIsBelowFxaasAndPresetsReachLongerSteps) {
    // Against the exact area coverage of the half-plane's edge. Measured on llvmpipe (64², high
    // preset): 23°: mean 0.052 worst 0.167 (FXAA 0.069 / 0.249); 60°: 0.071 / 0.247 (FXAA 0.079 /
    // 0.309); 2.5° (steps 23 px long): high 0.055 (FXAA 0.095), low 0.121 (4 search steps, 8 px,
    // cannot reach the ends).
    for (float tilt : {23.0f, 60.0f}) {
        const EdgeTilt t(tilt);
        auto f = edgeViewer(AntiAliasing::fxaa());
        const EdgeError fxaa = edgeError(renderFrames(*f));
        auto v = edgeViewer(AntiAliasing::smaa());
        const EdgeError e = edgeError(renderFrames(*v));
        std::printf("%.0f deg edge: SMAA mean %.4f worst %.3f, FXAA mean %.4f worst %.3f\n", tilt, e.mean,
                    e.worst, fxaa.mean, fxaa.worst);
        EXPECT_LT(e.mean, (tilt < 45.0f ? 0.9 : 1.0) * fxaa.mean) << tilt; // 60°: 0.071 against 0.079
        EXPECT_LT(e.worst, 0.9 * fxaa.worst) << tilt;
    }
    const EdgeTilt t(2.5f);
    auto f = edgeViewer(AntiAliasing::fxaa());
    const double fxaa = edgeError(renderFrames(*f)).mean;
    double mean[4];
    for (int p = 0; p < 4; ++p) {
        auto v = edgeViewer(AntiAliasing::smaa(AntiAliasing::SmaaPreset(p)));
        mean[p] = edgeError(renderFrames(*v)).mean;
        std::printf("2.5 deg edge, SMAA preset %d: mean %.4f (FXAA %.4f)\n", p, mean[p], fxaa);
    }
    EXPECT_LT(mean[2], 0.75 * fxaa);
    EXPECT_LT(mean[3], 0.75 * fxaa);
    EXPECT_LT(mean[2], 0.75 * mean[0]) << "16 search steps reach the 23 px steps' ends, 4 do not";
}

TEST(Smaa, DiagonalPatternsLowerTheErrorNear45Degrees) {
    // Edges near 45° against their exact area coverage: SMAA high with its diagonal patterns
    // against the same preset with them switched off (short orthogonal steps) and FXAA. 42°-48°
    // run down to the right ('\\' runs), 138° up to the right ('/'). Measured on llvmpipe (64²):
    // 42°: 0.059 against 0.105 without and FXAA's 0.113; 45°: 0.094, 0.218, 0.221; 138°: as 42°.
    for (float tilt : {42.0f, 45.0f, 138.0f}) {
        const EdgeTilt t(tilt);
        auto f = edgeViewer(AntiAliasing::fxaa());
        const double fxaa = edgeError(renderFrames(*f)).mean;
        auto v = edgeViewer(AntiAliasing::smaa());
        const double diag = edgeError(renderFrames(*v)).mean;
        AntiAliasing off = AntiAliasing::smaa();
        off.smaaDiagonalSteps = 0;
        auto o = edgeViewer(off);
        const double orth = edgeError(renderFrames(*o)).mean;
        std::printf("%.0f deg edge: SMAA high mean %.4f, without diagonals %.4f, FXAA %.4f\n", tilt, diag,
                    orth, fxaa);
        EXPECT_LT(diag, orth) << tilt;
        EXPECT_LT(diag, fxaa) << tilt;
    }
    // Low and medium search no diagonals (the reference's presets); ultra does, 16 steps.
    const EdgeTilt t(42.0f);
    AntiAliasing medium = AntiAliasing::smaa(AntiAliasing::SmaaPreset::Medium), mediumOff = medium;
    mediumOff.smaaDiagonalSteps = 0;
    auto m = edgeViewer(medium), mo = edgeViewer(mediumOff);
    EXPECT_EQ(renderFrames(*m).pixels, renderFrames(*mo).pixels);
    AntiAliasing ultraOff = AntiAliasing::smaa(AntiAliasing::SmaaPreset::Ultra);
    ultraOff.smaaDiagonalSteps = 0;
    auto u = edgeViewer(AntiAliasing::smaa(AntiAliasing::SmaaPreset::Ultra)), uo = edgeViewer(ultraOff);
    EXPECT_LT(edgeError(renderFrames(*u)).mean, edgeError(renderFrames(*uo)).mean);
}

TEST(Smaa, ThinLinesKeepTheirInkBetterThanFxaa) {
    // A 1-px strip at 23°: the black in each row against the strip's exact area there, and per
    // pixel against its coverage. Measured on llvmpipe: per row SMAA (high) 0.150 px, FXAA 0.395,
    // no AA 0.175 (FXAA smears the line across its neighbours); per pixel 0.085, 0.171, 0.207.
    auto none = lineViewer(AntiAliasing::none());
    const LineError n = lineError(renderFrames(*none));
    auto f = lineViewer(AntiAliasing::fxaa());
    const LineError fx = lineError(renderFrames(*f));
    auto v = lineViewer(AntiAliasing::smaa());
    const LineError sm = lineError(renderFrames(*v));
    std::printf(
        "1 px line: ink error per row SMAA %.3f FXAA %.3f none %.3f px; per pixel SMAA %.4f FXAA %.4f "
        "none %.4f\n",
        sm.rowMean, fx.rowMean, n.rowMean, sm.pixelMean, fx.pixelMean, n.pixelMean);
    EXPECT_LT(sm.rowMean, fx.rowMean);
    EXPECT_LT(sm.pixelMean, fx.pixelMean);
}

TEST(Smaa, ColourAndDepthEdgesAntialiasTheEdgeToo) {
    auto none = edgeViewer(AntiAliasing::none());
    const double noAa = edgeError(renderFrames(*none)).mean;
    for (auto edge : {AntiAliasing::SmaaEdge::Colour, AntiAliasing::SmaaEdge::Depth}) {
        auto v = edgeViewer(AntiAliasing::smaa(AntiAliasing::SmaaPreset::High, edge));
        const EdgeError e = edgeError(renderFrames(*v));
        std::printf("SMAA edges %d: mean %.4f worst %.3f (no AA %.4f)\n", int(edge), e.mean, e.worst, noAa);
        EXPECT_LT(e.mean, 0.35 * noAa) << int(edge);
    }
}

TEST(Smaa, T2xConvergesToTheMeanOfItsTwoJitteredFrames) {
    // From the second frame on each image is the mean of two SMAA'd frames jittered ±¼ px on a
    // diagonal: it stops changing, and its error is no worse than one SMAA 1x frame's.
    auto one = edgeViewer(AntiAliasing::smaa());
    const EdgeError single = edgeError(renderFrames(*one));
    auto v = edgeViewer(AntiAliasing::smaaT2x());
    std::vector<Image> frames;
    for (int i = 0; i < 5; ++i)
        frames.push_back(renderFrames(*v));
    const EdgeError first = edgeError(frames[0]), last = edgeError(frames[4]);
    const int changing = channelsDiffering(frames[3], frames[4], 1);
    std::printf("SMAA T2x: frame 1 mean %.4f worst %.3f, frame 5 mean %.4f worst %.3f (SMAA 1x %.4f %.3f); "
                "%d channels differ by > 1 between frames 4 and 5\n",
                first.mean, first.worst, last.mean, last.worst, single.mean, single.worst, changing);
    EXPECT_EQ(changing, 0);
    EXPECT_LE(last.mean, single.mean * 1.05);
    EXPECT_GT(channelsDiffering(frames[0], frames[1], 1), 0) << "the second frame adds the other jitter";
}

TEST(Smaa, FogAoAndOitKeepTheirInteriorUnderSmaa) {
    // Pixels away from edges are left alone: SMAA's passes come after fog, AO and the OIT resolve.
    for (const AntiAliasing& aa : {AntiAliasing::smaa(), AntiAliasing::smaaT2x()}) {
        const auto [interior, differing] = interiorChangedBy(aa);
        EXPECT_GT(interior, 96 * 96 / 2);
        // T2x's ¼ px jitter moves AO's screen-space samples over the geometry: a pixel or two.
        EXPECT_LE(differing, aa.mode == AntiAliasing::Mode::SmaaT2x ? interior / 1000 : 0) << aa.name();
        const auto img = paneOverHalfPlane(aa);
        const int x = kSize / 2 + 14, y = kSize / 2 - 8; // inside the pane, white below
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(pixelAt(img[1], x, y)[c], pixelAt(img[0], x, y)[c], 1) << aa.name();
        EXPECT_NE(pixelAt(img[1], x, y).r, 255) << "the pane is there";
    }
}

TEST(Smaa, SettingsAreValidatedAndNamed) {
    auto cam = Camera::create();
    AntiAliasing a = AntiAliasing::smaa();
    a.smaaPreset = AntiAliasing::SmaaPreset(7);
    EXPECT_THROW(cam->setAntiAliasing(a), std::invalid_argument);
    a = AntiAliasing::smaa();
    a.smaaEdge = AntiAliasing::SmaaEdge(5);
    try {
        cam->setAntiAliasing(a);
        ADD_FAILURE() << "accepted";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("smaaEdge"), std::string::npos) << e.what();
    }
    EXPECT_EQ(cam->antiAliasing().mode, AntiAliasing::Mode::None);
    for (const char* name :
         {"smaa", "smaa-low", "smaa-ultra-depth", "smaa-colour", "smaa-t2x", "smaa-t2x-medium"})
        EXPECT_EQ(AntiAliasing::parse(name).name(), name);
    EXPECT_EQ(AntiAliasing::parse("smaa-t2x-low-colour"),
              AntiAliasing::smaaT2x(AntiAliasing::SmaaPreset::Low, AntiAliasing::SmaaEdge::Colour));
    EXPECT_THROW(AntiAliasing::parse("smaa-huge"), std::invalid_argument);
    a = AntiAliasing::smaa();
    a.smaaDiagonalSteps = 20;
    EXPECT_THROW(a.validate(), std::invalid_argument);
    auto v = edgeViewer(AntiAliasing::smaa());
    for (auto [w, h] : {std::pair{17, 9}, std::pair{1, 1}, std::pair{kSize, kSize}}) {
        v->camera()->setViewport(0, 0, w, h);
        EXPECT_NO_THROW(v->frame()) << w << "x" << h;
    }
}

TEST(Smaa, CornerDetectionKeepsASquaresCornersSharp) {
    // An axis-aligned black square 16 px wide on pixel boundaries: the exact image is black and
    // white. Its sides end at real corners (the crossing edge runs on), which the high preset's
    // corner detection blends at a quarter of the weight; medium (no corner detection) rounds them.
    auto square = [](const AntiAliasing& aa) {
        auto q = shapes::quad(1.0f, 1.0f);
        auto m = Material::create();
        m->ambient = glm::vec3(0);
        m->diffuse = glm::vec4(0, 0, 0, 1);
        m->emissive = glm::vec3(0);
        q->getOrCreateStateSet().material.set(m);
        auto v = orthoTopViewer(kSize, kHalf);
        v->camera()->clearColor = {1, 1, 1, 1};
        v->camera()->setAntiAliasing(aa);
        v->setSceneData(q);
        const Image img = renderFrames(*v);
        double error = 0; // against the exact black-and-white image
        for (int y = 0; y < kSize; ++y)
            for (int x = 0; x < kSize; ++x) {
                const bool inside = x >= 24 && x < 40 && y >= 24 && y < 40;
                error += std::abs(linearValue(img, x, y) - (inside ? 0.0 : 1.0));
            }
        return error;
    };
    const double none = square(AntiAliasing::none());
    const double medium = square(AntiAliasing::smaa(AntiAliasing::SmaaPreset::Medium));
    const double high = square(AntiAliasing::smaa(AntiAliasing::SmaaPreset::High));
    std::printf("square's corners: total error none %.3f, SMAA medium %.3f, high (corners) %.3f\n", none,
                medium, high);
    EXPECT_LT(none, 0.05) << "the square lies on pixel boundaries";
    EXPECT_GT(medium, 0.5);
    EXPECT_LT(high, 0.5 * medium);
}

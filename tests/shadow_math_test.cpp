// ShadowMath (the CPU side of cascaded and spot shadow maps, docs/plans/shadows.md §5) against
// expectations computed here without it: hand values of the split scheme, frustum corners built
// from the camera pose, texel grids by integer division, rays from the light's rim.
#include <sgfx/nodes/shadow/ShadowMath.h>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

using namespace sgfx;

namespace {

constexpr double kPi = std::numbers::pi;
double deg(double d) {
    return d * kPi / 180.0;
}

// The message of the std::invalid_argument that `f` throws, or "" when it throws none.
template <class F> std::string thrown(F f) {
    try {
        f();
    } catch (const std::invalid_argument& e) {
        return e.what();
    }
    return "";
}

struct Pose {
    glm::dvec3 eye;
    glm::dmat3 rotation; // camera to world; the camera looks along −Z
};

Pose randomPose(std::mt19937& rng) {
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    glm::dvec3 axis(u(rng), u(rng), u(rng));
    if (glm::length(axis) < 1e-3) axis = {0, 0, 1};
    const glm::dquat q = glm::angleAxis(kPi * u(rng), glm::normalize(axis));
    return {glm::dvec3(u(rng), u(rng), u(rng)) * 1000.0, glm::mat3_cast(q)};
}

// The 8 corners of the perspective slice [a, b], built from the frustum's planes.
std::vector<glm::dvec3> perspectiveCorners(const Pose& p, double fovy, double aspect, double a, double b) {
    const double ty = std::tan(fovy / 2), tx = aspect * ty;
    std::vector<glm::dvec3> out;
    for (double d : {a, b})
        for (double sx : {-1.0, 1.0})
            for (double sy : {-1.0, 1.0})
                out.push_back(p.eye + p.rotation * glm::dvec3(sx * d * tx, sy * d * ty, -d));
    return out;
}

// Largest and smallest distance of the corners from `centre`.
std::pair<double, double> cornerDistances(const std::vector<glm::dvec3>& corners, const glm::dvec3& centre) {
    double lo = 1e300, hi = 0;
    for (const auto& c : corners) {
        lo = std::min(lo, glm::length(c - centre));
        hi = std::max(hi, glm::length(c - centre));
    }
    return {lo, hi};
}

// Plan defaults (§2): constantBias, slopeBias, maxSlope, normalOffset, pcfRadius.
constexpr double kCb = 0.5, kSb = 0.5, kM = 2.0, kNo = 1.0, kRk = 1.5;

} // namespace

TEST(ShadowMath, SplitsMatchThePlansHandValues) {
    const auto c = shadow::practicalSplits(0.1, 200.0, 3, 0.75);
    ASSERT_EQ(c.size(), 4u);
    EXPECT_NEAR(c[1], 17.6, 0.05);
    EXPECT_NEAR(c[2], 45.25, 0.005); // the plan rounds this 45.247 to "45.3"
    // 0.75·0.1·2000^(1/3) + 0.25·(0.1 + 199.9/3), by hand.
    EXPECT_NEAR(c[1], 0.75 * 0.1 * 12.599210498948732 + 0.25 * (0.1 + 199.9 / 3), 1e-12);
}

TEST(ShadowMath, SplitsAtLambdaZeroAreUniform) {
    for (int n = 1; n <= 4; ++n) {
        const auto c = shadow::practicalSplits(0.5, 300.0, n, 0.0);
        for (int i = 1; i <= n; ++i)
            EXPECT_NEAR(c[size_t(i)] - c[size_t(i) - 1], 299.5 / n, 1e-9) << "N " << n << " i " << i;
    }
}

TEST(ShadowMath, SplitsAtLambdaOneAreGeometric) {
    for (int n = 1; n <= 4; ++n) {
        const auto c = shadow::practicalSplits(0.1, 1000.0, n, 1.0);
        const double ratio = std::pow(1e4, 1.0 / n);
        for (int i = 1; i <= n; ++i)
            EXPECT_NEAR(c[size_t(i)] / c[size_t(i) - 1], ratio, 1e-9 * ratio) << "N " << n << " i " << i;
    }
}

TEST(ShadowMath, SplitsAreMonotoneWithExactEnds) {
    for (double nearD : {1e-3, 0.1, 1.0, 50.0})
        for (double farD : {60.0, 200.0, 1e6})
            for (int n = 1; n <= 4; ++n)
                for (double lambda : {0.0, 0.25, 0.5, 0.75, 1.0}) {
                    const auto c = shadow::practicalSplits(nearD, farD, n, lambda);
                    ASSERT_EQ(c.size(), size_t(n) + 1);
                    EXPECT_EQ(c.front(), nearD);
                    EXPECT_EQ(c.back(), farD);
                    for (size_t i = 1; i < c.size(); ++i)
                        EXPECT_GT(c[i], c[i - 1]) << nearD << " " << farD << " " << n << " " << lambda;
                }
}

TEST(ShadowMath, SplitsRejectBadParametersByName) {
    const double nan = std::nan("");
    EXPECT_EQ(thrown([] { shadow::practicalSplits(0.1, 200, 5, 0.5); }),
              "sgfx: ShadowMath: cascades = 5 is outside [1, 4]");
    EXPECT_EQ(thrown([] { shadow::practicalSplits(0.1, 200, 0, 0.5); }),
              "sgfx: ShadowMath: cascades = 0 is outside [1, 4]");
    EXPECT_EQ(thrown([] { shadow::practicalSplits(0.1, 200, 3, 1.5); }),
              "sgfx: ShadowMath: lambda = 1.5 is outside [0, 1]");
    EXPECT_EQ(thrown([] { shadow::practicalSplits(0.1, 200, 3, -0.1); }),
              "sgfx: ShadowMath: lambda = -0.1 is outside [0, 1]");
    EXPECT_EQ(thrown([] { shadow::practicalSplits(0, 200, 3, 0.5); }),
              "sgfx: ShadowMath: near = 0 is outside (0, inf)");
    EXPECT_EQ(thrown([] { shadow::practicalSplits(10, 10, 3, 0.5); }),
              "sgfx: ShadowMath: far = 10 is outside (near, inf)");
    EXPECT_EQ(thrown([&] { shadow::practicalSplits(0.1, nan, 3, 0.5); }),
              "sgfx: ShadowMath: far is nan; it must be finite");
    EXPECT_EQ(thrown([&] { shadow::practicalSplits(0.1, HUGE_VAL, 3, 0.5); }),
              "sgfx: ShadowMath: far is inf; it must be finite");
    EXPECT_EQ(thrown([&] { shadow::practicalSplits(0.1, 200, 3, nan); }),
              "sgfx: ShadowMath: lambda is nan; it must be finite");
    EXPECT_EQ(thrown([] { shadow::perspectiveSliceSphere(deg(60), 1.5, 5, 5); }),
              "sgfx: ShadowMath: b = 5 is outside (a, inf)");
    EXPECT_EQ(thrown([] { shadow::perspectiveSliceSphere(deg(60), 0, 1, 5); }),
              "sgfx: ShadowMath: aspect = 0 is outside (0, inf)");
    EXPECT_EQ(thrown([] { shadow::practicalSplits(0.1, 200, 3, 0.5); }), "");
}

TEST(ShadowMath, SliceSphereHoldsEveryCornerTightlyForAnyPose) {
    std::mt19937 rng(28);
    for (double fovy : {deg(10), deg(45), deg(60), deg(100), deg(150)})
        for (double aspect : {0.5, 1.0, 16.0 / 9.0, 4.0})
            for (auto [a, b] :
                 {std::pair{0.1, 17.6}, {15.8, 45.3}, {0.0, 1.0}, {40.0, 200.0}, {199.0, 200.0}}) {
                const auto s = shadow::perspectiveSliceSphere(fovy, aspect, a, b);
                for (int k = 0; k < 100; ++k) {
                    const Pose p = randomPose(rng);
                    const glm::dvec3 centre = p.eye + s.centreDistance * (p.rotation * glm::dvec3(0, 0, -1));
                    const auto [lo, hi] = cornerDistances(perspectiveCorners(p, fovy, aspect, a, b), centre);
                    // Contains all 8 corners, and the farthest lies on the surface: r is the same for
                    // every pose because the sphere is fixed to the frustum.
                    EXPECT_LE(hi, s.radius * (1 + 1e-12)) << fovy << " " << aspect << " " << a << " " << b;
                    EXPECT_NEAR(hi, s.radius, 1e-9 * s.radius)
                        << fovy << " " << aspect << " " << a << " " << b;
                    EXPECT_GE(lo, 0.0);
                }
            }
}

TEST(ShadowMath, SliceSphereIsEquidistantFromNearAndFarCornersWhenInside) {
    // 30°, 3:2, [1, 10]: k² ≈ 0.233, z* = 11·(1 + k²)/2 ≈ 6.8 < 10, so both corner sets lie on it.
    const double fovy = deg(30), aspect = 1.5;
    const auto s = shadow::perspectiveSliceSphere(fovy, aspect, 1.0, 10.0);
    ASSERT_LT(s.centreDistance, 10.0);
    const Pose p{{0, 0, 0}, glm::dmat3(1.0)};
    const auto [lo, hi] =
        cornerDistances(perspectiveCorners(p, fovy, aspect, 1.0, 10.0), {0, 0, -s.centreDistance});
    EXPECT_NEAR(lo, hi, 1e-12 * hi);
    // Wide fov: the centre stops at the far plane and the radius is the far half-diagonal.
    const auto w = shadow::perspectiveSliceSphere(deg(120), 2.0, 5.0, 10.0);
    EXPECT_EQ(w.centreDistance, 10.0);
    const double ty = std::tan(deg(60));
    EXPECT_NEAR(w.radius, 10.0 * ty * std::sqrt(1.0 + 4.0), 1e-12 * w.radius);
}

TEST(ShadowMath, OrthoSliceSphereIsTheBoxHalfDiagonal) {
    const auto s = shadow::orthoSliceSphere(3.0, 4.0, -2.0, 22.0);
    EXPECT_EQ(s.centreDistance, 10.0);
    EXPECT_NEAR(s.radius, 13.0, 1e-12); // √(9 + 16 + 144)
    std::mt19937 rng(7);
    for (int k = 0; k < 20; ++k) {
        const Pose p = randomPose(rng);
        std::vector<glm::dvec3> corners;
        for (double z : {-2.0, 22.0})
            for (double x : {-3.0, 3.0})
                for (double y : {-4.0, 4.0})
                    corners.push_back(p.eye + p.rotation * glm::dvec3(x, y, -z));
        const auto [lo, hi] = cornerDistances(corners, p.eye + p.rotation * glm::dvec3(0, 0, -10.0));
        EXPECT_NEAR(lo, 13.0, 1e-9);
        EXPECT_NEAR(hi, 13.0, 1e-9);
    }
}

TEST(ShadowMath, SlicesReachBackOverTheBlendBand) {
    const auto c = shadow::practicalSplits(0.1, 200.0, 4, 0.75);
    EXPECT_EQ(shadow::sliceStart(c, 0, 0.1), 0.1);
    for (int k = 1; k < 4; ++k) {
        const double expect = c[size_t(k)] - 0.1 * (c[size_t(k)] - c[size_t(k) - 1]);
        EXPECT_NEAR(shadow::sliceStart(c, k, 0.1), expect, 1e-12);
        EXPECT_EQ(shadow::sliceStart(c, k, 0.0), c[size_t(k)]);
    }
}

TEST(ShadowMath, LightRotationIsOrthonormalAndLooksAlongMinusL) {
    std::vector<glm::dvec3> lights = {{0, 0, 1},     {0, 0, -1}, {0.01, 0, 1},
                                      {0, 0.05, -1}, {1, 0, 0},  {0, -2, 0.1}};
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-1, 1);
    for (int k = 0; k < 50; ++k)
        lights.push_back({u(rng), u(rng), u(rng)});
    for (const glm::dvec3& raw : lights) {
        const glm::dvec3 l = glm::normalize(raw);
        const glm::dmat3 v = shadow::lightRotation(raw);
        const glm::dmat3 vvt = v * glm::transpose(v);
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j)
                EXPECT_NEAR(vvt[i][j], i == j ? 1.0 : 0.0, 1e-12);
        EXPECT_NEAR(glm::determinant(v), 1.0, 1e-12);
        const glm::dvec3 f = v * (-l);
        EXPECT_NEAR(f.x, 0, 1e-12);
        EXPECT_NEAR(f.y, 0, 1e-12);
        EXPECT_NEAR(f.z, -1, 1e-12);
        // Light-space x (first row) is horizontal unless the light is near vertical.
        const glm::dvec3 right(v[0][0], v[1][0], v[2][0]);
        if (std::abs(l.z) <= 0.99) {
            EXPECT_NEAR(right.z, 0.0, 1e-12);
        }
    }
    EXPECT_EQ(thrown([] {
                  shadow::lightRotation({0, 0, 0});
              }),
              "sgfx: ShadowMath: |towardsLight| = 0 is outside (0, inf)");
}

TEST(ShadowMath, MarginKeepsKernelTapsInsideTheTile) {
    EXPECT_EQ(shadow::marginTexels(1.5), 3);
    EXPECT_EQ(shadow::marginTexels(1.0), 2);
    EXPECT_EQ(shadow::pcssMarginTexels(16), 9);
    EXPECT_EQ(shadow::pcssMarginTexels(5), 4);
    // r' − r is exactly m texels of the enlarged map.
    const double r = 37.25, rp = shadow::marginRadius(r, 2048, 3), t = shadow::texelSize(rp, 2048);
    EXPECT_NEAR(rp - r, 3 * t, 1e-12 * r);
    EXPECT_NEAR(t, 2 * rp / 2048, 1e-15);
    EXPECT_FALSE(thrown([] { shadow::marginRadius(1, 8, 4); }).empty());
}

TEST(ShadowMath, SubTexelCameraMovesMoveTheSnappedBoxByWholeTexels) {
    const glm::dmat3 v = shadow::lightRotation({0.3, -0.5, 0.6});
    const auto s = shadow::perspectiveSliceSphere(deg(60), 16.0 / 9.0, 15.0, 45.0);
    const int size = 2048, m = 3;
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(-1, 1);
    for (glm::dvec3 base : {glm::dvec3(0), glm::dvec3(1234.5, -987.25, 3.0), glm::dvec3(1e5, 2e5, 50)}) {
        const auto first = shadow::fitCascade(v, base, s.radius, size, m);
        const double t = first.texel;
        for (int k = 0; k < 200; ++k) {
            // Any fraction of a texel, in any direction (k ≥ 100: up to 50 texels).
            const glm::dvec3 move = glm::dvec3(u(rng), u(rng), u(rng)) * t * (k < 100 ? 1.0 : 50.0);
            const glm::dvec3 centre = base + move;
            const auto fit = shadow::fitCascade(v, centre, s.radius, size, m);
            EXPECT_EQ(fit.texel, t);
            for (int axis = 0; axis < 2; ++axis) {
                const double shift = (fit.centre[axis] - first.centre[axis]) / t;
                EXPECT_NEAR(shift, std::round(shift), 1e-9) << "axis " << axis << " k " << k;
                // A sub-texel move in light space moves the box by 0 or ±1 texel.
                const double lightMove = (v * move)[axis];
                if (std::abs(lightMove) < t) {
                    EXPECT_LE(std::abs(std::round(shift)), 1.0);
                }
                // The snapped box c' ± r' contains the sphere's projection c ± r.
                const double c = glm::dot(glm::dvec3(v[0][axis], v[1][axis], v[2][axis]), centre);
                EXPECT_LE(std::abs(c - fit.centre[axis]) + s.radius, fit.halfExtent);
            }
        }
    }
}

TEST(ShadowMath, SnappedCentresAreMultiplesOfTheTexelAndUnsnappedOnesAreNot) {
    const double t = 0.0625 * 3;
    int offGrid = 0;
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(-500, 500);
    for (int k = 0; k < 100; ++k) {
        const glm::dvec2 c(u(rng), u(rng));
        const glm::dvec2 snapped = shadow::snapToTexels(c, t);
        for (int axis = 0; axis < 2; ++axis) {
            EXPECT_NEAR(snapped[axis] / t, std::round(snapped[axis] / t), 1e-9);
            EXPECT_LE(std::abs(snapped[axis] - c[axis]), t / 2 * (1 + 1e-12));
            if (std::abs(c[axis] / t - std::round(c[axis] / t)) > 1e-6) ++offGrid;
        }
    }
    EXPECT_GT(offGrid, 150); // negative control: the test can tell snapped from unsnapped
    const auto raw = shadow::fitCascade(glm::dmat3(1.0), {0.3, 0.7, 0}, 10.0, 1024, 3, false);
    EXPECT_EQ(raw.centre, glm::dvec2(0.3, 0.7));
}

TEST(ShadowMath, CascadeWeightsSumToOneAndAreContinuous) {
    for (int n = 1; n <= 4; ++n)
        for (double beta : {0.0, 0.1, 0.5})
            for (double phi : {0.0, 0.1, 0.5}) {
                const auto c = shadow::practicalSplits(0.1, 200.0, n, 0.75);
                auto prev = shadow::cascadeWeights(c, 0.0, beta, phi);
                const double h = 1e-3;
                for (double z = 0.0; z <= 210.0; z += h) {
                    const auto w = shadow::cascadeWeights(c, z, beta, phi);
                    double sum = 0;
                    for (int k = 0; k <= n; ++k) {
                        sum += w[size_t(k)];
                        EXPECT_GE(w[size_t(k)], 0.0);
                        // A cascade is used only inside its slice (which reaches back over the band).
                        if (k < n && w[size_t(k)] > 0) {
                            EXPECT_GE(z, k == 0 ? 0.0 : shadow::sliceStart(c, k, beta));
                            EXPECT_LE(z, c[size_t(k) + 1]);
                        }
                    }
                    ASSERT_NEAR(sum, 1.0, 1e-12) << n << " " << z;
                    // Bands at least 0.1·(C1 − C0) ≈ 1.7 m wide: smoothstep moves < 1e-3 per mm. A zero
                    // band is a step at the split by design; nothing else may jump.
                    for (int k = 0; k <= n && beta > 0 && phi > 0; ++k) {
                        ASSERT_LT(std::abs(w[size_t(k)] - prev[size_t(k)]), 2e-3)
                            << n << " " << z << " " << k;
                    }
                    prev = w;
                }
                // Past the far split everything is lit; before the fade band nothing is.
                EXPECT_EQ(shadow::cascadeWeights(c, 201.0, beta, phi)[size_t(n)], 1.0);
                EXPECT_EQ(shadow::selectCascade(c, 201.0, beta, phi).cascade, n);
                const double fadeStart = 200.0 - phi * (200.0 - c[size_t(n) - 1]);
                EXPECT_EQ(shadow::cascadeWeights(c, fadeStart - 1e-6, beta, phi)[size_t(n)], 0.0);
            }
}

TEST(ShadowMath, CascadeSelectionPicksTheFirstSplitBeyondTheDepth) {
    const auto c = shadow::practicalSplits(0.1, 200.0, 3, 0.75);
    EXPECT_EQ(shadow::selectCascade(c, 5.0, 0.1, 0.1).cascade, 0);
    EXPECT_EQ(shadow::selectCascade(c, c[1], 0.1, 0.1).cascade, 0);
    EXPECT_EQ(shadow::selectCascade(c, c[1] + 1e-9, 0.1, 0.1).cascade, 1);
    EXPECT_EQ(shadow::selectCascade(c, 100.0, 0.1, 0.1).cascade, 2);
    EXPECT_NEAR(shadow::selectCascade(c, c[1], 0.1, 0.1).blend, 1.0, 1e-12);
    // Midway through the band: smoothstep(½) = ½.
    const double mid = c[2] - 0.05 * (c[2] - c[1]);
    EXPECT_NEAR(shadow::selectCascade(c, mid, 0.1, 0.1).blend, 0.5, 1e-12);
}

TEST(ShadowMath, DefaultBiasOpensUnderTwoTexelsOfContactGapFrom3To85Degrees) {
    const double t = 0.04;
    for (double e = 3.0; e <= 85.0; e += 0.5) {
        // Ground receiver, sun at elevation e: θ = 90° − e, cos θ = sin e.
        const double b = shadow::receiverBias(t, std::sin(deg(e)), kCb, kSb, kRk, kM);
        const double gap = b * std::cos(deg(e)); // along the ground, box base to shadow start
        EXPECT_LE(gap / t, 2.0) << e;
        EXPECT_LE(b, 2.0 * t * (1 + 1e-12)) << e; // t·(0.5 + 0.5·1.5·2)
        EXPECT_GE(b, 0.5 * t);
    }
    // Head-on: the constant only; grazing and back-facing: capped at M.
    EXPECT_NEAR(shadow::receiverBias(t, 1.0, kCb, kSb, kRk, kM), kCb * t, 1e-15);
    EXPECT_NEAR(shadow::receiverBias(t, 0.0, kCb, kSb, kRk, kM), 2.0 * t, 1e-15);
    EXPECT_NEAR(shadow::receiverBias(t, -0.5, kCb, kSb, kRk, kM), 2.0 * t, 1e-15);
    // 45°: tan θ = 1, R = 1.5.
    EXPECT_NEAR(shadow::receiverBias(t, std::cos(deg(45)), kCb, kSb, kRk, kM), t * (0.5 + 0.5 * 1.5), 1e-12);
    // R = max(R_k, 1).
    EXPECT_NEAR(shadow::receiverBias(t, std::cos(deg(45)), kCb, kSb, 0.5, kM), t * (0.5 + 0.5), 1e-12);
}

TEST(ShadowMath, NormalOffsetCoversTheKernelsDepthSpreadOnTiltedPlanes) {
    const double t = 0.05;
    for (double tilt = 0.0; tilt <= 80.0; tilt += 1.0) {
        const double cosT = std::cos(deg(tilt));
        // Under a disc of R + ½ texels a plane tilted θ spans (R + ½)·t·tan θ of depth along L; the
        // normal offset δ adds δ/cos θ of margin (plan §5). Acne-free needs margin ≥ spread.
        const double delta = shadow::normalOffset(t, cosT, kNo, kRk);
        const double spread = (kRk + 0.5) * t * std::tan(deg(tilt));
        EXPECT_GE(delta / cosT, spread * (1 - 1e-12)) << tilt;
        EXPECT_NEAR(delta, (kRk + 0.5) * t * std::sin(deg(tilt)), 1e-12) << tilt;
    }
    EXPECT_EQ(shadow::normalOffset(t, 1.0, kNo, kRk), 0.0);
    EXPECT_NEAR(shadow::normalOffset(t, 0.0, 2.0, 0.5), 2.0 * t * 1.5, 1e-15);
}

TEST(ShadowMath, SunPenumbraGrowsLinearlyWithBlockerDistance) {
    const double alpha = 0.05;
    for (double h : {0.5, 1.0, 2.0, 4.0}) {
        // A blocker edge h above the receiver: rays from the sun's opposite rims (±α) through the
        // edge land h·tan α either side of the point below it.
        const double w = shadow::sunPenumbraWidth(100.0 + h, 100.0, alpha);
        EXPECT_NEAR(w, 2 * h * std::tan(alpha), 1e-12) << h;
        EXPECT_NEAR(w / h, shadow::sunPenumbraWidth(101.0, 100.0, alpha), 1e-12) << h;
        EXPECT_NEAR(shadow::pcssFilterRadius(w, 1.5, 0.01), std::max(h * std::tan(alpha), 0.015), 1e-12);
    }
    EXPECT_EQ(shadow::sunPenumbraWidth(10.0, 10.0, alpha), 0.0);
    // The search cone's radius, capped at maxPenumbra texels.
    EXPECT_NEAR(shadow::sunSearchWidth(12.0, 2.0, alpha, 16, 0.1), 10.0 * std::tan(alpha), 1e-12);
    EXPECT_NEAR(shadow::sunSearchWidth(500.0, 2.0, alpha, 16, 0.1), 1.6, 1e-12);
}

TEST(ShadowMath, SpotPenumbraFollowsSimilarTriangles) {
    const double wl = 0.05;
    for (double db : {0.5, 1.0, 3.0})
        for (double dr : {db, db + 0.5, db + 2.0, 4 * db}) {
            // Rays from the source rim (±w_l at depth 0) through the blocker edge (x = 0, depth d_b)
            // reach the receiver at x = ∓w_l·(d_r − d_b)/d_b: the penumbra spans the two.
            const double x0 = wl + (0.0 - wl) * dr / db, x1 = -wl + (0.0 + wl) * dr / db;
            EXPECT_NEAR(shadow::spotPenumbraWidth(wl, dr, db), x1 - x0, 1e-12) << db << " " << dr;
            EXPECT_NEAR(shadow::spotPenumbraWidth(wl, dr, db) / 2, (dr - db) * wl / db, 1e-12);
        }
    // Search: the cone from the receiver to the source's rim, cut at the near plane.
    const double dr = 8.0, nearD = 0.05;
    EXPECT_NEAR(shadow::spotSearchWidth(wl, dr, nearD), wl * (1 - nearD / dr), 1e-15);
}

TEST(ShadowMath, SpotTexelSizeMatchesItsProjection) {
    const glm::dvec3 pos(3, -2, 6), axis = glm::normalize(glm::dvec3(0.2, 0.1, -1));
    const double fovy = shadow::spotFovy(deg(30), deg(2));
    EXPECT_NEAR(fovy, deg(62), 1e-15);
    const int size = 1024;
    const glm::dmat4 pv = shadow::spotProjection(fovy, 0.05, 50.0) * shadow::spotView(pos, axis);
    for (double d : {0.5, 4.0, 30.0}) {
        const double t = shadow::spotTexelSize(d, fovy, size);
        // Two points d along the axis, one texel apart across it, land 2/S apart in NDC.
        const glm::dvec3 across = glm::normalize(glm::cross(axis, glm::dvec3(0, 0, 1)));
        const glm::dvec4 p0 = pv * glm::dvec4(pos + d * axis, 1.0);
        const glm::dvec4 p1 = pv * glm::dvec4(pos + d * axis + t * across, 1.0);
        EXPECT_NEAR(p0.x / p0.w, 0.0, 1e-12);
        EXPECT_NEAR(p0.y / p0.w, 0.0, 1e-12);
        EXPECT_NEAR(glm::length(glm::dvec2(p1) / p1.w - glm::dvec2(p0) / p0.w), 2.0 / size, 1e-9);
    }
    // A vertical spot takes the +X up fallback and stays finite.
    const glm::dmat4 down = shadow::spotView(pos, {0, 0, -1});
    const glm::dvec4 below = down * glm::dvec4(pos + glm::dvec3(0, 0, -2), 1.0);
    EXPECT_NEAR(below.z, -2.0, 1e-12);
    EXPECT_NEAR(glm::length(glm::dvec2(below)), 0.0, 1e-12);
}

// The PCF disc: 16 points in the unit disc, the 4 early-out probes first (radius 0.95, one per
// quadrant), and well spread: no two closer than 0.25 (a 16-point Poisson disc of the unit disc
// packs at about 0.3; clumps of random points come far closer).
TEST(ShadowMath, PoissonDiscIsInsideTheDiscAndSpread) {
    const auto& p = shadow::poissonDisc();
    ASSERT_EQ(p.size(), 16u);
    for (const glm::dvec2& q : p)
        EXPECT_LE(glm::length(q), 1.0);
    std::set<int> quadrants;
    for (int k = 0; k < 4; ++k) {
        EXPECT_NEAR(glm::length(p[std::size_t(k)]), 0.95, 1e-12);
        quadrants.insert((p[std::size_t(k)].x > 0 ? 1 : 0) + (p[std::size_t(k)].y > 0 ? 2 : 0));
    }
    EXPECT_EQ(quadrants.size(), 4u);
    double closest = 4.0;
    for (std::size_t i = 0; i < p.size(); ++i)
        for (std::size_t j = i + 1; j < p.size(); ++j)
            closest = std::min(closest, glm::distance(p[i], p[j]));
    EXPECT_GE(closest, 0.25);
    EXPECT_EQ(&shadow::poissonDisc(), &p); // one table, made once
}

TEST(ShadowMath, AtlasLayoutPutsTilesInRowsWithinTheLimit) {
    const shadow::AtlasLayout one = shadow::atlasLayout(3, 2048, 16384);
    EXPECT_EQ(one.size, glm::ivec2(6144, 2048));
    ASSERT_EQ(one.tiles.size(), 3u);
    EXPECT_EQ(one.tiles[2], glm::ivec4(4096, 0, 2048, 2048));
    const shadow::AtlasLayout two = shadow::atlasLayout(4, 4096, 8192); // two per row
    EXPECT_EQ(two.size, glm::ivec2(8192, 8192));
    EXPECT_EQ(two.tiles[3], glm::ivec4(4096, 4096, 4096, 4096));
    EXPECT_NE(thrown([] { shadow::atlasLayout(0, 512, 4096); }), "");
    EXPECT_NE(thrown([] { shadow::atlasLayout(2, 8192, 4096); }), "");
    EXPECT_NE(thrown([] { shadow::atlasLayout(5, 4096, 8192); }), ""); // three rows do not fit
}

// World to atlas: the fitted square's corners land on the tile's corners, the nearest depth of
// the range (towards the light) on 0 and the farthest on 1; built by hand from V_L.
TEST(ShadowMath, AtlasMatrixMapsTheCascadeSquareOntoItsTile) {
    const glm::dvec3 L = glm::normalize(glm::dvec3(0.3, -0.5, 0.8));
    const glm::dmat3 V = shadow::lightRotation(L);
    const shadow::CascadeFit fit = shadow::fitCascade(V, {10, 20, 0}, 30.0, 1024, 3);
    const glm::dmat4 P = shadow::cascadeProjection(fit, -50.0, 70.0);
    const glm::ivec4 tile(1024, 0, 1024, 1024);
    const glm::dmat4 M = shadow::atlasMatrix(tile, {3072, 1024}, P, V);
    const glm::dmat3 Vt = glm::transpose(V); // light to world
    for (int corner = 0; corner < 4; ++corner) {
        const double sx = corner & 1 ? 1.0 : -1.0, sy = corner & 2 ? 1.0 : -1.0;
        const glm::dvec2 light = fit.centre + glm::dvec2(sx, sy) * fit.halfExtent;
        for (const double z : {-50.0, 70.0}) {
            const glm::dvec3 world = Vt * glm::dvec3(light, z);
            const glm::dvec4 a = M * glm::dvec4(world, 1.0);
            EXPECT_NEAR(a.x, (1024.0 + (sx > 0 ? 1024.0 : 0.0)) / 3072.0, 1e-9);
            EXPECT_NEAR(a.y, sy > 0 ? 1.0 : 0.0, 1e-9);
            EXPECT_NEAR(a.z, z == 70.0 ? 0.0 : 1.0, 1e-9);
            EXPECT_NEAR(a.w, 1.0, 1e-12);
        }
    }
}

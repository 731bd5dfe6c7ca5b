// FogMath (the CPU mirror of fog_optical_depth.glsl) against numerical quadrature of the seed's
// integral (eq. 5) in double, over a grid that includes b = 0, exactly horizontal and vertical
// rays, cameras below the reference plane and at 20 km, and distances from 0 to 1e7 m.
#include <sgfx/nodes/fog/FogMath.h>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

using namespace sgfx;

namespace {

// ∫_0^S ρ0·e^(−b·(hO + t·Dh)) dt by Simpson's rule with 10^5 intervals, in double. Where the
// integrand spans more than 60 e-folds, the integral is restricted to the 60 e-folds at its
// large end (the rest is below 1e-26 of it), so each step covers a small fraction of an e-fold.
double simpson(double rho0, double b, double hO, double dh, double S) {
    if (S <= 0.0) return 0.0;
    double t0 = 0.0, t1 = S;
    const double rate = b * dh; // e-folds per metre along the ray (positive: density falls)
    if (rate * S > 60.0) t1 = 60.0 / rate;
    if (-rate * S > 60.0) t0 = S - 60.0 / -rate;
    const int n = 100000;
    const double h = (t1 - t0) / n;
    auto f = [&](double t) { return rho0 * std::exp(-b * (hO + t * dh)); };
    double sum = f(t0) + f(t1);
    for (int i = 1; i < n; ++i)
        sum += f(t0 + i * h) * (i % 2 ? 4.0 : 2.0);
    return sum * h / 3.0;
}

struct Case {
    double rho0, b, cameraHeight, elevationDeg, distance;
};

std::vector<Case> grid() {
    std::vector<Case> cases;
    for (double rho0 : {1e-4, 1e-3, 0.1})
        for (double b : {0.0, 1e-6, 1e-4, 4.5e-3, 0.05})
            for (double hO : {-50.0, 0.0, 2.0, 100.0, 20000.0})
                for (double el : {-90.0, -60.0, -10.0, -0.01, 0.0, 0.01, 10.0, 60.0, 90.0})
                    for (double S : {0.0, 1e-3, 1.0, 100.0, 1e4, 2e4, 1e5, 1e7}) {
                        const double lowest = std::min(hO, hO + S * std::sin(el * std::numbers::pi / 180));
                        // Below −40/b the shader holds the density (kMaxExponent); tested apart.
                        if (b > 0 && -b * lowest > 40.0) continue;
                        cases.push_back({rho0, b, hO, el, S});
                    }
    return cases;
}

} // namespace

TEST(FogMath, ExpQuotientIsContinuousAcrossTheSeriesThreshold) {
    const double y = fog::kSeriesBelow;
    const double below = fog::expQuotient(std::nextafter(y, 0.0));
    const double above = fog::expQuotient(y);
    EXPECT_NEAR(below, above, 1e-12);
    // float: the step is the rounding of 1 − e^(−y) in float32 (a few ulp of the result).
    EXPECT_NEAR(fog::expQuotient(std::nextafter(float(y), 0.0f)), fog::expQuotient(float(y)), 1e-6f);
    EXPECT_DOUBLE_EQ(fog::expQuotient(0.0), 1.0);
}

TEST(FogMath, OpticalDepthMatchesQuadratureInDoubleAndFloat) {
    const auto cases = grid();
    ASSERT_GT(cases.size(), 1500u);
    int checked = 0;
    double worstDouble = 0.0, worstFloat = 0.0;
    for (const Case& c : cases) {
        const double el = c.elevationDeg * std::numbers::pi / 180.0;
        // The ray as the shader sees it: float world positions (camera at x = 1000).
        const glm::vec3 O(1000.0f, -20.0f, float(c.cameraHeight));
        const glm::dvec3 D(std::cos(el), 0.0, std::sin(el));
        const glm::vec3 P = glm::vec3(glm::dvec3(O) + D * c.distance);
        // Reference on exactly that float segment.
        const glm::dvec3 Od(O), Pd(P);
        const double S = glm::length(Pd - Od);
        const double dh = S > 0 ? (Pd.z - Od.z) / S : 0.0;
        const double ref = simpson(c.rho0, c.b, Od.z, dh, S);

        const double Fd = fog::opticalDepth(c.rho0, c.b, Od.z, Pd.z, S);
        const glm::vec3 up(0, 0, 1);
        const float Ff = fog::opticalDepth(float(c.rho0), float(c.b), fog::heightOf(O, up, 0.0f),
                                           fog::heightOf(P, up, 0.0f), glm::length(P - O));
        ASSERT_TRUE(std::isfinite(Fd) && std::isfinite(Ff));
        ASSERT_GE(Ff, 0.0f);
        const double tol = 1e-300;
        const double relD = std::abs(Fd - ref) / std::max(ref, tol);
        const double relF = std::abs(double(Ff) - ref) / std::max(ref, tol);
        if (ref < 1e-30) {
            EXPECT_LT(Fd, 1e-30);
            EXPECT_LT(Ff, 1e-30f);
            continue;
        }
        ++checked;
        worstDouble = std::max(worstDouble, relD);
        worstFloat = std::max(worstFloat, relF);
        EXPECT_LE(relD, 1e-4) << "double: rho0=" << c.rho0 << " b=" << c.b << " hO=" << c.cameraHeight
                              << " el=" << c.elevationDeg << " S=" << c.distance << " F=" << Fd
                              << " ref=" << ref;
        EXPECT_LE(relF, 1e-3) << "float: rho0=" << c.rho0 << " b=" << c.b << " hO=" << c.cameraHeight
                              << " el=" << c.elevationDeg << " S=" << c.distance << " F=" << Ff
                              << " ref=" << ref;
    }
    EXPECT_GT(checked, 1000);
    std::printf("fog math: %d cases, worst relative error double %.2e, float %.2e\n", checked, worstDouble,
                worstFloat);
}

TEST(FogMath, NeverNegativeNanOrInfForExtremeValidInputs) {
    for (float rho0 : {0.0f, 1e-30f, 1e-4f, 1.0f, 1e6f})
        for (float b : {0.0f, 1e-9f, 4.5e-3f, 1.0f, 1e3f})
            for (float hA : {-1e10f, -1e5f, -1.0f, 0.0f, 2e4f, 1e10f})
                for (float hB : {-1e10f, 0.0f, 1e-3f, 1e10f})
                    for (float S : {0.0f, 1e-30f, 1.0f, 1e7f, 1e10f, 3e38f}) {
                        const float F = fog::opticalDepth(rho0, b, hA, hB, S);
                        ASSERT_TRUE(std::isfinite(F) && F >= 0.0f)
                            << rho0 << " " << b << " " << hA << " " << hB << " " << S << " -> " << F;
                        for (auto r : {fog::Response::Linear, fog::Response::Exponential}) {
                            const float k = fog::amount(F, r, 1.0f);
                            ASSERT_TRUE(k >= 0.0f && k <= 1.0f);
                        }
                    }
}

TEST(FogMath, HorizontalRayIsDensityTimesDistance) {
    // Δh = 0: F = ρ(h)·S exactly, with no threshold jump as the ray tilts by a hair.
    const double F0 = fog::opticalDepth(1e-3, 4.5e-3, 2.0, 2.0, 1000.0);
    EXPECT_NEAR(F0, 1e-3 * std::exp(-4.5e-3 * 2.0) * 1000.0, 1e-15);
    const double F1 = fog::opticalDepth(1e-3, 4.5e-3, 2.0, 2.0 + 1e-9, 1000.0);
    EXPECT_NEAR(F1 / F0, 1.0, 1e-11);
}

TEST(FogMath, ResponsesFollowTheSeedAndBeerLambert) {
    EXPECT_DOUBLE_EQ(fog::amount(0.4, fog::Response::Linear, 1.0), 0.4);
    EXPECT_DOUBLE_EQ(fog::amount(3.0, fog::Response::Linear, 1.0), 1.0);
    EXPECT_DOUBLE_EQ(fog::amount(0.4, fog::Response::Exponential, 1.0), 1.0 - std::exp(-0.4));
    EXPECT_DOUBLE_EQ(fog::amount(5.0, fog::Response::Exponential, 0.6), 0.6);
    // Beer–Lambert: transmittance of [O,P] = product over [O,Pn] and [Pn,P].
    const double a = fog::opticalDepth(1e-2, 0.05, 3.0, 1.0, 40.0);
    const double b = fog::opticalDepth(1e-2, 0.05, 1.0, 0.5, 10.0);
    const double whole = fog::opticalDepth(1e-2, 0.05, 3.0, 0.5, 50.0);
    EXPECT_NEAR((1 - fog::amount(a, fog::Response::Exponential, 1.0)) *
                    (1 - fog::amount(b, fog::Response::Exponential, 1.0)),
                1 - fog::amount(whole, fog::Response::Exponential, 1.0), 1e-12);
}

// elevationRange against brute force: the elevations of a 201×201 grid of pixel rays and of 2000
// rays along each image edge, over cameras that look up, down, level, straight at the zenith and
// the nadir, rolled, off-axis and orthographic. The range holds every sampled ray and is no wider
// than the samples' own range plus what the sampling can miss.
TEST(FogMath, ElevationRangeHoldsEveryPixelRayAndNoMore) {
    const glm::dvec3 up(0, 0, 1);
    struct View {
        const char* name;
        glm::dmat4 projection, view;
    };
    const auto persp = [](double fovyDeg, double aspect) {
        return glm::perspective(glm::radians(fovyDeg), aspect, 0.5, 3000.0);
    };
    const auto look = [](glm::dvec3 eye, glm::dvec3 at, glm::dvec3 u) { return glm::lookAt(eye, at, u); };
    const glm::dvec3 eye(3, -4, 25);
    const View views[] = {
        {"level", persp(60, 1.5), look(eye, eye + glm::dvec3(0, 1, 0), up)},
        {"down 30", persp(60, 16.0 / 9.0), look(eye, eye + glm::dvec3(0, 1, -0.577), up)},
        {"down 80", persp(60, 1.0), look(eye, eye + glm::dvec3(0.1, 0.17, -1), up)},
        {"up 50", persp(40, 2.0), look(eye, eye + glm::dvec3(1, 0, 1.19), up)},
        {"zenith", persp(60, 1.3), look(eye, eye + glm::dvec3(0, 0, 1), {0, 1, 0})},
        {"nadir", persp(90, 1.0), look(eye, eye + glm::dvec3(0, 0, -1), {1, 0, 0})},
        {"near zenith", persp(60, 1.0), look(eye, eye + glm::dvec3(0.3, 0, 1), {0, 1, 0})},
        {"rolled", persp(70, 1.7),
         look(eye, eye + glm::dvec3(0, 1, 0.2), glm::normalize(glm::dvec3(0.6, 0, 1)))},
        {"wide", persp(150, 3.0), look(eye, eye + glm::dvec3(0, 1, 0.3), up)},
        {"off-axis", glm::frustum(-0.2, 0.9, -0.1, 0.6, 0.5, 3000.0),
         look(eye, eye + glm::dvec3(1, 1, -0.4), up)},
        {"ortho", glm::ortho(-50.0, 50.0, -30.0, 30.0, 0.5, 3000.0),
         look(eye, eye + glm::dvec3(0, 1, -0.5), up)},
    };
    for (const View& v : views) {
        const glm::dmat4 inv = glm::inverse(v.projection * v.view);
        const glm::dvec3 camera = glm::inverse(v.view)[3];
        const glm::dvec2 range = fog::elevationRange(inv, camera, up);
        const auto elevation = [&](double x, double y) {
            const glm::dvec4 p = inv * glm::dvec4(x, y, 1, 1);
            return glm::dot(glm::normalize(glm::dvec3(p) / p.w - camera), up);
        };
        double lo = 1, hi = -1;
        const auto sample = [&](double x, double y) {
            const double e = elevation(x, y);
            lo = std::min(lo, e), hi = std::max(hi, e);
        };
        for (int j = 0; j <= 200; ++j)
            for (int i = 0; i <= 200; ++i)
                sample(-1 + i / 100.0, -1 + j / 100.0);
        for (int i = 0; i <= 2000; ++i) {
            const double t = -1 + i / 1000.0;
            sample(t, -1), sample(t, 1), sample(-1, t), sample(1, t);
        }
        EXPECT_LE(range.x, lo + 1e-12) << v.name;
        EXPECT_GE(range.y, hi - 1e-12) << v.name;
        // A grid step of 1/100 of the half-image misses at most about 2e-4 of elevation near an
        // interior extreme (quadratic there).
        EXPECT_GE(range.x, lo - 2e-4) << v.name;
        EXPECT_LE(range.y, hi + 2e-4) << v.name;
    }
}

// skyAmountRange against brute force: over intervals of elevation anywhere in [−1, 1], every
// sampled k lies in the range, and the range is no wider than the samples' (so the peak where a
// diving ray's end reaches the held density is found, not guessed). The tiny densities keep k off
// its saturation, where the peak shows: k falls on both sides of it.
TEST(FogMath, SkyAmountRangeHoldsEverySampledElevation) {
    const double distance = 1e5;
    int peaksInside = 0;
    for (double rho0 : {1e-30, 1e-26, 1e-4, 1e-2})
        for (double b : {0.0, 1e-4, 0.05})
            for (double h : {-1500.0, -20.0, 0.0, 30.0, 5000.0}) // −1500: below b = 0.05's held level
                for (auto r : {fog::Response::Linear, fog::Response::Exponential})
                    for (glm::dvec2 interval :
                         {glm::dvec2(-1, 1), glm::dvec2(-1, -0.5), glm::dvec2(-0.2, 0.1), glm::dvec2(0.05, 1),
                          glm::dvec2(-0.02, -0.005)}) {
                        const glm::dvec2 range = fog::skyAmountRange(rho0, b, h, interval, distance, r, 0.9);
                        double lo = 2.0, hi = -1.0;
                        for (int i = 0; i <= 20000; ++i) {
                            const double e = interval.x + (interval.y - interval.x) * i / 20000.0;
                            const double k = fog::skyAmount(rho0, b, h, e, distance, r, 0.9);
                            lo = std::min(lo, k), hi = std::max(hi, k);
                        }
                        const double tolerance = 1e-12 + 1e-9 * hi;
                        EXPECT_LE(range.x, lo + tolerance) << rho0 << " " << b << " " << h;
                        EXPECT_GE(range.y, hi - tolerance) << rho0 << " " << b << " " << h;
                        if (b > 0 && h < (fog::kSeriesBelow - fog::kMaxExponent) / b) {
                            // An eye in the held density: no exact range, so the whole one.
                            EXPECT_EQ(range, glm::dvec2(0.0, 1.0)) << rho0 << " " << b << " " << h;
                            continue;
                        }
                        EXPECT_GE(range.x, lo - 1e-3 * (hi - lo) - tolerance) << rho0 << " " << b << " " << h;
                        EXPECT_LE(range.y, hi + 1e-3 * (hi - lo) + tolerance) << rho0 << " " << b << " " << h;
                        const double peak = b > 0 ? (-fog::kMaxExponent / b - h) / distance : 2.0;
                        if (peak > interval.x && peak < interval.y &&
                            hi > 2.0 * fog::skyAmount(rho0, b, h, interval.x, distance, r, 0.9))
                            ++peaksInside;
                    }
    EXPECT_GT(peaksInside, 0) << "no interval showed the held density's peak";
}

#pragma once
/// @file
/// Height fog arithmetic on the CPU, written once for double (reference) and float (the shader's
/// precision). nodes/fog/fog_optical_depth.glsl is the same code in GLSL, line for line.
/// Seed: ../shared/seeds/fog-height-gpu-2020.txt, equations (3)–(7) and F_f.
#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>

namespace sgfx::fog {

/// Density below the reference plane grows as e^(b·depth); past 50 e-folds it is held there, so
/// no product overflows float32 (documented in docs/guide.md).
inline constexpr double kMaxExponent = 50.0;
/// Longer segments are shortened to this (metres): float32 positions mean nothing beyond it.
inline constexpr double kMaxSegment = 1e10;
/// Below this b·|Δh| the difference quotient uses its series: no cancellation, no jump.
inline constexpr double kSeriesBelow = 1e-2;

/// (1 − e^(−y)) / y for y ≥ 0, continuous at 0 (→ 1).
template <class T> T expQuotient(T y) {
    if (y < T(kSeriesBelow)) return T(1) - y * (T(0.5) - y * (T(1) / T(6) - y * (T(1) / T(24) - y / T(120))));
    return (T(1) - std::exp(-y)) / y;
}

/// Relative density e^(−b·h) at height h (seed eq. 3 without ρ0), held at e^50 below −50/b.
template <class T> T densityFactor(T falloff, T height) {
    return std::exp(std::min(-falloff * height, T(kMaxExponent)));
}

/// Optical depth F = ∫ ρ0·e^(−b·h(t)) dt along the segment from A to B, with h the height above
/// the reference plane (seed eq. 5), given the density factors eA = e^(−b·hA), eB = e^(−b·hB).
/// Eq. 6 with its exponents combined, so nothing overflows in float32:
///   F = ρ0·S·(eA − eB) / (b·(hB − hA))
/// and below b·|Δh| = 0.01 the same mean density as max(eA, eB)·(1 − e^(−y))/y by its series (no
/// cancellation, no jump). The mean never falls below the smallest density on the segment (it can
/// only by rounding, or where the density is held). One exp per end: the eye's end is a per-view
/// constant, so the shader pays one exp per fragment.
template <class T>
T opticalDepthFromFactors(T density, T falloff, T heightA, T heightB, T eA, T eB, T length) {
    if (!(density > T(0)) || !(length > T(0))) return T(0);
    const T s = std::min(length, T(kMaxSegment));
    const T y = falloff * std::abs(heightB - heightA);
    const T mean = y < T(kSeriesBelow) ? std::max(eA, eB) * expQuotient(y)
                                       : std::max(std::abs(eA - eB) / y, std::min(eA, eB));
    return density * s * mean;
}

template <class T> T opticalDepth(T density, T falloff, T heightA, T heightB, T length) {
    return opticalDepthFromFactors(density, falloff, heightA, heightB, densityFactor(falloff, heightA),
                                   densityFactor(falloff, heightB), length);
}

enum class Response { Linear, Exponential };

/// Fog amount k from the optical depth: the seed's clamp (eq. 7) or Beer–Lambert 1 − e^(−F).
template <class T> T amount(T F, Response response, T maxOpacity) {
    const T k = response == Response::Linear ? std::clamp(F, T(0), T(1)) : T(1) - std::exp(-F);
    return std::min(k, maxOpacity);
}

/// Height of a point above the reference plane through `referenceHeight` along unit `up`.
template <class T> T heightOf(const glm::vec<3, T>& p, const glm::vec<3, T>& up, T referenceHeight) {
    return glm::dot(p, up) - referenceHeight;
}

/// The lowest and highest elevation dot(d̂, up) among the view directions d = far(x, y) − eye of
/// the image rectangle (x, y) ∈ [−extent, extent]² in NDC, far(x, y) being the far-plane point
/// that `invViewProjection` unprojects there (extent slightly above 1 covers a jittered frame).
/// The directions of the rectangle fill a parallelogram d(u, v) = c0 + u·e1 + v·e2, u, v ∈ [0, 1]
/// (far(x, y) is affine in x and y), so the extremes lie at a corner, at the one stationary point
/// of an edge (the elevation along a segment of directions has one), or are ±1 where the zenith
/// or nadir direction itself is in view. A projection whose far plane does not map the image to
/// a parallelogram (not a perspective or orthographic matrix) gets the whole range [−1, 1].
inline glm::dvec2 elevationRange(const glm::dmat4& invViewProjection, const glm::dvec3& eye,
                                 const glm::dvec3& up, double extent = 1.0) {
    const auto dir = [&](double x, double y) {
        const glm::dvec4 p = invViewProjection * glm::dvec4(x, y, 1.0, 1.0);
        return glm::dvec3(p) / p.w - eye;
    };
    const glm::dvec3 c[4] = {dir(-extent, -extent), dir(extent, -extent), dir(extent, extent),
                             dir(-extent, extent)};
    const glm::dvec3 fourth = c[1] + c[3] - c[0];
    // Rounding leaves a perspective matrix's far quad off by ~1e-16·far/near: far above 1e-6.
    if (!(glm::length(c[2] - fourth) <= 1e-6 * (glm::length(c[2]) + glm::length(fourth)))) return {-1.0, 1.0};
    double lo = 1.0, hi = -1.0;
    const auto take = [&](const glm::dvec3& d) {
        const double e = glm::dot(glm::normalize(d), up);
        lo = std::min(lo, e), hi = std::max(hi, e);
    };
    for (int i = 0; i < 4; ++i) {
        const glm::dvec3 a = c[i], e = c[(i + 1) % 4] - a;
        take(a);
        // d/dt of dot(a + t·e, up) / |a + t·e| vanishes where the numerator below does: linear in t.
        const double az = glm::dot(a, up), ez = glm::dot(e, up), ae = glm::dot(a, e);
        const double den = ez * ae - az * glm::dot(e, e);
        if (den != 0.0) {
            const double t = (az * ae - ez * glm::dot(a, a)) / den;
            if (t > 0.0 && t < 1.0) take(a + t * e);
        }
    }
    // c0 + u·e1 + v·e2 = λ·up: the zenith (λ > 0) or the nadir (λ < 0) inside the parallelogram.
    const glm::dmat3 m(c[1] - c[0], c[3] - c[0], -up);
    if (std::abs(glm::determinant(m)) > 1e-12 * glm::length(c[1] - c[0]) * glm::length(c[3] - c[0])) {
        const glm::dvec3 s = glm::inverse(m) * -c[0];
        if (s.x >= 0.0 && s.x <= 1.0 && s.y >= 0.0 && s.y <= 1.0) {
            if (s.z > 0.0) hi = 1.0;
            if (s.z < 0.0) lo = -1.0;
        }
    }
    return {lo, hi};
}

/// The fog amount of the sky rule FogSky::Distance along a direction of elevation `elevation`
/// from an eye at `eyeHeight` above the reference plane: the segment to the point `skyDistance`
/// away.
inline double skyAmount(double density, double falloff, double eyeHeight, double elevation,
                        double skyDistance, Response response, double maxOpacity) {
    const double F =
        opticalDepth(density, falloff, eyeHeight, eyeHeight + elevation * skyDistance, skyDistance);
    return amount(F, response, maxOpacity);
}

/// The lowest and highest skyAmount over the elevations `elevations` (x ≤ y). k falls as the
/// elevation rises (the ray climbs into thinner fog) down to the elevation whose end point lies
/// where the density is held (height −kMaxExponent/b): below it the end's density stays at its
/// cap while the mean over the longer drop shrinks, so k falls there as the ray dips. k thus has
/// one peak, at that elevation, and its range over an interval is read off the interval's ends and
/// the peak when it lies inside. An eye at or below the held level sees the mean's series branch
/// (b·|Δh| < kSeriesBelow) dip and jump back near the horizontal: no such reading holds, and the
/// range returned is the whole [0, 1].
inline glm::dvec2 skyAmountRange(double density, double falloff, double eyeHeight, glm::dvec2 elevations,
                                 double skyDistance, Response response, double maxOpacity) {
    const auto k = [&](double e) {
        return skyAmount(density, falloff, eyeHeight, e, skyDistance, response, maxOpacity);
    };
    if (falloff > 0.0 && eyeHeight < (kSeriesBelow - kMaxExponent) / falloff) return {0.0, 1.0};
    const double kLow = k(elevations.x), kHigh = k(elevations.y);
    double hi = std::max(kLow, kHigh);
    const double peak = falloff > 0.0 ? (-kMaxExponent / falloff - eyeHeight) / skyDistance : 2.0;
    if (peak > elevations.x && peak < elevations.y) hi = std::max(hi, k(peak));
    return {std::min(kLow, kHigh), hi};
}

} // namespace sgfx::fog

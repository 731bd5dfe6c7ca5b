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

} // namespace sgfx::fog

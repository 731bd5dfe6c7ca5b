#pragma once
/// @file
/// Volume rendering on the CPU (lecture 12, "Volume rendering": Beer–Lambert absorption, emission,
/// scattering, phase functions, raymarching): the closed forms the tests compare pixels with, and
/// the shader's march (volume_march.glsl) step for step.
#include "sgfx/Export.h"
#include <glm/glm.hpp>

#include <cmath>
#include <functional>

namespace sgfx::volume {

inline constexpr double kPi = 3.14159265358979323846;

/// Phase functions p(cos θ), θ between the light's direction of travel and the scattered ray;
/// each integrates to 1 over the sphere.
template <class T> T isotropicPhase(T) {
    return T(1.0 / (4.0 * kPi));
}
template <class T> T rayleighPhase(T cosTheta) {
    return T(3.0 / (16.0 * kPi)) * (T(1) + cosTheta * cosTheta);
}
/// Henyey–Greenstein, g ∈ (−1, 1): g > 0 scatters forwards.
template <class T> T henyeyGreensteinPhase(T cosTheta, T g) {
    const T d = T(1) + g * g - T(2) * g * cosTheta;
    return (T(1) - g * g) / (T(4.0 * kPi) * d * std::sqrt(d));
}

/// (1 − e^(−y)) / y, continuous at y = 0 (→ 1): the emission a homogeneous segment adds per
/// metre of source, relative to its length.
template <class T> T expQuotient(T y) {
    if (y < T(1e-3)) return T(1) - y * (T(0.5) - y * (T(1) / T(6)));
    return (T(1) - std::exp(-y)) / y;
}

/// Closed forms for a homogeneous medium (density 1) along a path of length L.
inline double transmittance(double ka, double L) {
    return std::exp(-ka * L);
}
/// Absorption + emission: (1 − e^(−ka·L))·ke/ka, → ke·L as ka → 0.
inline double emitted(double ka, double ke, double L) {
    return ke * L * expQuotient(ka * L);
}

enum class Integration : std::uint8_t {
    Exact,   ///< default: each step's segment integrated in closed form (exact for a constant step)
    Riemann, ///< the lecture's loop: opt += σ·Δx; L += e^(−opt)·ke·Δx (the sample dims itself)
};

/// What a march along one ray gives: the light it gathered, its transmittance and the steps taken.
struct SGFX_API MarchResult {
    glm::dvec3 radiance{0.0};
    double transmittance = 1.0;
    int steps = 0;
};

/// The shader's front-to-back march over [0, length] in `steps` equal steps sampled at their
/// midpoints. `source(t)` is the radiance per metre the medium sends along the ray at t (emission
/// plus in-scattered light), `extinction(t)` is σ = (ka + ks)·ρ; it stops once the opacity
/// 1 − T exceeds `threshold`.
inline MarchResult march(double length, int steps, const std::function<double(double)>& extinction,
                         const std::function<glm::dvec3(double)>& source, Integration integration,
                         double threshold = 1.0) {
    MarchResult r;
    const double dx = length / steps;
    for (int i = 0; i < steps; ++i) {
        const double t = (i + 0.5) * dx;
        const double sigma = extinction(t);
        const glm::dvec3 s = source(t);
        const double tau = std::exp(-sigma * dx);
        if (integration == Integration::Riemann) {
            r.transmittance *= tau;
            r.radiance += r.transmittance * s * dx;
        } else {
            r.radiance += r.transmittance * s * (dx * expQuotient(sigma * dx));
            r.transmittance *= tau;
        }
        r.steps = i + 1;
        if (1.0 - r.transmittance > threshold) break;
    }
    return r;
}

} // namespace sgfx::volume

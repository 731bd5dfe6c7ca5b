#pragma once
/// @file
/// Volume rendering on the CPU (lecture 12, "Volume rendering": Beer–Lambert absorption, emission,
/// scattering, phase functions, raymarching): the closed forms the tests compare pixels with, and
/// the shader's march (volume_march.glsl) step for step.
#include "sgfx/Export.h"
#include <glm/glm.hpp>

#include <algorithm>
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

// ---------------------------------------------------------------- splatting
// Lecture 12, "Volume rendering: splatting": the medium as particles at grid points drawn as
// camera-facing billboards with a Gaussian texture, colour and opacity from the particle's
// centre, sorted back to front and blended like slices (alpha accounting for the spacing).
//
// Here each kernel is a normalised 3D Gaussian G3(x) = e^(−|x|²/2s²) / ((2π)^(3/2) s³) of weight
// h_x·h_y·h_z (its cell's volume), so Σ_i ρ_i·h³·G3(x − x_i) ≈ ρ(x) (a partition of unity once
// s ≳ 0.6·h). Its integral along any line at distance r from the centre is the 2D Gaussian
// ∫ G3 dt = G2(r) = e^(−r²/2s²) / (2π s²), so a ray's optical depth ∫σ dt is Σ_i σ_i·ℓ_i with
// the footprint length ℓ_i = h³·G2(r_i) (metres). Each splat is then drawn as a homogeneous
// segment of that length: α_i = 1 − e^(−σ_i·ℓ_i), radiance S_i·ℓ_i·(1 − e^(−σ_i ℓ_i))/(σ_i ℓ_i)
// (S the source per metre), composited with the over operator back to front. The transmittance
// Π(1 − α_i) = e^(−Σσ_i ℓ_i) is then the Beer–Lambert one of the reconstructed medium whatever
// the order, and splats that lie at one depth compose exactly as one segment; what remains is
// the Gaussian's blur of the medium (relative error ~ s²·∇²ρ/ρ, so O(h²)) and the depth order
// of overlapping kernels, both vanishing as the spacing shrinks.

/// Kernel standard deviation per unit of (the largest axis's) spacing: at 0.7 the lattice's
/// partition of unity ripples by ~4·e^(−2π²·0.49) ≈ 2.5e-4 across a ray, smaller s blurs less.
inline constexpr double kSplatSigmaPerSpacing = 0.7;
/// Billboard radius in standard deviations; the footprint is renormalised to the disc.
inline constexpr double kSplatRadiusSigmas = 3.0;
/// The most kernels a volume may have.
inline constexpr long long kMaxSplats = 1LL << 22;

/// The lattice of kernels: `count` per axis, their `spacing` (m) and standard deviation `sigma`.
struct SplatLattice {
    glm::ivec3 count{1};
    glm::dvec3 spacing{1.0};
    double sigma = 1.0;
    long long total() const { return (long long)count.x * count.y * count.z; }
    /// Kernel (i, j, k)'s centre, box frame (metres, centred on the box).
    glm::dvec3 centre(glm::ivec3 i, glm::dvec3 size) const {
        return (glm::dvec3(i) + 0.5) * spacing - 0.5 * size;
    }
};

inline SplatLattice splatLattice(glm::dvec3 size, double spacing) {
    SplatLattice l;
    for (int a = 0; a < 3; ++a) {
        const double n = std::max(1.0, std::round(size[a] / spacing));
        l.count[a] = n > 1048576.0 ? 1048576 : int(n); // the total stays within a long long
        l.spacing[a] = size[a] / double(l.count[a]);
    }
    l.sigma = kSplatSigmaPerSpacing * std::max({l.spacing.x, l.spacing.y, l.spacing.z});
    return l;
}

/// The footprint length ℓ = h³·G2(r) of a kernel whose ray passes at distance r (0 beyond the
/// billboard's radius; the truncated disc renormalised so the kernel keeps its mass).
inline double splatFootprint(double r, const SplatLattice& l) {
    const double R = kSplatRadiusSigmas * l.sigma;
    if (r >= R) return 0.0;
    const double s2 = l.sigma * l.sigma;
    const double g2 = std::exp(-r * r / (2.0 * s2)) / (2.0 * kPi * s2);
    const double disc = 1.0 - std::exp(-0.5 * kSplatRadiusSigmas * kSplatRadiusSigmas);
    return l.spacing.x * l.spacing.y * l.spacing.z * g2 / disc;
}

} // namespace sgfx::volume

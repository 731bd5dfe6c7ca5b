#pragma once
// An independent double-precision reference for the sky's single scattering (tests only). It shares
// nothing with SkyMath.h or the shaders but the physical inputs (sky::Atmosphere): its own
// ray–sphere geometry, composite Simpson quadrature with 1,024 intervals along the view ray and,
// at each of its nodes, another 1,024 along the ray to the sun; the phase functions written out from
// their formulas. The model it integrates is the sky's: single scattering, sun light attenuated from
// the top of the atmosphere to the scattering point and on to the eye, no light where the planet
// hides the sun, no ground (a view ray below the horizon sees the horizon at its azimuth).
//
// Its own error is far below the tolerances it is used with. Simpson's rule errs by
// (b − a)·Δ⁴/180·max|f⁗|; for e^(−t/H) that is a relative (Δ/H)⁴/180, the largest Δ/H being the
// Mie layer's along a vertical 60 km ray, 58.6 m / 1,200 m: 3e-8 (the zenith transmittance matches
// the closed form to 1e-9). The one non-smooth integrand, the view ray's at the edge of the
// planet's shadow, jumps by at most the transmittance of a sun ray grazing the ground (< 3e-4 in
// red) and costs at most that times one interval. Measured: doubling the intervals changes the
// radiance by at most 5e-5 of itself (where above 1e-6) over the tests' sun and view directions.
#include <sgfx/nodes/sky/SkyMath.h> // sky::Atmosphere: the inputs only

#include <glm/glm.hpp>

#include <cmath>

namespace sgfx::test::skyref {

using glm::dvec3;
inline constexpr double kPi = 3.14159265358979323846;
inline constexpr int kIntervals = 1024; // Simpson intervals, view ray and sun ray alike (even)

struct Medium {
    double planet, top; // radii, m
    dvec3 rayleigh;     // β_R at sea level, per m
    double rayleighHeight;
    double mie; // β_M (scattering) at sea level, per m
    double mieHeight;
    double g;             // Henyey–Greenstein asymmetry
    double mieExtinction; // extinction / scattering
};

inline Medium medium(const sky::Atmosphere& a) {
    return {a.planetRadius, a.atmosphereRadius, dvec3(a.rayleigh), a.rayleighHeight, a.mie, a.mieHeight,
            a.mieG,         a.mieExtinction};
}

// Sea-level-relative densities (Rayleigh, Mie) at the point p (planet centre at the origin).
inline glm::dvec2 density(const Medium& m, const dvec3& p) {
    const double h = glm::length(p) - m.planet;
    return {std::exp(-h / m.rayleighHeight), std::exp(-h / m.mieHeight)};
}

// Distance from p (inside the sphere of radius r about the origin) along unit u to its surface.
inline double exitDistance(const dvec3& p, const dvec3& u, double r) {
    const double along = glm::dot(p, u);
    const double pr = glm::length(p);
    const double inside = (r - pr) * (r + pr); // r² − |p|², written so it keeps its digits
    return -along + std::sqrt(along * along + inside);
}

// Whether the half-line p + s·u, s > 0, from p outside the planet, enters it.
inline bool planetInTheWay(const Medium& m, const dvec3& p, const dvec3& u) {
    const double along = glm::dot(p, u);
    if (along >= 0.0) return false;      // heading away from the centre
    const dvec3 closest = p - along * u; // the line's point nearest the centre
    return glm::dot(closest, closest) < m.planet * m.planet;
}

// Composite Simpson weight of node k of n intervals of width d.
inline double simpsonWeight(int k, int n, double d) {
    return d / 3.0 * (k == 0 || k == n ? 1.0 : (k % 2 == 1 ? 4.0 : 2.0));
}

// Column densities (Rayleigh, Mie), in sea-level metres, from p along unit u to the top.
inline glm::dvec2 columnToTop(const Medium& m, const dvec3& p, const dvec3& u) {
    const double d = exitDistance(p, u, m.top) / kIntervals;
    glm::dvec2 sum(0.0);
    for (int k = 0; k <= kIntervals; ++k)
        sum += simpsonWeight(k, kIntervals, d) * density(m, p + (k * d) * u);
    return sum;
}

// Optical depth per channel of the column densities `c`.
inline dvec3 opticalDepth(const Medium& m, const glm::dvec2& c) {
    return m.rayleigh * c.x + dvec3(m.mie * m.mieExtinction * c.y);
}

inline dvec3 expNeg(const dvec3& t) {
    return {std::exp(-t.x), std::exp(-t.y), std::exp(-t.z)};
}

// Transmittance from the eye at `altitude` m towards unit `sun` (0 when the planet is in the way).
inline dvec3 sunTransmittance(const Medium& m, dvec3 sun, double altitude) {
    const dvec3 eye(0.0, 0.0, m.planet + altitude);
    sun = glm::normalize(sun);
    if (planetInTheWay(m, eye, sun)) return dvec3(0.0);
    return expNeg(opticalDepth(m, columnToTop(m, eye, sun)));
}

// The closed form for a vertical ray: ∫ e^(−h/H) dh from h0 to the top is H·(e^(−h0/H) − e^(−top/H)).
inline dvec3 zenithTransmittance(const Medium& m, double altitude) {
    const double top = m.top - m.planet;
    const double hr = m.rayleighHeight, hm = m.mieHeight;
    const double columnR = hr * (std::exp(-altitude / hr) - std::exp(-top / hr));
    const double columnM = hm * (std::exp(-altitude / hm) - std::exp(-top / hm));
    return expNeg(m.rayleigh * columnR + dvec3(m.mie * m.mieExtinction * columnM));
}

inline double rayleighPhase(double mu) {
    return 3.0 / (16.0 * kPi) * (1.0 + mu * mu);
}
inline double henyeyGreenstein(double mu, double g) {
    return (1.0 - g * g) / (4.0 * kPi * std::pow(1.0 + g * g - 2.0 * g * mu, 1.5));
}

// Single-scattered radiance reaching the eye at `altitude` m from direction `view` (z up), the sun
// towards `sun` with irradiance `intensity`; the sun's disc is not included.
inline dvec3 radiance(const Medium& m, dvec3 view, dvec3 sun, double intensity, double altitude) {
    view = glm::normalize(view);
    sun = glm::normalize(sun);
    if (view.z < 0.0) view = glm::normalize(dvec3(view.x, view.y, 0.0)); // the horizon below it
    const dvec3 eye(0.0, 0.0, m.planet + altitude);
    const double length = planetInTheWay(m, eye, view) ? 0.0 : exitDistance(eye, view, m.top);
    const double d = length / kIntervals;
    glm::dvec2 column(0.0);   // from the eye to the node, by Simpson on each interval
    glm::dvec2 previous(0.0); // the density at the previous node
    dvec3 sumR(0.0), sumM(0.0);
    for (int k = 0; k <= kIntervals; ++k) {
        const dvec3 p = eye + (k * d) * view;
        const glm::dvec2 rho = density(m, p);
        if (k > 0) column += d / 6.0 * (previous + 4.0 * density(m, eye + ((k - 0.5) * d) * view) + rho);
        previous = rho;
        if (planetInTheWay(m, p, sun)) continue; // in the planet's shadow
        const dvec3 t = expNeg(opticalDepth(m, column + columnToTop(m, p, sun)));
        const double w = simpsonWeight(k, kIntervals, d);
        sumR += w * rho.x * t;
        sumM += w * rho.y * t;
    }
    const double mu = glm::dot(view, sun);
    return intensity * (sumR * m.rayleigh * rayleighPhase(mu) + sumM * m.mie * henyeyGreenstein(mu, m.g));
}

} // namespace sgfx::test::skyref

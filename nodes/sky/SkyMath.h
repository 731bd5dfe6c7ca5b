#pragma once
/// @file
/// Single scattering in a spherical atmosphere (lecture 12: Rayleigh and Mie scattering, the
/// Henyey–Greenstein phase, the nested light march; Earth's defaults after Nishita et al. 1993):
/// the CPU mirror of sky_scattering.glsl, for the tests and for the horizon colour a FogNode takes.
#include "volume/VolumeMath.h"

#include <glm/glm.hpp>

#include <cmath>

namespace sgfx::sky {

/// A spherical atmosphere: radii, scale heights and scattering coefficients (metres).
struct Atmosphere {
    float planetRadius = 6360e3f;                    ///< m
    float atmosphereRadius = 6420e3f;                ///< m
    glm::vec3 rayleigh{5.8e-6f, 13.5e-6f, 33.1e-6f}; ///< β_R at sea level, per metre (R, G, B)
    float rayleighHeight = 7994.0f;                  ///< scale height H_R, m
    float mie = 21e-6f;                              ///< β_M at sea level, per metre
    float mieHeight = 1200.0f;                       ///< H_M, m
    float mieG = 0.76f;                              ///< Henyey–Greenstein g of the haze
    float mieExtinction = 1.1f;                      ///< extinction / scattering of the haze
};

/// Distances along o + t·d (|d| = 1) to a sphere of radius r at the origin: (t0, t1), or (−1, −1).
inline glm::vec2 sphereHit(glm::vec3 o, glm::vec3 d, float r) {
    const float b = glm::dot(o, d);
    const float c = glm::dot(o, o) - r * r;
    const float disc = b * b - c;
    if (disc < 0.0f) return {-1.0f, -1.0f};
    const float s = std::sqrt(disc);
    return {-b - s, -b + s};
}

/// The direction whose sky a view ray `dir` (normalised) shows. There is no ground model: below the
/// horizon the sky shows the horizon at the ray's azimuth, and straight down, where that azimuth
/// is undefined, the horizon towards +x.
inline glm::vec3 skyDirection(glm::vec3 dir) {
    if (dir.z >= 0.0f) return dir;
    const float level = std::sqrt(dir.x * dir.x + dir.y * dir.y);
    return level > 1e-6f ? glm::vec3(dir.x / level, dir.y / level, 0.0f) : glm::vec3(1.0f, 0.0f, 0.0f);
}

/// Radiance of the sky seen from `altitude` metres along `dir` (world, z up, normalised), with the
/// sun towards `sun` (normalised) of irradiance `sunIntensity`; `steps` and `lightSteps` midpoint
/// steps. The sun's disc is left out (the shader adds it).
inline glm::vec3 skyRadiance(const Atmosphere& a, glm::vec3 dir, glm::vec3 sun, float sunIntensity,
                             float altitude, int steps = 16, int lightSteps = 8) {
    dir = skyDirection(glm::normalize(dir));
    const glm::vec3 o(0.0f, 0.0f, a.planetRadius + std::max(altitude, 1.0f));
    float tEnd = sphereHit(o, dir, a.atmosphereRadius).y;
    const glm::vec2 ground = sphereHit(o, dir, a.planetRadius);
    if (ground.x > 0.0f) tEnd = ground.x;
    if (!(tEnd > 0.0f)) return glm::vec3(0.0f);
    const float ds = tEnd / float(steps);
    float odR = 0.0f, odM = 0.0f;
    glm::vec3 sumR(0.0f), sumM(0.0f);
    for (int i = 0; i < steps; ++i) {
        const glm::vec3 p = o + dir * ((float(i) + 0.5f) * ds);
        const float h = glm::length(p) - a.planetRadius;
        const float hr = std::exp(-h / a.rayleighHeight) * ds;
        const float hm = std::exp(-h / a.mieHeight) * ds;
        odR += hr;
        odM += hm;
        if (sphereHit(p, sun, a.planetRadius).x > 0.0f) continue; // in the planet's shadow
        const float tl = sphereHit(p, sun, a.atmosphereRadius).y;
        const float dl = tl / float(lightSteps);
        float odRl = 0.0f, odMl = 0.0f;
        for (int j = 0; j < lightSteps; ++j) {
            const glm::vec3 q = p + sun * ((float(j) + 0.5f) * dl);
            const float hq = glm::length(q) - a.planetRadius;
            odRl += std::exp(-hq / a.rayleighHeight) * dl;
            odMl += std::exp(-hq / a.mieHeight) * dl;
        }
        const glm::vec3 tau = a.rayleigh * (odR + odRl) + glm::vec3(a.mie * a.mieExtinction * (odM + odMl));
        const glm::vec3 att(std::exp(-tau.x), std::exp(-tau.y), std::exp(-tau.z));
        sumR += att * hr;
        sumM += att * hm;
    }
    const float mu = glm::dot(dir, sun);
    return sunIntensity * (sumR * a.rayleigh * volume::rayleighPhase(mu) +
                           sumM * a.mie * volume::henyeyGreensteinPhase(mu, a.mieG));
}

/// What reaches the eye straight from the sun (the disc's colour): e^(−optical depth) along `sun`.
inline glm::vec3 sunTransmittance(const Atmosphere& a, glm::vec3 sun, float altitude, int steps = 16) {
    const glm::vec3 o(0.0f, 0.0f, a.planetRadius + std::max(altitude, 1.0f));
    if (sphereHit(o, sun, a.planetRadius).x > 0.0f) return glm::vec3(0.0f);
    const float ds = sphereHit(o, sun, a.atmosphereRadius).y / float(steps);
    float odR = 0.0f, odM = 0.0f;
    for (int i = 0; i < steps; ++i) {
        const float h = glm::length(o + sun * ((float(i) + 0.5f) * ds)) - a.planetRadius;
        odR += std::exp(-h / a.rayleighHeight) * ds;
        odM += std::exp(-h / a.mieHeight) * ds;
    }
    const glm::vec3 tau = a.rayleigh * odR + glm::vec3(a.mie * a.mieExtinction * odM);
    return {std::exp(-tau.x), std::exp(-tau.y), std::exp(-tau.z)};
}

/// The sky-view table's coordinates (after Hillaire 2020, which lecture 12 cites): azimuth across,
/// the square root of the elevation up, so texels crowd towards the horizon where colour changes.
inline glm::vec2 lutCoordinates(glm::vec3 dir) {
    const float az = std::atan2(dir.y, dir.x);
    const float el = std::asin(std::clamp(dir.z, 0.0f, 1.0f));
    return {az / (2.0f * float(volume::kPi)) + 0.5f, std::sqrt(el / (0.5f * float(volume::kPi)))};
}

/// Direction towards the sun at local solar time `hours` (0..24), latitude and day of the year
/// (world: x east, y north, z up).
inline glm::vec3 sunDirection(float hours, float latitudeDegrees = 45.0f, int dayOfYear = 172) {
    const float decl = glm::radians(23.44f) * std::sin(glm::radians(360.0f / 365.0f * float(dayOfYear - 81)));
    const float lat = glm::radians(latitudeDegrees);
    const float hourAngle = glm::radians(15.0f * (hours - 12.0f));
    const float sinEl = std::sin(lat) * std::sin(decl) + std::cos(lat) * std::cos(decl) * std::cos(hourAngle);
    const float el = std::asin(std::clamp(sinEl, -1.0f, 1.0f));
    // Azimuth from north, clockwise (east positive).
    const float az =
        std::atan2(-std::sin(hourAngle) * std::cos(decl),
                   std::cos(lat) * std::sin(decl) - std::sin(lat) * std::cos(decl) * std::cos(hourAngle));
    return {std::cos(el) * std::sin(az), std::cos(el) * std::cos(az), std::sin(el)};
}

} // namespace sgfx::sky

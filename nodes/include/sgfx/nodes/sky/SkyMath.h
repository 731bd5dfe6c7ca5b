#pragma once
/// @file
/// Single scattering in a spherical atmosphere (lecture 12: Rayleigh and Mie scattering, the
/// Henyey–Greenstein phase, the nested light march; Earth's defaults after Nishita et al. 1993):
/// the CPU mirror of sky_scattering.glsl, for the tests and for the horizon colour a FogNode takes.
#include "sgfx/Export.h"
#include <sgfx/nodes/volume/VolumeMath.h>

#include <glm/glm.hpp>

#include <cmath>

namespace sgfx::sky {

/// A spherical atmosphere: radii, scale heights and scattering coefficients (metres).
struct SGFX_API Atmosphere {
    float planetRadius = 6360e3f;                    ///< m
    float atmosphereRadius = 6420e3f;                ///< m
    glm::vec3 rayleigh{5.8e-6f, 13.5e-6f, 33.1e-6f}; ///< β_R at sea level, per metre (R, G, B)
    float rayleighHeight = 7994.0f;                  ///< scale height H_R, m
    float mie = 21e-6f;                              ///< β_M at sea level, per metre
    float mieHeight = 1200.0f;                       ///< H_M, m
    float mieG = 0.76f;                              ///< Henyey–Greenstein g of the haze
    float mieExtinction = 1.1f;                      ///< extinction / scattering of the haze
    bool operator==(const Atmosphere&) const = default;
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

/// Step i of n of a march along a ray of `length`: (t of its sample, its length, the distance
/// from its start to the sample). The steps crowd towards the ray's start, where the air is
/// densest and an upward ray's density falls fastest: t = length·u² with u at the midpoints of n
/// equal parts of [0, 1] (the midpoint rule in u), so step i spans length·[i², (i + 1)²]/n².
inline glm::vec3 marchStep(float length, int i, int n) {
    const float scale = length / (float(n) * float(n));
    const float k = float(i);
    return {scale * (k + 0.5f) * (k + 0.5f), scale * (2.0f * k + 1.0f), scale * (k + 0.25f)};
}

/// Radiance of the sky seen from `altitude` metres along `dir` (world, z up, normalised), with the
/// sun towards `sun` (normalised) of irradiance `sunIntensity`; `steps` along the view ray and
/// `lightSteps` towards the sun (marchStep). The sun's disc is left out (the shader adds it).
inline glm::vec3 skyRadiance(const Atmosphere& a, glm::vec3 dir, glm::vec3 sun, float sunIntensity,
                             float altitude, int steps = 16, int lightSteps = 8) {
    dir = skyDirection(glm::normalize(dir));
    const glm::vec3 o(0.0f, 0.0f, a.planetRadius + std::max(altitude, 1.0f));
    float tEnd = sphereHit(o, dir, a.atmosphereRadius).y;
    const glm::vec2 ground = sphereHit(o, dir, a.planetRadius);
    if (ground.x > 0.0f) tEnd = ground.x;
    if (!(tEnd > 0.0f)) return glm::vec3(0.0f);
    float odR = 0.0f, odM = 0.0f; // column densities from the eye to the current step's start
    glm::vec3 sumR(0.0f), sumM(0.0f);
    for (int i = 0; i < steps; ++i) {
        const glm::vec3 s = marchStep(tEnd, i, steps);
        const glm::vec3 p = o + dir * s.x;
        const float h = glm::length(p) - a.planetRadius;
        const float rhoR = std::exp(-h / a.rayleighHeight), rhoM = std::exp(-h / a.mieHeight);
        // From the eye to the sample: the steps before it and its own start.
        const float toR = odR + rhoR * s.z, toM = odM + rhoM * s.z;
        odR += rhoR * s.y;
        odM += rhoM * s.y;
        if (sphereHit(p, sun, a.planetRadius).x > 0.0f) continue; // in the planet's shadow
        const float tl = sphereHit(p, sun, a.atmosphereRadius).y;
        float odRl = 0.0f, odMl = 0.0f;
        for (int j = 0; j < lightSteps; ++j) {
            const glm::vec3 l = marchStep(tl, j, lightSteps);
            const float hq = glm::length(p + sun * l.x) - a.planetRadius;
            odRl += std::exp(-hq / a.rayleighHeight) * l.y;
            odMl += std::exp(-hq / a.mieHeight) * l.y;
        }
        const glm::vec3 tau = a.rayleigh * (toR + odRl) + glm::vec3(a.mie * a.mieExtinction * (toM + odMl));
        const glm::vec3 att(std::exp(-tau.x), std::exp(-tau.y), std::exp(-tau.z));
        sumR += att * (rhoR * s.y);
        sumM += att * (rhoM * s.y);
    }
    const float mu = glm::dot(dir, sun);
    return sunIntensity * (sumR * a.rayleigh * volume::rayleighPhase(mu) +
                           sumM * a.mie * volume::henyeyGreensteinPhase(mu, a.mieG));
}

/// What reaches the eye straight from the sun (the disc's colour): e^(−optical depth) along `sun`.
inline glm::vec3 sunTransmittance(const Atmosphere& a, glm::vec3 sun, float altitude, int steps = 16) {
    const glm::vec3 o(0.0f, 0.0f, a.planetRadius + std::max(altitude, 1.0f));
    if (sphereHit(o, sun, a.planetRadius).x > 0.0f) return glm::vec3(0.0f);
    const float length = sphereHit(o, sun, a.atmosphereRadius).y;
    float odR = 0.0f, odM = 0.0f;
    for (int i = 0; i < steps; ++i) {
        const glm::vec3 s = marchStep(length, i, steps);
        const float h = glm::length(o + sun * s.x) - a.planetRadius;
        odR += std::exp(-h / a.rayleighHeight) * s.y;
        odM += std::exp(-h / a.mieHeight) * s.y;
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

// Single scattering in a spherical atmosphere: Rayleigh (phase 3/(16π)·(1 + μ²)) and Mie haze
// (Henyey–Greenstein), a march along the view ray with a nested march towards the sun for its
// optical depth (lecture 12). SkyMath.h is the CPU mirror.
uniform vec3 u_sunDirection; // towards the sun, world
uniform float u_sunIntensity;
uniform float u_altitude;    // the eye's height above sea level, m
uniform float u_planetRadius;
uniform float u_atmosphereRadius;
uniform vec3 u_rayleigh;
uniform float u_rayleighHeight;
uniform float u_mie;
uniform float u_mieHeight;
uniform float u_mieG;
uniform float u_mieExtinction;
uniform int u_steps;
uniform int u_lightSteps;

vec2 sphereHit(vec3 o, vec3 d, float r) {
    float b = dot(o, d);
    float c = dot(o, o) - r * r;
    float disc = b * b - c;
    if (disc < 0.0) return vec2(-1.0);
    float s = sqrt(disc);
    return vec2(-b - s, -b + s);
}

// The direction whose sky the view ray `dir` (normalised) shows (SkyMath.h: skyDirection): no
// ground model, so below the horizon the horizon at the ray's azimuth; straight down, where that
// is undefined, the horizon towards +x (normalising vec3(dir.xy, 0) there would give NaN).
vec3 skyDirection(vec3 dir) {
    if (dir.z >= 0.0) return dir;
    float level = length(dir.xy);
    return level > 1e-6 ? vec3(dir.xy / level, 0.0) : vec3(1.0, 0.0, 0.0);
}

// Step i of n along a ray of `length` (SkyMath.h: marchStep): (t of its sample, its length, the
// distance from its start to the sample); t = length·u², u at the midpoints of n parts of [0, 1],
// so the steps crowd towards the ray's start, where the air is densest.
vec3 marchStep(float length, int i, int n) {
    float scale = length / (float(n) * float(n));
    float k = float(i);
    return vec3(scale * (k + 0.5) * (k + 0.5), scale * (2.0 * k + 1.0), scale * (k + 0.25));
}

// Returns the in-scattered radiance; `sunTransmittance` is what reaches the eye straight from
// the sun along `dir` (0 when the ground is in the way).
vec3 skyRadiance(vec3 dir, out vec3 sunTransmittance) {
    dir = skyDirection(dir);
    vec3 o = vec3(0.0, 0.0, u_planetRadius + max(u_altitude, 1.0));
    float tEnd = sphereHit(o, dir, u_atmosphereRadius).y;
    vec2 ground = sphereHit(o, dir, u_planetRadius);
    bool hitsGround = ground.x > 0.0;
    if (hitsGround) tEnd = ground.x;
    sunTransmittance = vec3(0.0);
    if (!(tEnd > 0.0)) return vec3(0.0);
    float odR = 0.0, odM = 0.0; // column densities from the eye to the current step's start
    vec3 sumR = vec3(0.0), sumM = vec3(0.0);
    for (int i = 0; i < u_steps; ++i) {
        vec3 s = marchStep(tEnd, i, u_steps);
        vec3 p = o + dir * s.x;
        float h = length(p) - u_planetRadius;
        float rhoR = exp(-h / u_rayleighHeight), rhoM = exp(-h / u_mieHeight);
        // From the eye to the sample: the steps before it and its own start.
        float toR = odR + rhoR * s.z, toM = odM + rhoM * s.z;
        odR += rhoR * s.y;
        odM += rhoM * s.y;
        if (sphereHit(p, u_sunDirection, u_planetRadius).x > 0.0) continue; // the planet's shadow
        float tl = sphereHit(p, u_sunDirection, u_atmosphereRadius).y;
        float odRl = 0.0, odMl = 0.0;
        for (int j = 0; j < u_lightSteps; ++j) {
            vec3 l = marchStep(tl, j, u_lightSteps);
            float hq = length(p + u_sunDirection * l.x) - u_planetRadius;
            odRl += exp(-hq / u_rayleighHeight) * l.y;
            odMl += exp(-hq / u_mieHeight) * l.y;
        }
        vec3 tau = u_rayleigh * (toR + odRl) + vec3(u_mie * u_mieExtinction * (toM + odMl));
        vec3 att = exp(-tau);
        sumR += att * (rhoR * s.y);
        sumM += att * (rhoM * s.y);
    }
    float mu = dot(dir, u_sunDirection);
    float phaseR = 0.05968310365946075 * (1.0 + mu * mu);
    float d = 1.0 + u_mieG * u_mieG - 2.0 * u_mieG * mu;
    float phaseM = 0.07957747154594767 * (1.0 - u_mieG * u_mieG) / (d * sqrt(d));
    if (!hitsGround) sunTransmittance = exp(-(u_rayleigh * odR + vec3(u_mie * u_mieExtinction * odM)));
    return u_sunIntensity * (sumR * u_rayleigh * phaseR + sumM * u_mie * phaseM);
}

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
    float ds = tEnd / float(u_steps);
    float odR = 0.0, odM = 0.0;
    vec3 sumR = vec3(0.0), sumM = vec3(0.0);
    for (int i = 0; i < u_steps; ++i) {
        vec3 p = o + dir * ((float(i) + 0.5) * ds);
        float h = length(p) - u_planetRadius;
        float hr = exp(-h / u_rayleighHeight) * ds;
        float hm = exp(-h / u_mieHeight) * ds;
        odR += hr;
        odM += hm;
        if (sphereHit(p, u_sunDirection, u_planetRadius).x > 0.0) continue; // the planet's shadow
        float tl = sphereHit(p, u_sunDirection, u_atmosphereRadius).y;
        float dl = tl / float(u_lightSteps);
        float odRl = 0.0, odMl = 0.0;
        for (int j = 0; j < u_lightSteps; ++j) {
            vec3 q = p + u_sunDirection * ((float(j) + 0.5) * dl);
            float hq = length(q) - u_planetRadius;
            odRl += exp(-hq / u_rayleighHeight) * dl;
            odMl += exp(-hq / u_mieHeight) * dl;
        }
        vec3 tau = u_rayleigh * (odR + odRl) + vec3(u_mie * u_mieExtinction * (odM + odMl));
        vec3 att = exp(-tau);
        sumR += att * hr;
        sumM += att * hm;
    }
    float mu = dot(dir, u_sunDirection);
    float phaseR = 0.05968310365946075 * (1.0 + mu * mu);
    float d = 1.0 + u_mieG * u_mieG - 2.0 * u_mieG * mu;
    float phaseM = 0.07957747154594767 * (1.0 - u_mieG * u_mieG) / (d * sqrt(d));
    if (!hitsGround) sunTransmittance = exp(-(u_rayleigh * odR + vec3(u_mie * u_mieExtinction * odM)));
    return u_sunIntensity * (sumR * u_rayleigh * phaseR + sumM * u_mie * phaseM);
}

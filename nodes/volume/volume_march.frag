#version 450 core
// Raymarching a participating medium in a box (lecture 12, "Volume rendering: raymarching"):
// the ray from the eye through this back-face fragment, clipped to the box (t_min clamped to 0)
// and to the opaque scene's depth, N steps sampled at their midpoints, front to back, with
// absorption, emission and single scattering towards a directional light (an inner march of M
// steps for the light's optical depth), early termination. Output is premultiplied: radiance
// and opacity 1 − T, so the background shows through by the transmittance T.
#include "volume_phase.glsl"
#include "volume_density.glsl"

in vec3 v_worldPos;
layout(location = 0) out vec4 sgfx_fragColor;
#ifdef SGFX_VOLUME_HALF
layout(location = 1) out vec4 sgfx_volumeDepth; // where this ray stopped: linear view depth
#endif

uniform mat4 u_worldToBox; // world → box frame (metres, centred)
uniform vec3 u_boxSize;
uniform float u_absorption; // k_a per metre at density 1
uniform float u_scattering; // k_s per metre at density 1
uniform vec3 u_emission;    // k_e per metre at density 1
uniform vec3 u_lightColor;
uniform float u_ambient; // scales the scene's ambient light scattered by the medium
uniform vec3 u_lightDirection; // world, the direction the light travels (normalised)
uniform int u_steps;           // N (fixed), or the most when u_stepLength > 0
uniform float u_stepLength;    // > 0: N from the segment length
uniform int u_lightSteps;      // M
uniform float u_threshold;     // early termination: stop once 1 − T exceeds it
uniform int u_integration;     // 0 exact per step, 1 the lecture's sum
uniform int u_jitter;          // start each pixel's samples at a random offset (noise for banding)
uniform int u_skip;            // empty-space skipping with the coarse maximum grid
uniform int u_countSamples;    // diagnostics: output the number of density samples taken
uniform ivec3 u_maxGridSize;
uniform int u_useTransfer;
uniform int u_pixelScale;      // 2 when marching at half resolution
uniform sampler2D u_sceneDepth; // the scene depth, on a unit the renderer picks
layout(binding = SGFX_VOLUME_DENSITY_UNIT + 2) uniform sampler2D u_transfer; // emission colour by ρ
uniform int u_hasSceneDepth;

// @sgfx:fragment_decl

// Ray (o + t·d, box frame, t in world metres) against the box: [t_near, t_far].
vec2 boxInterval(vec3 o, vec3 d, vec3 lo, vec3 hi) {
    vec3 inv = vec3(abs(d.x) > 1e-12 ? 1.0 / d.x : 1e30, abs(d.y) > 1e-12 ? 1.0 / d.y : 1e30,
                    abs(d.z) > 1e-12 ? 1.0 / d.z : 1e30);
    vec3 t0 = (lo - o) * inv, t1 = (hi - o) * inv;
    vec3 tn = min(t0, t1), tf = max(t0, t1);
    return vec2(max(max(tn.x, tn.y), tn.z), min(min(tf.x, tf.y), tf.z));
}

// (1 − e^(−y)) / y, → 1 at 0 (VolumeMath.h: expQuotient).
float expQuotient(float y) {
    return y < 1e-3 ? 1.0 - y * (0.5 - y * (1.0 / 6.0)) : (1.0 - exp(-y)) / y;
}

float pixelHash(vec2 p) {
    return fract(sin(dot(p, vec2(12.9898, 78.233))) * 43758.5453);
}

void main() {
    vec3 eye = sgfx_eye.xyz;
    vec3 dirW = normalize(v_worldPos - eye);
    vec3 o = (u_worldToBox * vec4(eye, 1.0)).xyz;
    vec3 d = mat3(u_worldToBox) * dirW;
    vec3 h = 0.5 * u_boxSize;
    vec2 seg = boxInterval(o, d, -h, h);
    float tmin = max(seg.x, 0.0); // points behind the camera are not rendered
    float tmax = seg.y;
    // The opaque scene cuts the ray (a wall inside the smoke).
    if (u_hasSceneDepth != 0) {
        ivec2 px = ivec2(gl_FragCoord.xy) * u_pixelScale;
        float z = texelFetch(u_sceneDepth, px, 0).r;
        if (u_pixelScale > 1) {
            // The farthest of the block's depths: the upsampling keeps what lies beyond a nearer
            // surface from bleeding onto it.
            ivec2 last = textureSize(u_sceneDepth, 0) - 1;
            z = max(z, texelFetch(u_sceneDepth, min(px + ivec2(1, 0), last), 0).r);
            z = max(z, texelFetch(u_sceneDepth, min(px + ivec2(0, 1), last), 0).r);
            z = max(z, texelFetch(u_sceneDepth, min(px + ivec2(1, 1), last), 0).r);
        }
        if (z < 1.0) {
            vec2 ndcXY = (vec2(px) + 0.5 * float(u_pixelScale)) / sgfx_viewport.zw * 2.0 - 1.0;
            vec4 w = sgfx_invViewProjection * vec4(ndcXY, z * 2.0 - 1.0, 1.0);
            tmax = min(tmax, distance(eye, w.xyz / w.w));
        }
    }
    if (!(tmax > tmin)) discard;

    float len = tmax - tmin;
    int n = u_stepLength > 0.0 ? clamp(int(ceil(len / u_stepLength)), 1, u_steps) : u_steps;
    float dt = len / float(n);
    float offset = u_jitter != 0 ? pixelHash(gl_FragCoord.xy) : 0.5;
    float extinctionPerRho = u_absorption + u_scattering;
    float cosTheta = dot(u_lightDirection, -dirW);
    float phase = volumePhase(cosTheta);
    vec3 dl = mat3(u_worldToBox) * -u_lightDirection; // towards the light, box frame
    vec3 radiance = vec3(0.0);
    float T = 1.0;
    int samples = 0;
    for (int i = 0; i < n; ++i) {
        float t = tmin + (float(i) + offset) * dt;
        vec3 p = o + t * d;
        vec3 uvw = p / u_boxSize + 0.5;
        if (u_skip != 0) {
            // Empty-space skipping: a coarse cell whose maximum is 0 is jumped over whole.
            ivec3 cell = clamp(ivec3(floor(uvw * vec3(u_maxGridSize))), ivec3(0), u_maxGridSize - 1);
            if (texelFetch(u_densityMax, cell, 0).r <= 0.0) {
                vec3 cellLo = (vec3(cell) / vec3(u_maxGridSize) - 0.5) * u_boxSize;
                vec3 cellHi = (vec3(cell + 1) / vec3(u_maxGridSize) - 0.5) * u_boxSize;
                float tExit = boxInterval(o, d, cellLo, cellHi).y;
                int next = int(floor((tExit - tmin) / dt - offset)) + 1;
                if (next > i) {
                    i = next - 1;
                    continue;
                }
            }
        }
        float rho = densityAt(uvw);
        ++samples;
        if (rho <= 0.0) continue;
        float sigma = extinctionPerRho * rho;
        vec3 source = u_emission * rho;
        if (u_useTransfer != 0) source *= texture(u_transfer, vec2(rho, 0.5)).rgb;
        // Sky light from every direction, uniform: the phase integrates to 1.
        source += u_ambient * sgfx_ambientLight.rgb * (u_scattering * rho);
        if (u_scattering > 0.0) {
            // Single scattering: the light that reaches p through the medium, M midpoint steps.
            float sMax = max(boxInterval(p, dl, -h, h).y, 0.0);
            float ds = sMax / float(u_lightSteps);
            float lightDepth = 0.0;
            for (int j = 0; j < u_lightSteps; ++j) {
                vec3 q = p + (float(j) + 0.5) * ds * dl;
                lightDepth += extinctionPerRho * densityAt(q / u_boxSize + 0.5) * ds;
            }
            vec3 sunlit = u_lightColor * exp(-lightDepth);
#ifdef SGFX_SHADOW_SUN
            // A ShadowNode above: the sun's visibility at the sample (no surface: no offset).
            sunlit *= sgfx_sunVisibility(eye + dirW * t, vec3(0.0));
#endif
            source += sunlit * (u_scattering * rho) * phase;
        }
        float tau = exp(-sigma * dt);
        if (u_integration == 1) {
            T *= tau; // the lecture's loop: the sample dims its own emission
            radiance += T * source * dt;
        } else {
            radiance += T * source * (dt * expQuotient(sigma * dt));
            T *= tau;
        }
        if (1.0 - T > u_threshold) break; // early termination
    }
    if (u_countSamples != 0) {
        sgfx_fragColor = vec4(float(samples), 0.0, 0.0, 1.0);
        return;
    }
    vec4 sgfx_color = vec4(radiance, 1.0 - T);
    vec3 sgfx_worldPos = eye + dirW * tmin; // where the medium starts: fog up to there
    vec3 sgfx_eyePos = eye;
    // @sgfx:color
    sgfx_fragColor = sgfx_color;
#ifdef SGFX_VOLUME_HALF
    sgfx_volumeDepth = vec4(dot(dirW * tmax, -vec3(sgfx_view[0][2], sgfx_view[1][2], sgfx_view[2][2])));
#endif
}

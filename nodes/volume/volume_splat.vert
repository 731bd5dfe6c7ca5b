#version 450 core
// Splatting (lecture 12, "Volume rendering: splatting"): one Gaussian kernel per instance, its
// centre a grid point (box frame; sorted back to front on the CPU each frame), drawn as a
// billboard facing the eye. Density, extinction and the light the medium sends towards the eye
// are taken at the kernel's centre, as the lecture says; VolumeMath.h derives the footprint.
#include "volume_density.glsl"

layout(location = 0) in vec3 a_centre; // box frame, metres; one per instance
uniform mat4 sgfx_model;
uniform vec3 u_boxSize;
uniform mat4 u_worldToBox;
uniform float u_absorption;
uniform float u_scattering;
uniform vec3 u_emission;
uniform float u_ambient;
uniform vec3 u_lightColor;
uniform vec3 u_lightDirection;
uniform int u_lightSteps;
uniform int u_useTransfer;
uniform float u_splatRadius; // R: the billboard's radius (world metres)
layout(binding = SGFX_VOLUME_DENSITY_UNIT + 2) uniform sampler2D u_transfer; // emission colour by ρ

out vec3 v_worldPos;
flat out vec3 v_centre;    // world
flat out float v_sigma;    // extinction (ka + ks)·ρ at the centre, per metre
flat out vec3 v_source;    // emission + ambient in-scattering per metre (isotropic)
flat out vec3 v_sunSource; // sunlight scattered per metre before the phase function

// @sgfx:vertex_decl

vec2 boxInterval(vec3 o, vec3 d, vec3 lo, vec3 hi) {
    vec3 inv = vec3(abs(d.x) > 1e-12 ? 1.0 / d.x : 1e30, abs(d.y) > 1e-12 ? 1.0 / d.y : 1e30,
                    abs(d.z) > 1e-12 ? 1.0 / d.z : 1e30);
    vec3 t0 = (lo - o) * inv, t1 = (hi - o) * inv;
    vec3 tn = min(t0, t1), tf = max(t0, t1);
    return vec2(max(max(tn.x, tn.y), tn.z), min(min(tf.x, tf.y), tf.z));
}

void main() {
    vec3 centre = (sgfx_model * vec4(a_centre, 1.0)).xyz;
    float rho = densityAt(a_centre / u_boxSize + 0.5);
    v_sigma = (u_absorption + u_scattering) * rho;
    v_source = u_emission * rho;
    if (u_useTransfer != 0) v_source *= texture(u_transfer, vec2(rho, 0.5)).rgb;
    v_source += u_ambient * sgfx_ambientLight.rgb * (u_scattering * rho);
    v_sunSource = vec3(0.0);
    if (u_scattering > 0.0 && rho > 0.0) {
        // The light that reaches the centre through the medium: M midpoint steps to the box.
        vec3 h = 0.5 * u_boxSize;
        vec3 dl = mat3(u_worldToBox) * -u_lightDirection;
        float ds = max(boxInterval(a_centre, dl, -h, h).y, 0.0) / float(u_lightSteps);
        float lightDepth = 0.0;
        for (int j = 0; j < u_lightSteps; ++j)
            lightDepth += (u_absorption + u_scattering) *
                          densityAt((a_centre + (float(j) + 0.5) * ds * dl) / u_boxSize + 0.5) * ds;
        v_sunSource = u_lightColor * exp(-lightDepth) * (u_scattering * rho);
    }
    // The quad facing the eye covers every ray passing within R of the centre: half-side
    // R·d/√(d² − R²). Empty kernels and those around the eye (not drawn) collapse to a point.
    vec3 toEye = sgfx_eye.xyz - centre;
    float dist = length(toEye);
    float R = u_splatRadius;
    bool drawn = rho > 0.0 && dist > 1.01 * R;
    float half_ = drawn ? R * dist / sqrt(dist * dist - R * R) : 0.0;
    vec3 f = toEye / max(dist, 1e-6);
    vec3 right = normalize(cross(abs(f.z) < 0.99 ? vec3(0.0, 0.0, 1.0) : vec3(1.0, 0.0, 0.0), f));
    vec3 up = cross(f, right);
    vec2 corner = vec2(float(gl_VertexID & 1), float(gl_VertexID >> 1)) * 2.0 - 1.0; // a strip
    vec3 sgfx_worldPos = centre + (corner.x * right + corner.y * up) * half_;
    vec3 sgfx_worldNormal = f;
    vec4 sgfx_viewPos = sgfx_view * vec4(sgfx_worldPos, 1.0);
    // @sgfx:vertex
    v_worldPos = sgfx_worldPos;
    v_centre = centre;
    gl_Position = sgfx_projection * sgfx_viewPos;
}

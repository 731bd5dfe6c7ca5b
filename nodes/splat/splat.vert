#version 450 core
// One Gaussian per instance, drawn as a 3σ square of four corners (a triangle strip), taken in
// the order of the sorted index buffer (back to front). Everything is pulled from storage
// buffers; nothing is interpolated but flat values.
layout(std430, binding = 13) readonly buffer SplatData { vec4 sgfx_splats[]; }; // 3 per splat
layout(std430, binding = 14) readonly buffer SplatSh { float sgfx_splatSh[]; };
layout(std430, binding = 15) readonly buffer SplatOrder { uint sgfx_splatOrder[]; };
uniform mat4 sgfx_model;
uniform int u_shDegree;

flat out vec2 v_centre;   // window pixels
flat out vec3 v_conic;    // a, b, c of the inverse 2D covariance
flat out vec4 v_colour;   // rgb (SH), opacity
flat out vec3 v_worldPos; // the centre, for the colour hook (fog)

#include "splat_sh.glsl"
#include "splat_project.glsl"

// @sgfx:vertex_decl

void main() {
    uint s = sgfx_splatOrder[gl_InstanceID];
    vec4 posOpacity = sgfx_splats[3u * s];
    vec3 sgfx_worldPos = (sgfx_model * vec4(posOpacity.xyz, 1.0)).xyz;
    vec3 sgfx_worldNormal = vec3(0.0, 0.0, 1.0);
    vec4 sgfx_viewPos = sgfx_view * vec4(sgfx_worldPos, 1.0);
    // @sgfx:vertex
    vec4 clip = sgfx_projection * sgfx_viewPos;
    vec3 conic;
    float radius;
    mat3 modelView = mat3(sgfx_view) * mat3(sgfx_model);
    mat3 sigma = splatCovariance(sgfx_splats[3u * s + 1u].xyz, sgfx_splats[3u * s + 2u]);
    if (!(clip.w > 0.0) || clip.z < -clip.w || !splatConic(sigma, modelView, sgfx_viewPos, conic, radius)) {
        gl_Position = vec4(2.0, 2.0, 2.0, 1.0); // culled: outside the clip volume
        return;
    }
    vec3 dir = normalize(inverse(mat3(sgfx_model)) * (sgfx_worldPos - sgfx_eye.xyz));
    v_colour = vec4(splatColour(s, dir), posOpacity.w);
    v_centre = sgfx_viewport.xy + (clip.xy / clip.w * 0.5 + 0.5) * sgfx_viewport.zw;
    v_conic = conic;
    v_worldPos = sgfx_worldPos;
    vec2 corner = vec2(gl_VertexID & 1, gl_VertexID >> 1) * 2.0 - 1.0;
    gl_Position = clip + vec4(corner * radius * 2.0 / sgfx_viewport.zw * clip.w, 0.0, 0.0);
}

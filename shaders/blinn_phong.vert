#version 450 core
// Built-in material, vertex stage. Effects hook in at @sgfx:vertex with the world position,
// world normal and view position in hand. SGFX_* feature defines select what is passed on, so
// a plain material interpolates no attribute it does not use.
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec4 a_tangent;
layout(location = 3) in vec2 a_texcoord;
layout(location = 4) in vec4 a_color;

uniform mat4 sgfx_model;
uniform mat3 sgfx_normalMatrix;

out vec3 v_worldPos;
#ifdef SGFX_NORMALS
out vec3 v_worldNormal;
#endif
#ifdef SGFX_TANGENTS
out vec4 v_worldTangent;
#endif
#ifdef SGFX_TEXCOORDS
out vec2 v_texcoord;
#endif
#ifdef SGFX_VERTEX_COLOR
out vec4 v_color;
#endif

// @sgfx:vertex_decl

void main() {
    vec3 sgfx_worldPos = (sgfx_model * vec4(a_position, 1.0)).xyz;
    vec3 sgfx_worldNormal = sgfx_normalMatrix * a_normal;
    vec4 sgfx_viewPos = sgfx_view * vec4(sgfx_worldPos, 1.0);
    // @sgfx:vertex
    v_worldPos = sgfx_worldPos;
#ifdef SGFX_NORMALS
    v_worldNormal = sgfx_worldNormal;
#endif
#ifdef SGFX_TANGENTS
    v_worldTangent = vec4(mat3(sgfx_model) * a_tangent.xyz, a_tangent.w);
#endif
#ifdef SGFX_TEXCOORDS
    v_texcoord = a_texcoord;
#endif
#ifdef SGFX_VERTEX_COLOR
    v_color = a_color;
#endif
    gl_Position = sgfx_projection * sgfx_viewPos;
}

#version 450 core
// Instanced path: no geometry shader; each instance is one particle (its record arrives as
// per-instance attributes) and gl_VertexID walks the shape's triangles.
#include "particle_shape.glsl"

layout(location = 0) in vec4 a_state; // age, position
layout(location = 1) in vec3 a_velocity;
layout(location = 2) in vec3 a_angles0;
layout(location = 3) in vec3 a_angles;

out vec3 v_worldPos;
out vec3 v_worldNormal;
out vec2 v_texcoord;
out vec4 v_color;

// @sgfx:vertex_decl

void main() {
    float age = a_state.x;
#if SGFX_PARTICLE_SHAPE == 2
    // Separate faces: drawn as triangles, three vertices per strip of three.
    int strip = gl_VertexID / 3;
    int k = gl_VertexID % 3;
#else
    // One strip per particle: drawn as an instanced triangle strip.
    int strip = 0;
    int k = gl_VertexID;
#endif
    if (age < 0.0) {
        gl_Position = vec4(2.0, 2.0, 2.0, 1.0); // not born: outside the clip volume
        return;
    }
    vec3 P = a_state.yzw;
    float life = particleLife(age);
    vec3 local, normal;
    vec2 uv;
    shapeCorner(strip, k, local, normal, uv);
    mat3 frame = particleFrame(P, a_angles0, a_angles);
    vec3 sgfx_worldPos = particleCorner(P, a_velocity, frame, mix(u_size.x, u_size.y, life), local);
    vec3 sgfx_worldNormal = frame * normal;
    vec4 sgfx_viewPos = sgfx_view * vec4(sgfx_worldPos, 1.0);
    // @sgfx:vertex
    v_worldPos = sgfx_worldPos;
    v_worldNormal = sgfx_worldNormal;
    v_texcoord = uv;
    v_color = mix(u_colorStart, u_colorEnd, life);
    gl_Position = sgfx_projection * sgfx_viewPos;
}

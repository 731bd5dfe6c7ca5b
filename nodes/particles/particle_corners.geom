#version 450 core
// Geometry-shader path: one point in, the particle's polygons out (seed, fig. 2 and 3).
layout(points) in;
layout(triangle_strip, max_vertices = 12) out;

#include "particle_shape.glsl"

in Particle {
    vec4 state;
    vec3 velocity;
    vec3 angles0;
    vec3 angles;
} p_in[];

out vec3 v_worldPos;
out vec3 v_worldNormal;
out vec2 v_texcoord;
out vec4 v_color;

// @sgfx:vertex_decl

void emitCorner(vec3 worldPos, vec3 worldNormal, vec2 uv, vec4 color) {
    vec3 sgfx_worldPos = worldPos;
    vec3 sgfx_worldNormal = worldNormal;
    vec4 sgfx_viewPos = sgfx_view * vec4(sgfx_worldPos, 1.0);
    // @sgfx:vertex
    v_worldPos = sgfx_worldPos;
    v_worldNormal = sgfx_worldNormal;
    v_texcoord = uv;
    v_color = color;
    gl_Position = sgfx_projection * sgfx_viewPos;
    EmitVertex();
}

void main() {
    float age = p_in[0].state.x;
    if (age < 0.0) return; // not born yet
    vec3 P = p_in[0].state.yzw;
    float life = particleLife(age);
    float size = mix(u_size.x, u_size.y, life);
    vec4 color = mix(u_colorStart, u_colorEnd, life);
    mat3 frame = particleFrame(P, p_in[0].angles0, p_in[0].angles);
    for (int s = 0; s < kShapeStrips; ++s) {
        for (int k = 0; k < kShapeStripLength; ++k) {
            vec3 local, normal;
            vec2 uv;
            shapeCorner(s, k, local, normal, uv);
            emitCorner(particleCorner(P, p_in[0].velocity, frame, size, local), frame * normal, uv, color);
        }
        EndPrimitive();
    }
}

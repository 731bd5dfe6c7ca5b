#version 450 core
// Vertex-pulling path: one plain draw of every particle's triangles (no instancing, no geometry
// shader); each vertex finds its particle from gl_VertexID and reads the record from buffer
// textures. Software rasterizers run large plain draws far faster than a million tiny instances.
#include "particle_shape.glsl"

#ifdef SGFX_PARTICLE_SPLIT
layout(binding = SGFX_PARTICLE_BUFFER_UNIT) uniform samplerBuffer p_state;        // age, position
layout(binding = SGFX_PARTICLE_BUFFER_UNIT + 1) uniform samplerBuffer p_velocity;
layout(binding = SGFX_PARTICLE_BUFFER_UNIT + 2) uniform samplerBuffer p_angles0;
layout(binding = SGFX_PARTICLE_BUFFER_UNIT + 3) uniform samplerBuffer p_angles;
vec4 recordState(int i) { return texelFetch(p_state, i); }
vec3 recordVelocity(int i) { return texelFetch(p_velocity, i).xyz; }
vec3 recordAngles0(int i) { return texelFetch(p_angles0, i).xyz; }
vec3 recordAngles(int i) { return texelFetch(p_angles, i).xyz; }
#else
layout(binding = SGFX_PARTICLE_BUFFER_UNIT) uniform samplerBuffer p_records; // 13 floats each
float recordFloat(int i, int k) { return texelFetch(p_records, i * 13 + k).x; }
vec4 recordState(int i) { return vec4(recordFloat(i, 0), recordFloat(i, 1), recordFloat(i, 2), recordFloat(i, 3)); }
vec3 recordVelocity(int i) { return vec3(recordFloat(i, 4), recordFloat(i, 5), recordFloat(i, 6)); }
vec3 recordAngles0(int i) { return vec3(recordFloat(i, 7), recordFloat(i, 8), recordFloat(i, 9)); }
vec3 recordAngles(int i) { return vec3(recordFloat(i, 10), recordFloat(i, 11), recordFloat(i, 12)); }
#endif

out vec3 v_worldPos;
out vec3 v_worldNormal;
out vec2 v_texcoord;
out vec4 v_color;

// @sgfx:vertex_decl

void main() {
    // Each particle: its strips as triangles, (length − 2) · 3 vertices per strip.
    const int perStrip = (kShapeStripLength - 2) * 3;
    const int perParticle = kShapeStrips * perStrip;
    int particle = gl_VertexID / perParticle;
    int v = gl_VertexID - particle * perParticle;
    int strip = v / perStrip;
    v -= strip * perStrip;
    int triangle = v / 3;
    int c = v % 3;
    // A strip's odd triangles run (k+1, k, k+2), so every triangle keeps the strip's facing.
    int k = triangle + ((triangle & 1) != 0 && c < 2 ? 1 - c : c);
    vec4 state = recordState(particle);
    if (state.x < 0.0) {
        gl_Position = vec4(2.0, 2.0, 2.0, 1.0); // not born: outside the clip volume
        return;
    }
    vec3 P = state.yzw;
    float life = particleLife(state.x);
    vec3 local, normal;
    vec2 uv;
    shapeCorner(strip, k, local, normal, uv);
#if SGFX_PARTICLE_SHAPE == 0
    mat3 frame = particleFrame(P, vec3(0.0), vec3(0.0));
#else
    mat3 frame = particleFrame(P, recordAngles0(particle), recordAngles(particle));
#endif
#if SGFX_PARTICLE_SHAPE == 2
    vec3 velocity = recordVelocity(particle);
#else
    vec3 velocity = vec3(0.0);
#endif
    vec3 sgfx_worldPos = particleCorner(P, velocity, frame, mix(u_size.x, u_size.y, life), local);
    vec3 sgfx_worldNormal = frame * normal;
    vec4 sgfx_viewPos = sgfx_view * vec4(sgfx_worldPos, 1.0);
    // @sgfx:vertex
    v_worldPos = sgfx_worldPos;
    v_worldNormal = sgfx_worldNormal;
    v_texcoord = uv;
    v_color = mix(u_colorStart, u_colorEnd, life);
    gl_Position = sgfx_projection * sgfx_viewPos;
}

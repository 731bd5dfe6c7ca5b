#version 450 core
// Compute step M → M': the same equations as the transform feedback step (particle_update.vert),
// one invocation per particle, copy M read and copy M' written as shader storage. The host
// defines SGFX_PARTICLE_SOURCE / SGFX_PARTICLE_TARGET (first bindings of each copy) and, for the
// split layout, SGFX_PARTICLE_SPLIT.
layout(local_size_x = 64) in;
#include "particle_random.glsl"
#include "particle_motion.glsl"

uniform uint u_count; // particles in the buffers (the last work group may run past them)

// The records are packed (52-byte interleaved records, 12-byte vec3 streams), so vec3s are read
// and written as floats: std430 would pad a vec3 array to 16 bytes.
#ifdef SGFX_PARTICLE_SPLIT
layout(std430, binding = SGFX_PARTICLE_SOURCE) readonly buffer State { vec4 m_state[]; };
layout(std430, binding = SGFX_PARTICLE_SOURCE + 1) readonly buffer Velocity { float m_velocity[]; };
layout(std430, binding = SGFX_PARTICLE_SOURCE + 2) readonly buffer Angles0 { float m_angles0[]; };
layout(std430, binding = SGFX_PARTICLE_SOURCE + 3) readonly buffer Angles { float m_angles[]; };
layout(std430, binding = SGFX_PARTICLE_TARGET) writeonly buffer State2 { vec4 o_state[]; };
layout(std430, binding = SGFX_PARTICLE_TARGET + 1) writeonly buffer Velocity2 { float o_velocity[]; };
layout(std430, binding = SGFX_PARTICLE_TARGET + 2) writeonly buffer Angles02 { float o_angles0[]; };
layout(std430, binding = SGFX_PARTICLE_TARGET + 3) writeonly buffer Angles2 { float o_angles[]; };

vec3 load3(uint s, uint i) {
    if (s == 1u) return vec3(m_velocity[3u * i], m_velocity[3u * i + 1u], m_velocity[3u * i + 2u]);
    if (s == 2u) return vec3(m_angles0[3u * i], m_angles0[3u * i + 1u], m_angles0[3u * i + 2u]);
    return vec3(m_angles[3u * i], m_angles[3u * i + 1u], m_angles[3u * i + 2u]);
}

Particle load(uint i) {
    vec4 s = m_state[i];
    return Particle(s.x, s.yzw, load3(1u, i), load3(2u, i), load3(3u, i));
}

void store(uint i, Particle p) {
    o_state[i] = vec4(p.age, p.position);
    for (uint k = 0u; k < 3u; ++k) {
        o_velocity[3u * i + k] = p.velocity[k];
        o_angles0[3u * i + k] = p.angles0[k];
        o_angles[3u * i + k] = p.angles[k];
    }
}
#else
layout(std430, binding = SGFX_PARTICLE_SOURCE) readonly buffer Records { float m_record[]; };
layout(std430, binding = SGFX_PARTICLE_TARGET) writeonly buffer Records2 { float o_record[]; };

vec3 load3(uint at) { return vec3(m_record[at], m_record[at + 1u], m_record[at + 2u]); }

Particle load(uint i) { // ParticleRecord: age, P, v, r0, r (13 floats)
    uint at = 13u * i;
    return Particle(m_record[at], load3(at + 1u), load3(at + 4u), load3(at + 7u), load3(at + 10u));
}

void store(uint i, Particle p) {
    uint at = 13u * i;
    o_record[at] = p.age;
    for (uint k = 0u; k < 3u; ++k) {
        o_record[at + 1u + k] = p.position[k];
        o_record[at + 4u + k] = p.velocity[k];
        o_record[at + 7u + k] = p.angles0[k];
        o_record[at + 10u + k] = p.angles[k];
    }
}
#endif

void main() {
    // Work groups in rows of gl_NumWorkGroups.x: 2^24 particles need more than 65535 in x.
    uint index = gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x + gl_GlobalInvocationID.x;
    if (index >= u_count) return;
    store(index, updateParticle(load(index), index));
}

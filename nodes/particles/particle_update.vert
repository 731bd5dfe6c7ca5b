#version 450 core
// Transform feedback step M → M' (seed, fig. 1): one particle per vertex, rasterizer off.
#include "particle_random.glsl"
#include "particle_motion.glsl"

layout(location = 0) in vec4 a_state; // age, position
layout(location = 1) in vec3 a_velocity;
layout(location = 2) in vec3 a_angles0;
layout(location = 3) in vec3 a_angles;

out vec4 o_state;
out vec3 o_velocity;
out vec3 o_angles0;
out vec3 o_angles;

uniform int u_init;       // 0: step; 1 steady, 2 ramp, 3 burst: the records at reset
uniform uint u_initFirst; // first index of the range being set up
uniform uint u_initCount;

void main() {
    uint index = uint(gl_VertexID);
    Particle p;
    if (u_init == 0) {
        p = updateParticle(Particle(a_state.x, a_state.yzw, a_velocity, a_angles0, a_angles), index);
    } else {
        float stagger = (float(index - u_initFirst) + 0.5) / float(u_initCount);
        if (u_init == 3) {
            p = spawnParticle(index, 0.0);
        } else if (u_init == 2) {
            p = Particle(-u_tmax * stagger, u_emitter[3].xyz, vec3(0.0), vec3(0.0), vec3(0.0));
        } else {
            p = spawnParticle(index, u_tmax * stagger * 0.999999);
        }
    }
    o_state = vec4(p.age, p.position);
    o_velocity = p.velocity;
    o_angles0 = p.angles0;
    o_angles = p.angles;
}

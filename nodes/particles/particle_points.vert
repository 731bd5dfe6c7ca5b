#version 450 core
// Geometry-shader path: the vertex stage only hands the particle on (seed, fig. 2).
layout(location = 0) in vec4 a_state; // age, position
layout(location = 1) in vec3 a_velocity;
layout(location = 2) in vec3 a_angles0;
layout(location = 3) in vec3 a_angles;

out Particle {
    vec4 state;
    vec3 velocity;
    vec3 angles0;
    vec3 angles;
} p_out;

void main() {
    p_out.state = a_state;
    p_out.velocity = a_velocity;
    p_out.angles0 = a_angles0;
    p_out.angles = a_angles;
}

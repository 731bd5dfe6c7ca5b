#version 450 core
// The distortion mesh: positions already in clip space (the projector image), the direction each
// vertex shows (display frame) and the angle its intensity is read at.
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 3) in vec2 a_texcoord;
out vec3 v_direction;
out float v_angle;
void main() {
    v_direction = a_normal;
    v_angle = a_texcoord.x;
    gl_Position = vec4(a_position, 1.0);
}

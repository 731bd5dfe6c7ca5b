#version 450 core
// Depth-only pass (pre-passes): the same position arithmetic as blinn_phong.vert, so the depth
// written here matches the main pass's depth for the same triangle.
layout(location = 0) in vec3 a_position;
uniform mat4 sgfx_model;
void main() {
    vec3 world = (sgfx_model * vec4(a_position, 1.0)).xyz;
    gl_Position = sgfx_projection * (sgfx_view * vec4(world, 1.0));
}

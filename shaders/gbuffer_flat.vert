#version 450 core
// G-buffer for programs the composer cannot vary (foreign shaders): positions only, the same
// arithmetic as blinn_phong.vert; the fragment stage takes the normal from the triangle's plane.
layout(location = 0) in vec3 a_position;
uniform mat4 sgfx_model;
out vec3 v_viewPos;
void main() {
    vec3 world = (sgfx_model * vec4(a_position, 1.0)).xyz;
    vec4 view = sgfx_view * vec4(world, 1.0);
    v_viewPos = view.xyz;
    gl_Position = sgfx_projection * view;
}

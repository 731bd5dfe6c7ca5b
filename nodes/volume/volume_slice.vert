#version 450 core
// Slicing (lecture 12, "Volume rendering: slicing"): polygons where planes perpendicular to the
// view direction cut the box, made on the CPU each frame in the box frame, drawn back to front.
layout(location = 0) in vec3 a_position; // box frame, metres
uniform mat4 sgfx_model;

out vec3 v_worldPos;
out vec3 v_boxPos;

// @sgfx:vertex_decl

void main() {
    vec3 sgfx_worldPos = (sgfx_model * vec4(a_position, 1.0)).xyz;
    vec3 sgfx_worldNormal = vec3(0.0, 0.0, 1.0);
    vec4 sgfx_viewPos = sgfx_view * vec4(sgfx_worldPos, 1.0);
    // @sgfx:vertex
    v_worldPos = sgfx_worldPos;
    v_boxPos = a_position;
    gl_Position = sgfx_projection * sgfx_viewPos;
}

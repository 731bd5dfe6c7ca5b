#version 450 core
// Full-screen triangle from gl_VertexID; no vertex buffer needed.
out vec2 v_uv;
void main() {
    vec2 p = vec2((gl_VertexID << 1) & 2, gl_VertexID & 2);
    v_uv = p;
#ifdef SGFX_FULLSCREEN_FAR
    gl_Position = vec4(p * 2.0 - 1.0, 1.0, 1.0); // depth exactly 1: only uncovered pixels pass EQUAL
#else
    gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
#endif
}

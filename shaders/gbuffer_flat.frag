#version 450 core
// G-buffer outputs (as the built-in material's SGFX_GBUFFER variant): view-space normal, linear
// view depth in metres, view-space position. Flat normals from screen-space derivatives.
in vec3 v_viewPos;
layout(location = 0) out vec4 sgfx_gNormal;
layout(location = 1) out vec4 sgfx_gDepth;
layout(location = 2) out vec4 sgfx_gPosition;
void main() {
    vec3 n = normalize(cross(dFdx(v_viewPos), dFdy(v_viewPos)));
    sgfx_gNormal = vec4(gl_FrontFacing ? n : -n, 0.0);
    sgfx_gDepth = vec4(-v_viewPos.z);
    sgfx_gPosition = vec4(v_viewPos, 1.0);
}

#version 450 core
// G-buffer outputs (as the built-in material's SGFX_GBUFFER variant): view-space normal, linear
// view depth in metres, view-space position. Flat normals from screen-space derivatives.
in vec3 v_viewPos;
layout(location = 0) out vec4 sgfx_gNormal;
layout(location = 1) out vec4 sgfx_gDepth;
layout(location = 2) out vec4 sgfx_gPosition;
void main() {
    // A sliver seen edge-on has (nearly) parallel derivatives: its cross product is zero and
    // normalising it gives NaN, which AO's blur would spread. Such a pixel faces the eye instead.
    vec3 c = cross(dFdx(v_viewPos), dFdy(v_viewPos));
    float c2 = dot(c, c);
    vec3 n = c2 > 1e-30 ? c * inversesqrt(c2) : vec3(0.0, 0.0, 1.0);
    sgfx_gNormal = vec4(gl_FrontFacing ? n : -n, 0.0);
    sgfx_gDepth = vec4(-v_viewPos.z);
    sgfx_gPosition = vec4(v_viewPos, 1.0);
}

#version 450 core
// The sky without the sun's disc (a directional light stands for the sun) as a 6:1 strip of cube
// faces in OpenGL's order, one texel per fragment, for the environment light
// (EnvironmentMath.h: cubeDirection, the same addressing).
#include "sky_scattering.glsl"

layout(location = 0) out vec4 sgfx_fragColor;
uniform int u_faceSize;

vec3 cubeDirection(int face, vec2 st) {
    float sc = 2.0 * st.x - 1.0, tc = 2.0 * st.y - 1.0;
    if (face == 0) return vec3(1.0, -tc, -sc);
    if (face == 1) return vec3(-1.0, -tc, sc);
    if (face == 2) return vec3(sc, 1.0, tc);
    if (face == 3) return vec3(sc, -1.0, -tc);
    if (face == 4) return vec3(sc, -tc, 1.0);
    return vec3(-sc, -tc, -1.0);
}

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    int face = p.x / u_faceSize;
    vec2 st = (vec2(p.x - face * u_faceSize, p.y) + 0.5) / float(u_faceSize);
    vec3 sunT;
    sgfx_fragColor = vec4(skyRadiance(normalize(cubeDirection(face, st)), sunT), 1.0);
}

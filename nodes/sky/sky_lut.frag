#version 450 core
// The sky-view table: the sky's radiance for each (azimuth, √elevation) texel (SkyMath.h:
// lutCoordinates), made once per frame at a few thousand texels instead of per pixel.
#include "sky_scattering.glsl"

in vec2 v_uv;
layout(location = 0) out vec4 fragColor;

void main() {
    float az = (v_uv.x - 0.5) * 6.283185307179586;
    float el = v_uv.y * v_uv.y * 1.5707963267948966;
    vec3 dir = vec3(cos(el) * cos(az), cos(el) * sin(az), sin(el));
    vec3 sunT;
    fragColor = vec4(skyRadiance(dir, sunT), 1.0);
}

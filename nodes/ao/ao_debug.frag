#version 450 core
// Debug view of the occlusion map over the whole view: white open, black fully occluded (the
// seed's figures 5 and 7).
in vec2 v_uv;
layout(location = 0) out vec4 sgfx_fragColor;
uniform sampler2D sgfx_aoShown; // (k, linear depth)

void main() {
    ivec2 size = textureSize(sgfx_aoShown, 0);
    ivec2 p = ivec2(gl_FragCoord.xy) * size / ivec2(sgfx_viewport.zw);
    float k = texelFetch(sgfx_aoShown, min(p, size - 1), 0).r;
    sgfx_fragColor = vec4(vec3(1.0 - k), 1.0);
}

#version 450 core
// MSAA resolve: the mean of a pixel's samples in linear colour (the sRGB samples decode on
// fetch, the target encodes on write); a plain blit may average the encoded values.
in vec2 v_uv;
layout(location = 0) out vec4 sgfx_fragColor;
layout(binding = 0) uniform sampler2DMS sgfx_aaSamples;
uniform int sgfx_aaSampleCount;

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    vec4 sum = vec4(0.0);
    for (int i = 0; i < sgfx_aaSampleCount; ++i)
        sum += texelFetch(sgfx_aaSamples, p, i);
    sgfx_fragColor = sum / float(sgfx_aaSampleCount);
}

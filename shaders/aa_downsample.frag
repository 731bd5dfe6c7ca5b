#version 450 core
// SSAA: the mean of the factor×factor samples behind each output pixel (a box filter), in linear
// colour (the sRGB source decodes on fetch; the target encodes on write).
in vec2 v_uv;
layout(location = 0) out vec4 sgfx_fragColor;
layout(binding = 0) uniform sampler2D sgfx_aaSource;
uniform int sgfx_aaFactor;

void main() {
    ivec2 base = ivec2(gl_FragCoord.xy) * sgfx_aaFactor;
    vec4 sum = vec4(0.0);
    for (int y = 0; y < sgfx_aaFactor; ++y)
        for (int x = 0; x < sgfx_aaFactor; ++x)
            sum += texelFetch(sgfx_aaSource, base + ivec2(x, y), 0);
    sgfx_fragColor = sum / float(sgfx_aaFactor * sgfx_aaFactor);
}

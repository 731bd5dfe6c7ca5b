#version 450 core
// FXAA's first step: perceptual luma of the finished image into its own texture, so the edge
// search reads one channel instead of decoding colour at every step.
in vec2 v_uv;
layout(location = 0) out vec4 sgfx_fragColor;
layout(binding = 0) uniform sampler2D sgfx_aaSource; // linear on fetch

void main() {
    vec3 c = texelFetch(sgfx_aaSource, ivec2(gl_FragCoord.xy), 0).rgb;
    sgfx_fragColor = vec4(sqrt(dot(c, vec3(0.299, 0.587, 0.114)))); // thresholds are tuned for gamma values
}

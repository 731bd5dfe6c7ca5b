#version 450 core
// The exact Gaussian falloff (Kerbl et al. 2023 eq. 2 in screen space): α = o · exp(−½ dᵀ Σ'⁻¹ d),
// discarded below 1/255, written premultiplied for back-to-front "over" blending.
flat in vec2 v_centre;
flat in vec3 v_conic;
flat in vec4 v_colour;
flat in vec3 v_worldPos;
layout(location = 0) out vec4 sgfx_fragColor;

// @sgfx:fragment_decl

void main() {
    vec2 d = gl_FragCoord.xy - v_centre;
    float power = -0.5 * (v_conic.x * d.x * d.x + v_conic.z * d.y * d.y) - v_conic.y * d.x * d.y;
    if (power > 0.0) discard;
    float alpha = v_colour.a * exp(power);
    if (alpha < 1.0 / 255.0) discard;
    vec4 sgfx_color = vec4(v_colour.rgb * alpha, alpha);
    vec3 sgfx_worldPos = v_worldPos;
    vec3 sgfx_eyePos = sgfx_eye.xyz;
    // @sgfx:color
    sgfx_fragColor = sgfx_color;
}

// Height fog: density ρ(h) = ρ0·e^(−b·h) integrated along a segment (seed fog-height-gpu-2020,
// eq. 3–7). Mirrors nodes/fog/FogMath.h line for line; its comments give the derivation.
uniform float sgfx_fogDensity; // ρ0
uniform float sgfx_fogFalloff; // b
uniform vec3 sgfx_fogColor;    // linear RGB
uniform vec4 sgfx_fogPlane;    // xyz: unit up, w: reference height
uniform vec4 sgfx_fogShape;    // x: 1 = exponential response, 0 = linear; y: max opacity;
                               // z: sky distance (0: no sky fog, < 0: to the far plane)

// (1 − e^(−y)) / y, continuous at 0: a series below 1e-2, so horizontal rays do not cancel.
float sgfx_fogExpQuotient(float y) {
    return y < 1e-2 ? 1.0 - y * (0.5 - y * (1.0 / 6.0 - y * (1.0 / 24.0 - y / 120.0))) : (1.0 - exp(-y)) / y;
}

// F on the segment a → b (eq. 6 with combined exponents; F_f of §2 when a = Pn).
float sgfx_fogOpticalDepth(vec3 a, vec3 b) {
    float s = length(b - a);
    if (!(sgfx_fogDensity > 0.0) || !(s > 0.0)) return 0.0;
    s = min(s, 1e10);
    float ha = dot(a, sgfx_fogPlane.xyz) - sgfx_fogPlane.w;
    float hb = dot(b, sgfx_fogPlane.xyz) - sgfx_fogPlane.w;
    float y = sgfx_fogFalloff * abs(hb - ha);
    return sgfx_fogDensity * s * exp(min(-sgfx_fogFalloff * min(ha, hb), 50.0)) * sgfx_fogExpQuotient(y);
}

// k from F: eq. 7's clamp, or Beer–Lambert.
float sgfx_fogAmount(float F) {
    float k = sgfx_fogShape.x > 0.5 ? 1.0 - exp(-F) : clamp(F, 0.0, 1.0);
    return min(k, sgfx_fogShape.y);
}

// Eq. 7 for the blend mode the output goes through: fog attenuates what an additive surface
// adds and what a multiplicative one removes; premultiplied colour carries its alpha.
vec4 sgfx_fogApply(vec4 c, float k) {
#if defined(SGFX_BLEND_ADDITIVE)
    c.rgb *= 1.0 - k;
#elif defined(SGFX_BLEND_MULTIPLY)
    c.rgb = mix(c.rgb, vec3(1.0), k);
#elif defined(SGFX_BLEND_PREMULTIPLIED)
    c.rgb = mix(c.rgb, sgfx_fogColor * c.a, k);
#else
    c.rgb = mix(c.rgb, sgfx_fogColor, k);
#endif
    return c;
}

// Height fog: density ρ(h) = ρ0·e^(−b·h) integrated along a segment (seed fog-height-gpu-2020,
// eq. 3–7). Mirrors nodes/fog/FogMath.h line for line; its comments give the derivation.
uniform float sgfx_fogDensity; // ρ0
uniform float sgfx_fogFalloff; // b
uniform vec3 sgfx_fogColor;    // linear RGB
uniform vec4 sgfx_fogPlane;    // xyz: unit up, w: reference height
uniform vec4 sgfx_fogShape;    // x: 1 = exponential response, 0 = linear; y: max opacity;
                               // z: sky distance (0: no sky fog, < 0: to the far plane)
uniform vec2 sgfx_fogEye;      // the eye's height and density factor e^(−b·h), per view

float sgfx_fogHeight(vec3 p) {
    return dot(p, sgfx_fogPlane.xyz) - sgfx_fogPlane.w;
}

// e^(−b·h), held at e^50 below −50/b.
float sgfx_fogDensityFactor(float h) {
    return exp(min(-sgfx_fogFalloff * h, 50.0));
}

// F on a segment of length s between heights ha, hb with density factors ea, eb (eq. 6 with
// combined exponents; its series below b·|Δh| = 0.01).
float sgfx_fogOpticalDepthOf(float ha, float hb, float ea, float eb, float s) {
    if (!(sgfx_fogDensity > 0.0) || !(s > 0.0)) return 0.0;
    s = min(s, 1e10);
    float y = sgfx_fogFalloff * abs(hb - ha);
    float mean = y < 1e-2 ? max(ea, eb) * (1.0 - y * (0.5 - y * (1.0 / 6.0 - y * (1.0 / 24.0 - y / 120.0))))
                          : max(abs(ea - eb) / y, min(ea, eb));
    return sgfx_fogDensity * s * mean;
}

// F on the segment a → b (F_f of §2 when a = Pn).
float sgfx_fogOpticalDepth(vec3 a, vec3 b) {
    float ha = sgfx_fogHeight(a), hb = sgfx_fogHeight(b);
    return sgfx_fogOpticalDepthOf(ha, hb, sgfx_fogDensityFactor(ha), sgfx_fogDensityFactor(hb), length(b - a));
}

// F from the eye to p: one exp per fragment.
float sgfx_fogOpticalDepthFromEye(vec3 p) {
    float hp = sgfx_fogHeight(p);
    return sgfx_fogOpticalDepthOf(sgfx_fogEye.x, hp, sgfx_fogEye.y, sgfx_fogDensityFactor(hp),
                                  distance(p, sgfx_eye.xyz));
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

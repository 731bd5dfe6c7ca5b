// Weighted blended order-independent transparency (McGuire & Bavoil 2013), declarations.
// Only straight and premultiplied alpha surfaces accumulate: additive and multiplicative
// blending commute and stay in the sorted stage.
#if defined(SGFX_BLEND) && !defined(SGFX_BLEND_ADDITIVE) && !defined(SGFX_BLEND_MULTIPLY)
#define SGFX_OIT_ACCUMULATE
layout(location = 1) out vec4 sgfx_oitRevealage;
#endif

uniform vec2 sgfx_oitWeight; // x: equation (0 = constant, 7..10), y: metres per unit of z

// w(z, α), equations 7–10; z the view depth in metres, d the window depth. Powers as products:
// pow() is an exp2 and a log2 per call.
float sgfx_oitWeightOf(float alpha, float z, float d) {
    int eq = int(sgfx_oitWeight.x);
    z = abs(z) / sgfx_oitWeight.y;
    float far = z * (1.0 / 200.0), far2 = far * far;
    float w;
    if (eq == 7) {
        float n = z * (1.0 / 5.0);
        w = 10.0 / (1e-5 + n * n + far2 * far2 * far2);
    } else if (eq == 8) {
        float n = z * (1.0 / 10.0);
        w = 10.0 / (1e-5 + n * n * n + far2 * far2 * far2);
    } else if (eq == 9) {
        w = 0.03 / (1e-5 + far2 * far2);
    } else if (eq == 10) {
        float e = 1.0 - d;
        return alpha * max(1e-2, 3e3 * e * e * e);
    } else {
        return alpha;
    }
    return alpha * clamp(w, 1e-2, 3e3);
}

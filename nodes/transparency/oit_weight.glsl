// Weighted blended order-independent transparency (McGuire & Bavoil 2013), declarations.
// Only straight and premultiplied alpha surfaces accumulate: additive and multiplicative
// blending commute and stay in the sorted stage.
#if defined(SGFX_BLEND) && !defined(SGFX_BLEND_ADDITIVE) && !defined(SGFX_BLEND_MULTIPLY)
#define SGFX_OIT_ACCUMULATE
layout(location = 1) out vec4 sgfx_oitRevealage;
#endif

uniform vec2 sgfx_oitWeight; // x: equation (0 = constant, 7..10), y: metres per unit of z

// w(z, α), equations 7–10; z the view depth in metres, d the window depth.
float sgfx_oitWeightOf(float alpha, float z, float d) {
    int eq = int(sgfx_oitWeight.x);
    z = abs(z) / sgfx_oitWeight.y;
    float w;
    if (eq == 7)
        w = 10.0 / (1e-5 + pow(z / 5.0, 2.0) + pow(z / 200.0, 6.0));
    else if (eq == 8)
        w = 10.0 / (1e-5 + pow(z / 10.0, 3.0) + pow(z / 200.0, 6.0));
    else if (eq == 9)
        w = 0.03 / (1e-5 + pow(z / 200.0, 4.0));
    else if (eq == 10)
        return alpha * max(1e-2, 3e3 * pow(1.0 - d, 3.0));
    else
        return alpha;
    return alpha * clamp(w, 1e-2, 3e3);
}

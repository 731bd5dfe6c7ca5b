// Punctual lights (KHR_lights_punctual) for the built-in material, both stages: what attenuates
// a light, and the light list (FeatureLightList) in shader storage buffers. Light colours are
// irradiance over π (Material.h); see docs/lights.md for the units.
#if defined(SGFX_LIGHT_ATTENUATION) || defined(SGFX_LIGHT_LIST)
// Every light of the view: with the unrolled loop (SGFX_LIGHT_COUNT) the first 8 are the frame
// block's, with the light list those without a range come first (sgfx_lightCount.y of them).
struct SgfxLight {
    vec4 vector; // as sgfx_lightVector
    vec4 color;  // rgb: colour x intensity; w: 1 / range (0: unlimited)
    vec4 spot;   // xyz: the axis a spot shines along; w: cone scale (0: no cone)
    vec4 params; // x: cone offset (1: no cone); y: 1 = inverse-square falloff; z: index in the view
};
layout(std430, binding = 8) readonly buffer SgfxLights { // sgfx::kLightsBinding
    SgfxLight sgfx_lights[];
};
#endif
#if defined(SGFX_LIGHT_LIST) && !defined(SGFX_VERTEX_LIGHTING)
// Per screen tile of sgfx_lightCount.w pixels, row by row: [2t] the first index of its list,
// [2t + 1] its length; the lists hold indices into sgfx_lights (ranged lights only).
layout(std430, binding = 9) readonly buffer SgfxLightTiles { // sgfx::kLightTilesBinding
    uint sgfx_lightTiles[];
};
#endif

#if defined(SGFX_LIGHT_ATTENUATION) || defined(SGFX_LIGHT_LIST)
// The factor on a light's colour at world position P, and L, the unit vector towards the light:
// window(d) = clamp(1 - (d / range)^4, 0, 1), 1 / d^2 with inverse-square falloff, and the
// spot's a^2, a = clamp(cos(theta) * scale + offset, 0, 1) (KHR_lights_punctual's reference).
float sgfx_lightFactor(vec4 lv, vec4 lc, vec4 ls, vec4 lp, vec3 P, out vec3 L) {
    vec3 toLight = lv.xyz - lv.w * P; // w = 0: direction, w = 1: position
    float d2 = max(dot(toLight, toLight), 1e-12);
    L = toLight * inversesqrt(d2);
    float x = d2 * lv.w * lc.w * lc.w; // (d / range)^2; 0 for directions and unlimited lights
    float window = clamp(1.0 - x * x, 0.0, 1.0);
    float a = clamp(dot(ls.xyz, -L) * ls.w + lp.x, 0.0, 1.0);
    return window * a * a * (lp.y != 0.0 ? 1.0 / d2 : 1.0);
}
#endif

// Light visibility for the built-in material's hook (blinn_phong.frag, SGFX_LIGHT_VISIBILITY): the
// sun's cascades and the spots' maps, with the receiver's bias and normal offset (plan §5,
// ShadowMath's receiverBias and normalOffset).

// The filter the node chose (SGFX_SHADOW_FILTER: 0 Hard2x2, 1 Pcf, 2 Pcss); spots take PCF under
// PCSS.
float sgfx_shadowFiltered(vec4 tile, float t, vec2 uv, float depth, vec3 P, bool sun) {
#if SGFX_SHADOW_FILTER == 0
    return sgfx_shadowHard(tile, uv, depth);
#elif SGFX_SHADOW_FILTER == 1
    return sgfx_shadowPcf(tile, t, uv, depth, P, sgfx_shadowFilter.x, sgfx_shadowSun.z != 0);
#else
    return sun ? sgfx_shadowPcss(tile, t, uv, depth, P)
               : sgfx_shadowPcf(tile, t, uv, depth, P, sgfx_shadowFilter.x, sgfx_shadowSun.z != 0);
#endif
}

// Where the bias and offset come from: a texel of t metres, the surface's normal Ng and the unit
// vector L to the light. A zero normal (point sprites, media, foreign shaders that pass none): no
// offset, and the bias of the steepest slope allowed, as the surface's slope is unknown.
struct SgfxShadowReceiver {
    vec3 moved;  // P moved along the normal
    float bias;  // metres along the light's ray
};
SgfxShadowReceiver sgfx_shadowReceiver(vec3 P, vec3 Ng, vec3 L, float t) {
    float R = max(sgfx_shadowFilter.x, 1.0);
    float cosT = clamp(dot(Ng, L), 0.0, 1.0);
    float sinT = sqrt(1.0 - cosT * cosT);
    float tanT = cosT > 0.0 ? min(sinT / cosT, sgfx_shadowBias.z) : sgfx_shadowBias.z;
    return SgfxShadowReceiver(P + Ng * (sgfx_shadowBias.w * t * (R + 0.5) * sinT),
                              t * (sgfx_shadowBias.x + sgfx_shadowBias.y * R * tanT));
}

float sgfx_shadowCascade(int i, vec3 P, vec3 Ng) {
    float t = sgfx_shadowTexel[i];
    SgfxShadowReceiver r = sgfx_shadowReceiver(P, Ng, sgfx_shadowLight.xyz, t);
    vec3 ls = sgfx_shadowRotation * r.moved; // light space: one rotation for every cascade
    vec4 k = sgfx_shadowCascadeMap[i];
    float depth = ls.z * sgfx_shadowDepthMap.x + sgfx_shadowDepthMap.y;
    return sgfx_shadowFiltered(sgfx_shadowTile[i], t, ls.xy * k.xy + k.zw, depth - r.bias * sgfx_shadowLight.w,
                               r.moved, true);
}

// Which cascade shades view depth z (N when none), and the weight of what follows it.
int sgfx_shadowSelect(float z, out float follow) {
    int n = sgfx_shadowSun.y;
    int i = 0;
    while (i < n && z > sgfx_shadowSplits[i])
        ++i;
    follow = 0.0;
    // smoothstep needs e0 < e1: a band of zero width never blends.
    if (i < n && z > sgfx_shadowBandStart[i])
        follow = smoothstep(sgfx_shadowBandStart[i], sgfx_shadowSplits[i], z);
    return i;
}

// The cascade that holds the point's view depth, faded to lit at the end of the last
// (ShadowMath's selectCascade); across a blend band a pixel takes the next cascade where its
// weight exceeds a hash of the point's light-space cell (a dithered blend: one lookup a pixel,
// anchored to the world; TAA or the PCF disc smooth it); the seed's shadow density.
float sgfx_sunVisibility(vec3 P, vec3 Ng) {
    float follow;
    int i = sgfx_shadowSelect(-(sgfx_view * vec4(P, 1.0)).z, follow);
    int n = sgfx_shadowSun.y;
    if (i >= n) return 1.0;
    vec2 cell = floor((sgfx_shadowRotation * P).xy / sgfx_shadowTexel[i]);
    float dither = fract(52.9829189 * fract(dot(cell, vec2(0.06711056, 0.00583715)))); // Jimenez 2014
    bool next = follow > dither;
    float v = next && i + 1 >= n ? 1.0 : sgfx_shadowCascade(next ? i + 1 : i, P, Ng);
    return 1.0 - sgfx_shadowFilter.w * (1.0 - v);
}

#ifdef SGFX_SHADOW_SPOTS
// Spot slot j: a perspective map; depth along the axis d, a texel of d·2·tan(fovy/2)/S metres,
// the bias subtracted from d before it becomes the map's depth f(d − n)/(d(f − n)).
float sgfx_spotVisibility(int j, vec3 P, vec3 Ng) {
    vec3 pos = sgfx_shadowSpotPos[j].xyz, axis = sgfx_shadowSpotAxis[j].xyz;
    vec4 spot = sgfx_shadowSpot[j];
    float t = max(dot(P - pos, axis), spot.x) * spot.z;
    SgfxShadowReceiver r = sgfx_shadowReceiver(P, Ng, normalize(pos - P), t);
    vec4 c = sgfx_shadowSpotMatrix[j] * vec4(r.moved, 1.0);
    if (c.w <= 0.0) return 1.0; // behind the light
    float d = max(dot(r.moved - pos, axis) - r.bias, spot.x);
    float depth = spot.y * (d - spot.x) / (d * (spot.y - spot.x));
    float v = sgfx_shadowFiltered(sgfx_shadowSpotTile[j], t, c.xy / c.w, depth, r.moved, false);
    return 1.0 - sgfx_shadowFilter.w * (1.0 - v);
}

#endif

// Spots only in the variant that has them (SGFX_SHADOW_SPOTS): a rasterizer that shades blocks of
// pixels together runs every branch a uniform does not rule out at compile time.
float sgfx_lightVisibility(int light, vec3 worldPos, vec3 worldNormal) {
    if (light == sgfx_shadowSun.x) return sgfx_sunVisibility(worldPos, worldNormal);
#ifdef SGFX_SHADOW_SPOTS
    for (int j = 0; j < 3; ++j)
        if (light == sgfx_shadowSpots[j]) return sgfx_spotVisibility(j, worldPos, worldNormal);
#endif
    return 1.0;
}

// The sun's visibility at a world point: the cascade that holds its view depth, blended into the
// next over the band and faded to lit at the end of the last (ShadowMath's selectCascade), with
// the receiver's bias and normal offset (plan §5, ShadowMath's receiverBias and normalOffset).
float sgfx_shadowCascade(int i, vec3 P, vec3 Ng) {
    float t = sgfx_shadowTexel[i];
    float R = max(sgfx_shadowFilter.x, 1.0);
    // A zero normal (point sprites, foreign shaders that pass none): no offset, and the bias of
    // the steepest slope allowed, as the surface's slope is unknown.
    float cosT = clamp(dot(Ng, sgfx_shadowLight.xyz), 0.0, 1.0);
    float sinT = sqrt(1.0 - cosT * cosT);
    vec3 moved = P + Ng * (sgfx_shadowBias.w * t * (R + 0.5) * sinT);
    vec3 s = (sgfx_shadowMatrix[i] * vec4(moved, 1.0)).xyz;
    float tanT = cosT > 0.0 ? min(sinT / cosT, sgfx_shadowBias.z) : sgfx_shadowBias.z;
    float bias = t * (sgfx_shadowBias.x + sgfx_shadowBias.y * R * tanT);
    return sgfx_shadowFiltered(i, s.xy, s.z - bias * sgfx_shadowLight.w, moved);
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

float sgfx_sunVisibility(vec3 P, vec3 Ng) {
    float follow;
    int i = sgfx_shadowSelect(-(sgfx_view * vec4(P, 1.0)).z, follow);
    int n = sgfx_shadowSun.y;
    if (i >= n) return 1.0;
    float v = sgfx_shadowCascade(i, P, Ng);
    if (follow > 0.0) v = mix(v, i + 1 < n ? sgfx_shadowCascade(i + 1, P, Ng) : 1.0, follow);
    return 1.0 - sgfx_shadowFilter.w * (1.0 - v);
}

// The hook of the built-in material's light loops (blinn_phong.frag, SGFX_LIGHT_VISIBILITY).
float sgfx_lightVisibility(int light, vec3 worldPos, vec3 worldNormal) {
    return light == sgfx_shadowSun.x ? sgfx_sunVisibility(worldPos, worldNormal) : 1.0;
}

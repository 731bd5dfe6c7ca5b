// glTF 2.0 metallic-roughness specular lobe (glTF spec, appendix B.3): GGX (Trowbridge-Reitz)
// distribution, height-correlated Smith visibility, Schlick Fresnel. Included by the built-in
// material; compiled only for metallic-roughness variants. Written for llvmpipe, which runs every
// operation for every fragment: H once per light, π cancelled, Schlick's fifth power as products
// (pow is a log2 and an exp2 there) and no select.
#ifdef SGFX_METALLIC_ROUGHNESS
// Schlick's (1 - c)^5 (glTF B.3.4) by multiplication.
float sgfx_schlick5(float c) {
    float x = 1.0 - c;
    float x2 = x * x;
    return x2 * x2 * x;
}

// π·D·Vis from the cosines (glTF B.3.2, B.3.3): π·D = α²/d², d = (N·H)²(α² - 1) + 1; Vis =
// 0.5/(N·L·√((N·V)²(1 - α²) + α²) + N·V·√((N·L)²(1 - α²) + α²)). Finite for N·L = 0 (every caller
// multiplies by N·L). Roughness is perceptual (α = roughness²), clamped so D stays finite.
float sgfx_lobe(float NdotL, float NdotV, float NdotH, float roughness) {
    float alpha = max(roughness, 0.045);
    alpha *= alpha;
    float a2 = alpha * alpha;
    float oneMinusA2 = 1.0 - a2;
    float d = NdotH * NdotH * -oneMinusA2 + 1.0;
    float vis = NdotL * sqrt(NdotV * NdotV * oneMinusA2 + a2) + NdotV * sqrt(NdotL * NdotL * oneMinusA2 + a2);
    return 0.5 * a2 / (d * d * vis);
}

// π·D·Vis, the lobe without Fresnel, times nothing else (the caller multiplies by the light and
// N·L); N·L ≤ 0 gives a finite value that N·L = 0 then cancels.
float brdfLobe(vec3 N, vec3 V, vec3 L, float roughness) {
    vec3 H = normalize(L + V);
    return sgfx_lobe(max(dot(N, L), 0.0), max(dot(N, V), 1e-4), max(dot(N, H), 0.0), roughness);
}

// Returns π·F·D·Vis; F (Schlick, from f0 at normal incidence to f90 at grazing) is returned for
// the diffuse lobe's (1 - F). As brdfLobe, to be multiplied by N·L.
vec3 brdfSpecular(vec3 N, vec3 V, vec3 L, vec3 f0, vec3 f90, float roughness, out vec3 F) {
    vec3 H = normalize(L + V);
    F = f0 + (f90 - f0) * sgfx_schlick5(max(dot(V, H), 0.0));
    return F * sgfx_lobe(max(dot(N, L), 0.0), max(dot(N, V), 1e-4), max(dot(N, H), 0.0), roughness);
}
#endif

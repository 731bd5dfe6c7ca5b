// glTF 2.0 metallic-roughness specular lobe (glTF spec, appendix B.3): GGX (Trowbridge-Reitz)
// distribution, height-correlated Smith visibility, Schlick Fresnel. Included by the built-in
// material; compiled only for metallic-roughness variants.
#ifdef SGFX_METALLIC_ROUGHNESS
const float kPi = 3.14159265358979;

// π·D·Vis, the lobe without Fresnel (the caller multiplies by the light and N·L). Roughness is
// perceptual (α = roughness²), clamped so D stays finite.
float brdfLobe(vec3 N, vec3 V, vec3 L, float roughness) {
    vec3 H = normalize(L + V);
    float NdotL = max(dot(N, L), 0.0);
    float NdotV = max(dot(N, V), 1e-4);
    float NdotH = max(dot(N, H), 0.0);
    float alpha = max(roughness, 0.045);
    alpha *= alpha;
    float a2 = alpha * alpha;
    float d = NdotH * NdotH * (a2 - 1.0) + 1.0;
    float D = a2 / (kPi * d * d);
    float vis = 0.5 / (NdotL * sqrt(NdotV * NdotV * (1.0 - a2) + a2) + NdotV * sqrt(NdotL * NdotL * (1.0 - a2) + a2));
    return NdotL > 0.0 ? kPi * D * vis : 0.0;
}

// Returns π·F·D·Vis; F (Schlick, from f0 at normal incidence to f90 at grazing) is returned for
// the diffuse lobe's (1 - F).
vec3 brdfSpecular(vec3 N, vec3 V, vec3 L, vec3 f0, vec3 f90, float roughness, out vec3 F) {
    float VdotH = max(dot(V, normalize(L + V)), 0.0);
    F = f0 + (f90 - f0) * pow(1.0 - VdotH, 5.0);
    return F * brdfLobe(N, V, L, roughness);
}
#endif

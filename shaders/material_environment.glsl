// Image-based light on the built-in material. EnvironmentLightNode's snippet defines
// SGFX_ENVIRONMENT and the sgfx_environment* functions (nodes/environment/env_light.glsl).
// Split sum (Karis 2013): the specular lobe reflects E = F0·A + F90·B of the light from
// everywhere, and the diffuse layer gets what the lobe does not reflect, (1 − E) (with
// KHR_materials_specular, 1 − max(E), as its lights do).
#ifdef SGFX_ENVIRONMENT
void environmentMetallicRoughness(vec3 N, vec3 V, vec3 diffuseColor, vec3 f0, vec3 f90, float roughness,
                                  inout vec3 color, inout vec3 added) {
    vec2 ab = sgfx_environmentBrdf(max(dot(N, V), 1e-4), roughness);
    vec3 e = f0 * ab.x + f90 * ab.y;
#ifdef SGFX_SPECULAR_EXT
    vec3 scattered = vec3(1.0 - max(e.r, max(e.g, e.b)));
#else
    vec3 scattered = vec3(1.0) - e;
#endif
    color += diffuseColor * scattered * sgfx_environmentDiffuse(N);
    added += e * sgfx_environmentRadiance(reflect(-V, N), roughness);
}

// Blinn-Phong: the diffuse colour under the irradiance, the specular colour on the GGX lobe of
// the same width (α = √(2/(n+2)), EnvironmentMath.h: roughnessFromShininess) without Fresnel.
void environmentBlinnPhong(vec3 N, vec3 V, vec3 diffuse, vec3 specular, float shininess,
                           inout vec3 color, inout vec3 added) {
    color += diffuse * sgfx_environmentDiffuse(N);
#ifdef SGFX_SPECULAR // compiled out, not branched over: llvmpipe would run both sides
    float roughness = sqrt(sqrt(2.0 / (max(shininess, 0.0) + 2.0)));
    vec2 ab = sgfx_environmentBrdf(max(dot(N, V), 1e-4), roughness);
    added += specular * (ab.x + ab.y) * sgfx_environmentRadiance(reflect(-V, N), roughness);
#endif
}
#endif

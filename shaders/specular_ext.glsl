// KHR_materials_specular: the dielectric part's Fresnel from the extension (spec, "Implementation"):
//   F0  = mix(min(F0_ior·specularColor, 1)·specular, base, metallic)  (F0_ior: 0.04 at ior 1.5)
//   F90 = mix(specular, 1, metallic)
// with specular = factor × texture A and specularColor = factor × texture RGB (sRGB).
#ifdef SGFX_SPECULAR_EXT
uniform vec4 sgfx_specularExt; // specularColorFactor, specularFactor

void specularFresnel(vec3 base, float metallic, out vec3 f0, out vec3 f90) {
    float specular = sgfx_specularExt.a * sgfx_extensionMap(sgfx_specularMap, SGFX_MAP_SPECULAR).a;
    vec3 colour = sgfx_specularExt.rgb * sgfx_extensionMap(sgfx_specularColorMap, SGFX_MAP_SPECULAR_COLOR).rgb;
    f0 = mix(min(vec3(sgfx_dielectricF0) * colour, vec3(1.0)) * specular, base, metallic);
    f90 = vec3(mix(specular, 1.0, metallic));
}
#endif

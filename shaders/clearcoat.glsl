// KHR_materials_clearcoat: a dielectric layer (F0 = 0.04, ior 1.5) over the metallic-roughness
// surface, with its own roughness and normal. Spec: coated = base·(1 - clearcoat·Fc) +
// clearcoat·Fc·lobe, Fc = Schlick(0.04, |N_c·V|); the base includes emission and ambient light.
#if defined(SGFX_CLEARCOAT) && !defined(SGFX_VERTEX_LIGHTING) // per-pixel lighting only
uniform vec3 sgfx_clearcoat; // factor, roughness factor, normal scale

struct Clearcoat {
    float weight;    // clearcoat × texture R
    float roughness; // clearcoat roughness × texture G
    vec3 N;          // the layer's normal, facing the viewer's side
    float fresnel;   // Fc
};

Clearcoat clearcoatLayer(vec3 V, vec3 geometricN) {
    Clearcoat c;
    c.weight = sgfx_clearcoat.x * sgfx_extensionMap(sgfx_clearcoatMap, SGFX_MAP_CLEARCOAT).r;
    c.roughness = sgfx_clearcoat.y * sgfx_extensionMap(sgfx_clearcoatRoughnessMap, SGFX_MAP_CLEARCOAT_ROUGHNESS).g;
    c.N = geometricN;
#ifdef SGFX_TEXCOORDS
    if ((sgfx_extensionMaps & (1 << SGFX_MAP_CLEARCOAT_NORMAL)) != 0)
        c.N = sgfx_applyNormalMap(geometricN, sgfx_clearcoatNormalMap, SGFX_MAP_CLEARCOAT_NORMAL, sgfx_clearcoat.z);
#endif
    c.N = gl_FrontFacing ? c.N : -c.N;
    c.fresnel = 0.04 + 0.96 * pow(1.0 - min(abs(dot(c.N, V)), 1.0), 5.0);
    return c;
}
#endif

// KHR_materials_transmission with _volume and _ior, as three.js and Khronos' sample viewer draw it
// (the extensions' implementation notes): the surface lets through the opaque scene behind it,
// read from a copy of that scene (SGFX_UNIT_TRANSMISSION) where the refracted ray leaves the volume,
//   exit = P + normalize(refract(-V, N, 1/ior)) · thickness · modelScale,
// at mip level log2(width) · roughness · clamp(2·ior − 2, 0, 1) (rough glass blurs what it shows;
// at ior 1 the microfacets bend nothing, so it stays sharp), attenuated by Beer–Lambert over the
// path inside, T = attenuationColor^(d / attenuationDistance) (KHR_materials_volume), and tinted
// by the diffuse colour and (1 − F).
#ifdef SGFX_TRANSMISSION
layout(binding = SGFX_UNIT_TRANSMISSION) uniform sampler2D sgfx_transmissionColour;
uniform vec4 sgfx_transmission; // factor, ior, thickness, attenuation distance (0: clear)
uniform vec3 sgfx_attenuationColor;
flat in vec3 v_modelScale; // lengths of the model matrix's columns

float sgfx_transmissionFactor() {
    return sgfx_transmission.x * sgfx_extensionMap(sgfx_transmissionMap, SGFX_MAP_TRANSMISSION).r;
}

// Where the refracted ray leaves the volume (world space); `inside`: the path length there.
vec3 sgfx_transmissionExit(vec3 P, vec3 N, vec3 V, out float inside) {
    float ior = sgfx_transmission.y;
    vec3 dir = ior >= 1.0 ? refract(-V, N, 1.0 / ior) : -V; // ior 0 (F0 = 1): nothing bends
    float thickness = sgfx_transmission.z * sgfx_extensionMap(sgfx_thicknessMap, SGFX_MAP_THICKNESS).g;
    vec3 ray = normalize(dir) * thickness * v_modelScale;
    inside = length(ray);
    return P + ray;
}

// The opaque scene as the eye sees it at the projection of `exit`, blurred for rough surfaces.
vec3 sgfx_transmissionSample(vec3 exit, float roughness) {
    vec4 clip = sgfx_viewProjection * vec4(exit, 1.0);
    vec2 uv = clip.xy / max(clip.w, 1e-6) * 0.5 + 0.5;
    float width = max(float(textureSize(sgfx_transmissionColour, 0).x), 1.0); // no NaN level unbound
    float lod = log2(width) * roughness * clamp(2.0 * sgfx_transmission.y - 2.0, 0.0, 1.0);
    return textureLod(sgfx_transmissionColour, uv, lod).rgb;
}

// Beer–Lambert over `inside` metres of the medium.
vec3 sgfx_volumeAttenuation(vec3 radiance, float inside) {
    if (sgfx_transmission.w <= 0.0) return radiance;
    return radiance * pow(sgfx_attenuationColor, vec3(inside / sgfx_transmission.w));
}
#endif

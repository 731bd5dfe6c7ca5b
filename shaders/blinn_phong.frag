#version 450 core
// Built-in material, fragment stage, in linear colour: Blinn-Phong, glTF's metallic-roughness
// model with SGFX_METALLIC_ROUGHNESS (brdf_metallic_roughness.glsl; its extensions in
// clearcoat.glsl and specular_ext.glsl), or unlit (SGFX_UNLIT); image-based light with
// SGFX_ENVIRONMENT (material_environment.glsl); transmission with SGFX_TRANSMISSION
// (transmission.glsl).
// Hooks: @sgfx:ambient may change sgfx_ambient (ambient light) and sgfx_indirect (scales all
// indirect light: ambient and environment); @sgfx:transmitted may change sgfx_transmitted (the
// scene seen through a transmissive surface, as the eye sees it, into what reaches the surface:
// fog takes its own share out); @sgfx:color may change sgfx_color.
// Feature defines (SGFX_BASE_MAP, SGFX_ALPHA_MAP, SGFX_NORMAL_MAP, SGFX_VERTEX_COLOR,
// SGFX_NORMALS, SGFX_TANGENTS, SGFX_ALPHA_MASK, SGFX_BLEND, ...) are set per variant: a material
// without an alpha mask has no `discard`, so the rasterizer keeps early depth rejection.
#ifdef SGFX_WORLD_POSITION
in vec3 v_worldPos; // only when something reads it: every varying costs per fragment
#endif
#ifdef SGFX_NORMALS
in vec3 v_worldNormal;
#endif
#ifdef SGFX_TANGENTS
in vec4 v_worldTangent;
#endif
#ifdef SGFX_TEXCOORDS
#ifdef SGFX_POINT_SPRITE
#define v_texcoord gl_PointCoord // a base drawing point sprites: the texture runs over the point
#else
in vec2 v_texcoord;
#endif
#endif
#ifdef SGFX_TEXCOORDS1
in vec2 v_texcoord1;
#endif
#ifdef SGFX_VERTEX_COLOR
in vec4 v_color;
#endif

#ifdef SGFX_VERTEX_LIGHTING
in vec3 v_diffuseFront;
in vec3 v_diffuseBack;
#ifdef SGFX_SPECULAR
in vec3 v_specularFront;
in vec3 v_specularBack;
#endif
#endif

uniform vec3 sgfx_matAmbient;
uniform vec4 sgfx_matDiffuse;
uniform vec3 sgfx_matSpecular;
uniform float sgfx_matShininess;
uniform vec3 sgfx_matEmissive;
uniform float sgfx_alphaCutoff;
uniform vec2 sgfx_matMetallicRoughness;
uniform float sgfx_normalScale;
uniform float sgfx_occlusionStrength;

// Units (and uv indices) SGFX_MAP_* come from the composer (the renderer's TextureUnits.h).
layout(binding = SGFX_MAP_BASE_COLOR) uniform sampler2D sgfx_baseColorMap;
layout(binding = SGFX_MAP_ALPHA) uniform sampler2D sgfx_alphaMap;
layout(binding = SGFX_MAP_NORMAL) uniform sampler2D sgfx_normalMap;
layout(binding = SGFX_MAP_METAL_ROUGH) uniform sampler2D sgfx_metalRoughMap;
layout(binding = SGFX_MAP_OCCLUSION) uniform sampler2D sgfx_occlusionMap;
layout(binding = SGFX_MAP_EMISSIVE) uniform sampler2D sgfx_emissiveMap;
layout(binding = SGFX_MAP_CLEARCOAT) uniform sampler2D sgfx_clearcoatMap;
layout(binding = SGFX_MAP_CLEARCOAT_ROUGHNESS) uniform sampler2D sgfx_clearcoatRoughnessMap;
layout(binding = SGFX_MAP_CLEARCOAT_NORMAL) uniform sampler2D sgfx_clearcoatNormalMap;
layout(binding = SGFX_MAP_SPECULAR) uniform sampler2D sgfx_specularMap;
layout(binding = SGFX_MAP_SPECULAR_COLOR) uniform sampler2D sgfx_specularColorMap;
layout(binding = SGFX_MAP_TRANSMISSION) uniform sampler2D sgfx_transmissionMap;
layout(binding = SGFX_MAP_THICKNESS) uniform sampler2D sgfx_thicknessMap;
uniform float sgfx_dielectricF0; // KHR_materials_ior: ((ior - 1)/(ior + 1))², 0.04 at 1.5

// Texture coordinates of a map (Material::mappings, indexed by MaterialMap): its set,
// transformed (KHR_texture_transform).
#ifdef SGFX_UV_TRANSFORM
uniform mat3 sgfx_uvTransform[SGFX_MAP_COUNT];
uniform int sgfx_uvSet[SGFX_MAP_COUNT];
vec2 sgfx_uv(int map) {
#ifdef SGFX_TEXCOORDS1
    vec2 uv = sgfx_uvSet[map] == 1 ? v_texcoord1 : v_texcoord;
#else
    vec2 uv = v_texcoord;
#endif
    return (sgfx_uvTransform[map] * vec3(uv, 1.0)).xy;
}
#else
#define sgfx_uv(map) v_texcoord
#endif

// The maps of KHR_materials_clearcoat, _specular, _transmission and _volume are chosen per
// material by a uniform (bit = MaterialMap index), not per variant; an absent map reads as 1.
#if defined(SGFX_CLEARCOAT) || defined(SGFX_SPECULAR_EXT) || defined(SGFX_TRANSMISSION)
uniform int sgfx_extensionMaps;
vec4 sgfx_extensionMap(sampler2D map, int index) {
#ifdef SGFX_TEXCOORDS
    if ((sgfx_extensionMaps & (1 << index)) != 0) return texture(map, sgfx_uv(index));
#endif
    return vec4(1.0);
}
#endif

layout(location = 0) out vec4 sgfx_fragColor;
#ifdef SGFX_GBUFFER
// G-buffer variant (pre-passes such as ambient occlusion): location 0 holds the view-space normal.
layout(location = 1) out vec4 sgfx_gDepth;    // linear view depth, metres
layout(location = 2) out vec4 sgfx_gPosition; // view-space position
#endif

// @sgfx:fragment_decl

#include "brdf_metallic_roughness.glsl"
#include "material_environment.glsl"
#include "lights.glsl"

#if !defined(SGFX_VERTEX_LIGHTING) || defined(SGFX_ENVIRONMENT) || defined(SGFX_TRANSMISSION)
// The interpolated normal (or the triangle's), not yet turned towards the viewer's side.
vec3 sgfx_geometricNormal() {
#ifdef SGFX_NORMALS
    vec3 N = normalize(v_worldNormal);
#else
    // Flat shading from the triangle's plane when the geometry has no normals; a sliver with
    // parallel derivatives (a zero cross product) faces the eye rather than normalising zero.
    vec3 c = cross(dFdx(v_worldPos), dFdy(v_worldPos));
    float c2 = dot(c, c);
    vec3 N = c2 > 1e-30 ? c * inversesqrt(c2) : sgfx_eye.xyz - v_worldPos;
    N = dot(N, N) > 1e-30 ? normalize(N) : vec3(0.0, 0.0, 1.0);
#endif
    return N;
}

#if defined(SGFX_TEXCOORDS) && (defined(SGFX_NORMAL_MAP) || defined(SGFX_CLEARCOAT))
// A tangent-space normal map (Material map `index`) applied to the normal N.
vec3 sgfx_applyNormalMap(vec3 N, sampler2D map, int index, float scale) {
    vec3 T, B;
#ifdef SGFX_TANGENTS
    T = normalize(v_worldTangent.xyz - N * dot(N, v_worldTangent.xyz));
    B = cross(N, T) * v_worldTangent.w;
#else
    // Tangent frame from screen-space derivatives of position and texcoord.
    vec3 dpdx = dFdx(v_worldPos), dpdy = dFdy(v_worldPos);
    vec2 dtx = dFdx(sgfx_uv(index)), dty = dFdy(sgfx_uv(index));
    // T = dP/du. glTF's bitangent points up the image, where v falls (v = 0 is the top row), so
    // B = -dP/dv: the same frame as supplied TANGENTs with MikkTSpace's rules.
    float det = dtx.x * dty.y - dty.x * dtx.y;
    vec3 t = (dpdx * dty.y - dpdy * dtx.y) * (det < 0.0 ? -1.0 : 1.0);
    T = normalize(t - N * dot(N, t));
    B = cross(N, T) * (det < 0.0 ? 1.0 : -1.0);
#endif
    vec3 m = texture(map, sgfx_uv(index)).xyz * 2.0 - 1.0;
    m.xy *= scale;
    return normalize(mat3(T, B, N) * m);
}
#endif

vec3 surfaceNormal() {
    vec3 N = sgfx_geometricNormal();
#if defined(SGFX_NORMAL_MAP) && defined(SGFX_TEXCOORDS)
    N = sgfx_applyNormalMap(N, sgfx_normalMap, SGFX_MAP_NORMAL, sgfx_normalScale);
#endif
    return gl_FrontFacing ? N : -N;
}
#endif

#include "clearcoat.glsl"
#include "specular_ext.glsl"
#include "transmission.glsl"

#ifndef SGFX_VERTEX_LIGHTING
// What a light needs of the surface, the same for the unrolled loop and the light list.
struct SgfxSurface {
    vec3 N, V, albedo, f0, f90;
    float roughness;
    vec3 coatN; // KHR_materials_clearcoat: the layer's normal and roughness (unused without it)
    float coatRoughness;
};

// Adds one light: E, its colour times its attenuation, arriving along the unit vector L.
// Light colours are irradiance over π (a white Lambert surface facing a light shows its colour,
// as with Blinn-Phong), so both metallic-roughness lobes are multiplied by π. coatLight gathers
// what the clearcoat layer reflects.
void sgfx_addLight(vec3 E, vec3 L, SgfxSurface s, inout vec3 color, inout vec3 added, inout vec3 coatLight) {
    float NdotL = max(dot(s.N, L), 0.0);
#ifdef SGFX_METALLIC_ROUGHNESS
    vec3 F;
    vec3 specular = brdfSpecular(s.N, s.V, L, s.f0, s.f90, s.roughness, F);
#ifdef SGFX_SPECULAR_EXT
    vec3 scattered = vec3(1.0 - max(F.r, max(F.g, F.b))); // the extension's (1 - max(F))
#else
    vec3 scattered = vec3(1.0) - F;
#endif
    color += E * NdotL * scattered * s.albedo;
    added += E * NdotL * specular;
#ifdef SGFX_CLEARCOAT
    coatLight += E * max(dot(s.coatN, L), 0.0) * brdfLobe(s.coatN, s.V, L, s.coatRoughness);
#endif
#else
    color += E * s.albedo * NdotL;
#ifdef SGFX_SPECULAR
    vec3 H = normalize(L + s.V);
    added += NdotL > 0.0 ? E * sgfx_matSpecular * pow(max(dot(s.N, H), 0.0), sgfx_matShininess) : vec3(0.0);
#endif
#endif
}

#ifdef SGFX_LIGHT_VISIBILITY
// The share of light `light` (its index in the view) that reaches this point, from an effect's
// sgfx_lightVisibility (shadows). It gets the interpolated normal turned towards the light, the
// direction its normal offset moves the point along; normal maps do not move shadows.
float sgfx_visibility(int light, vec3 L) {
    vec3 Ng = sgfx_geometricNormal();
    return sgfx_lightVisibility(light, v_worldPos, dot(Ng, L) < 0.0 ? -Ng : Ng);
}
#endif

#ifdef SGFX_LIGHT_LIST
void sgfx_addListedLight(int i, SgfxSurface s, inout vec3 color, inout vec3 added, inout vec3 coatLight) {
    vec3 L;
    float k = sgfx_lightFactor(sgfx_lights[i].vector, sgfx_lights[i].color, sgfx_lights[i].spot,
                               sgfx_lights[i].params, v_worldPos, L);
    if (k <= 0.0) return;
    vec3 E = sgfx_lights[i].color.rgb * k;
#ifdef SGFX_LIGHT_VISIBILITY
    if (dot(s.N, L) > 0.0) E *= sgfx_visibility(int(sgfx_lights[i].params.z), L);
#endif
    sgfx_addLight(E, L, s, color, added, coatLight);
}

// The lights without a range, then the ranged lights listed for this fragment's screen tile.
void sgfx_addLightList(SgfxSurface s, inout vec3 color, inout vec3 added, inout vec3 coatLight) {
    for (int i = 0; i < sgfx_lightCount.y; ++i)
        sgfx_addListedLight(i, s, color, added, coatLight);
    ivec2 tile = ivec2(gl_FragCoord.xy) / sgfx_lightCount.w;
    int t = tile.y * sgfx_lightCount.z + tile.x;
    uint first = sgfx_lightTiles[2 * t], count = sgfx_lightTiles[2 * t + 1];
    for (uint k = 0u; k < count; ++k)
        sgfx_addListedLight(int(sgfx_lightTiles[first + k]), s, color, added, coatLight);
}
#endif
#endif

void main() {
#if defined(SGFX_DEBUG_CONSTANT) && !defined(SGFX_GBUFFER)
    sgfx_fragColor = vec4(sgfx_matDiffuse.rgb, 1.0); // profiling floor: raster, depth and store only
    return;
#endif
    vec4 base = sgfx_matDiffuse;
    vec3 ambientColor = sgfx_matAmbient;
#ifdef SGFX_VERTEX_COLOR
    base *= v_color;
    ambientColor *= v_color.rgb;
#endif
#if defined(SGFX_BASE_MAP) && defined(SGFX_TEXCOORDS)
    vec4 t = texture(sgfx_baseColorMap, sgfx_uv(SGFX_MAP_BASE_COLOR));
    base *= t;
    ambientColor *= t.rgb;
#endif
#if defined(SGFX_ALPHA_MAP) && defined(SGFX_TEXCOORDS)
    base.a *= texture(sgfx_alphaMap, sgfx_uv(SGFX_MAP_ALPHA)).r;
#endif
    float sgfx_coverage = 1.0; // scales all the surface adds, emission and highlights included
#if defined(SGFX_BASE_MODIFIER) && !defined(SGFX_GBUFFER)
    // A base shader built on this material may adjust the surface colour and its coverage here
    // by defining SGFX_BASE_MODIFIER and `void sgfx_modifyBase(inout vec4 base, inout float
    // coverage)` (soft particles).
    sgfx_modifyBase(base, sgfx_coverage);
#endif
#ifdef SGFX_ALPHA_MASK
    if (base.a < sgfx_alphaCutoff) discard;
    base.a = 1.0; // what passes the mask is opaque
#endif
#ifndef SGFX_BLEND
    base.a = 1.0; // opaque surfaces write opaque pixels whatever the material's alpha
#endif
#ifdef SGFX_GBUFFER
#if defined(SGFX_ALPHA_MAP) && defined(SGFX_TEXCOORDS) && !defined(SGFX_ALPHA_MASK)
    // SSAO seed §1: texels of an alpha map below ε cut holes in the G-buffer.
    if (texture(sgfx_alphaMap, sgfx_uv(SGFX_MAP_ALPHA)).r < 1.0 / 255.0) discard;
#endif
    vec4 gView = sgfx_view * vec4(v_worldPos, 1.0);
    sgfx_fragColor = vec4(normalize(mat3(sgfx_view) * surfaceNormal()), 0.0); // seed §1: N_vcs
    sgfx_gDepth = vec4(-gView.z);
    sgfx_gPosition = vec4(gView.xyz, 1.0);
    return;
#endif

    vec3 sgfx_ambient = sgfx_ambientLight.rgb;
#ifdef SGFX_WORLD_POSITION
    vec3 sgfx_worldPos = v_worldPos;
#else
    vec3 sgfx_worldPos = vec3(0.0); // no snippet or light of this variant reads it
#endif
    vec3 sgfx_eyePos = sgfx_eye.xyz;
    float sgfx_indirect = 1.0;
    // @sgfx:ambient
#ifdef SGFX_UNLIT
    // KHR_materials_unlit: the base colour alone, whatever the lights.
    vec3 color = base.rgb;
    vec3 added = vec3(0.0);
#else
#ifdef SGFX_METALLIC_ROUGHNESS
    float metallic = sgfx_matMetallicRoughness.x;
    float roughness = sgfx_matMetallicRoughness.y;
#ifdef SGFX_METAL_ROUGH_MAP
    vec4 metalRough = texture(sgfx_metalRoughMap, sgfx_uv(SGFX_MAP_METAL_ROUGH));
    roughness *= metalRough.g;
    metallic *= metalRough.b;
#endif
    vec3 diffuseColor = mix(base.rgb, vec3(0.0), metallic);
    vec3 f0 = mix(vec3(sgfx_dielectricF0), base.rgb, metallic);
    vec3 f90 = vec3(1.0);
#ifdef SGFX_SPECULAR_EXT
    specularFresnel(base.rgb, metallic, f0, f90);
#endif
    // Ambient light has no direction: it lights the diffuse colour plus F0 as a mirror would.
    ambientColor = diffuseColor + f0;
#endif
#ifdef SGFX_OCCLUSION_MAP
    // glTF occlusion: darkens indirect (ambient and environment) light only.
    sgfx_indirect *= 1.0 + sgfx_occlusionStrength * (texture(sgfx_occlusionMap, sgfx_uv(SGFX_MAP_OCCLUSION)).r - 1.0);
#endif
    // Light the surface scatters (scaled by its coverage when the output is premultiplied) and
    // light it adds on top (emission, specular reflection: glass keeps its highlights).
    vec3 color = sgfx_indirect * sgfx_ambient * ambientColor;
    vec3 added = sgfx_matEmissive;
#ifdef SGFX_EMISSIVE_MAP
    added *= texture(sgfx_emissiveMap, sgfx_uv(SGFX_MAP_EMISSIVE)).rgb;
#endif
#ifdef SGFX_VERTEX_LIGHTING
#ifdef SGFX_METALLIC_ROUGHNESS
    // Gouraud: Lambert on the diffuse colour, F0 times a Blinn-Phong lobe of the same width.
    color += diffuseColor * (gl_FrontFacing ? v_diffuseFront : v_diffuseBack);
    added += f0 * (gl_FrontFacing ? v_specularFront : v_specularBack);
#else
    color += base.rgb * (gl_FrontFacing ? v_diffuseFront : v_diffuseBack);
#ifdef SGFX_SPECULAR
    added += sgfx_matSpecular * (gl_FrontFacing ? v_specularFront : v_specularBack);
#endif
#endif
#else
    vec3 N = surfaceNormal();
#if defined(SGFX_SPECULAR) || defined(SGFX_METALLIC_ROUGHNESS)
    vec3 V = normalize(sgfx_eye.xyz - v_worldPos);
#else
    vec3 V = vec3(0.0);
#endif
#ifdef SGFX_CLEARCOAT
    Clearcoat coat = clearcoatLayer(V, sgfx_geometricNormal());
    vec3 coatLight = sgfx_indirect * sgfx_ambient; // the layer mirrors ambient light like the base's F0 term
    vec3 coatN = coat.N;
    float coatRoughness = coat.roughness;
#else
    vec3 coatLight = vec3(0.0), coatN = N;
    float coatRoughness = 1.0;
#endif
#ifdef SGFX_METALLIC_ROUGHNESS
    SgfxSurface surface = SgfxSurface(N, V, diffuseColor, f0, f90, roughness, coatN, coatRoughness);
#else
    SgfxSurface surface = SgfxSurface(N, V, base.rgb, vec3(0.0), vec3(1.0), 0.0, coatN, coatRoughness);
#endif
#ifdef SGFX_LIGHT_LIST
    sgfx_addLightList(surface, color, added, coatLight);
#else
    // SGFX_LIGHT_COUNT is the number of lights in the view, compiled in so the loop unrolls.
    for (int i = 0; i < SGFX_LIGHT_COUNT; ++i) {
        vec4 lv = sgfx_lightVector[i];
        vec3 E = sgfx_lightColor[i].rgb;
#if defined(SGFX_LIGHT_ATTENUATION)
        vec3 L;
        float k = sgfx_lightFactor(lv, sgfx_lights[i].color, sgfx_lights[i].spot, sgfx_lights[i].params, v_worldPos, L);
        if (k <= 0.0) continue; // out of range or outside the cone: no shading
        E *= k;
#elif defined(SGFX_POINT_LIGHTS)
        vec3 L = normalize(lv.xyz - lv.w * v_worldPos); // w = 0: direction, w = 1: position
#else
        vec3 L = lv.xyz; // directions come normalised
#endif
#ifdef SGFX_LIGHT_VISIBILITY
        if (dot(surface.N, L) > 0.0) E *= sgfx_visibility(i, L);
#endif
        sgfx_addLight(E, L, surface, color, added, coatLight);
    }
#endif // SGFX_LIGHT_LIST
#ifdef SGFX_CLEARCOAT
    float coatWeight = coat.weight * coat.fresnel;
    color *= 1.0 - coatWeight;
    added = added * (1.0 - coatWeight) + coatWeight * coatLight;
#endif
#endif // SGFX_VERTEX_LIGHTING
#ifdef SGFX_ENVIRONMENT
#ifdef SGFX_VERTEX_LIGHTING
    vec3 envN = surfaceNormal();
#else
    vec3 envN = N;
#endif
    vec3 envV = normalize(sgfx_eye.xyz - v_worldPos);
    vec3 envColor = vec3(0.0), envAdded = vec3(0.0);
#ifdef SGFX_METALLIC_ROUGHNESS
    environmentMetallicRoughness(envN, envV, diffuseColor, f0, f90, roughness, envColor, envAdded);
#else
    environmentBlinnPhong(envN, envV, base.rgb, sgfx_matSpecular, sgfx_matShininess, envColor, envAdded);
#endif
#if defined(SGFX_CLEARCOAT) && !defined(SGFX_VERTEX_LIGHTING)
    // The coat darkens the light under it and mirrors the environment at its own normal and
    // roughness, as it does the lights: its lobe without Fresnel reflects A + B of it (split sum).
    envColor *= 1.0 - coatWeight;
    vec2 coatAB = sgfx_environmentBrdf(max(dot(coat.N, envV), 1e-4), coat.roughness);
    envAdded = envAdded * (1.0 - coatWeight) +
               coatWeight * (coatAB.x + coatAB.y) * sgfx_environmentRadiance(reflect(-envV, coat.N), coat.roughness);
#endif
    color += sgfx_indirect * envColor;
    added += sgfx_indirect * envAdded;
#endif
#ifdef SGFX_TRANSMISSION
    {
        // The diffuse part lets the scene behind through (transmission.glsl), less what the
        // surface reflects at this angle (Schlick's F at N·V) and what a clearcoat takes.
        vec3 tN = surfaceNormal();
        vec3 tV = normalize(sgfx_eye.xyz - v_worldPos);
        float inside;
        vec3 sgfx_transmitted = sgfx_transmissionSample(sgfx_transmissionExit(v_worldPos, tN, tV, inside), roughness);
        // @sgfx:transmitted
        vec3 F = f0 + (f90 - f0) * pow(1.0 - max(dot(tN, tV), 0.0), 5.0);
        vec3 through = (1.0 - F) * diffuseColor * sgfx_volumeAttenuation(sgfx_transmitted, inside);
#if defined(SGFX_CLEARCOAT) && !defined(SGFX_VERTEX_LIGHTING)
        through *= 1.0 - coatWeight;
#endif
        color = mix(color, through, sgfx_transmissionFactor());
    }
#endif
#endif // SGFX_UNLIT
    // Premultiplied output (SGFX_BLEND_PREMULTIPLIED): colour effects at the hook below see and
    // keep premultiplied colour.
#ifdef SGFX_BLEND_PREMULTIPLIED
    vec4 sgfx_color = vec4(color * base.a + added, base.a);
#else
    vec4 sgfx_color = vec4(color + added, base.a);
#endif
#ifdef SGFX_BLEND_PREMULTIPLIED
    sgfx_color *= sgfx_coverage;
#else
    sgfx_color.a *= sgfx_coverage;
#endif
    // @sgfx:color
    sgfx_fragColor = sgfx_color;
}

#version 450 core
// Built-in material, fragment stage, in linear colour: Blinn-Phong, or glTF's metallic-roughness
// model with SGFX_METALLIC_ROUGHNESS (brdf_metallic_roughness.glsl).
// Hooks: @sgfx:ambient may change sgfx_ambient (ambient light) and sgfx_indirect (scales all
// indirect light: ambient and environment); @sgfx:color may change sgfx_color.
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

layout(binding = 0) uniform sampler2D sgfx_baseColorMap;
layout(binding = 1) uniform sampler2D sgfx_alphaMap;
layout(binding = 2) uniform sampler2D sgfx_normalMap;
layout(binding = 3) uniform sampler2D sgfx_metalRoughMap;
layout(binding = 4) uniform sampler2D sgfx_occlusionMap;
layout(binding = 5) uniform sampler2D sgfx_emissiveMap;

// Texture coordinates of a map (Material::mappings: 0 base, 1 alpha, 2 normal, 3 metallic-
// roughness, 4 occlusion, 5 emissive): its set, transformed (KHR_texture_transform).
#ifdef SGFX_UV_TRANSFORM
uniform mat3 sgfx_uvTransform[6];
uniform int sgfx_uvSet[6];
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

#ifndef SGFX_VERTEX_LIGHTING
// Adds one light: E, its colour times its attenuation, arriving along the unit vector L.
// Light colours are irradiance over π (a white Lambert surface facing a light shows its colour,
// as with Blinn-Phong), so both metallic-roughness lobes are multiplied by π.
void sgfx_addLight(vec3 E, vec3 L, vec3 N, vec3 V, vec3 albedo, vec3 f0, float roughness, inout vec3 color,
                   inout vec3 added) {
    float NdotL = max(dot(N, L), 0.0);
#ifdef SGFX_METALLIC_ROUGHNESS
    vec3 F;
    vec3 specular = brdfSpecular(N, V, L, f0, roughness, F);
    color += E * NdotL * (vec3(1.0) - F) * albedo;
    added += E * NdotL * specular;
#else
    color += E * albedo * NdotL;
#ifdef SGFX_SPECULAR
    vec3 H = normalize(L + V);
    added += NdotL > 0.0 ? E * sgfx_matSpecular * pow(max(dot(N, H), 0.0), sgfx_matShininess) : vec3(0.0);
#endif
#endif
}

#ifdef SGFX_LIGHT_LIST
void sgfx_addListedLight(int i, vec3 N, vec3 V, vec3 albedo, vec3 f0, float roughness, inout vec3 color,
                         inout vec3 added) {
    vec3 L;
    float k = sgfx_lightFactor(sgfx_lights[i].vector, sgfx_lights[i].color, sgfx_lights[i].spot,
                               sgfx_lights[i].params, v_worldPos, L);
    if (k > 0.0) sgfx_addLight(sgfx_lights[i].color.rgb * k, L, N, V, albedo, f0, roughness, color, added);
}

// The lights without a range, then the ranged lights listed for this fragment's screen tile.
void sgfx_addLightList(vec3 N, vec3 V, vec3 albedo, vec3 f0, float roughness, inout vec3 color, inout vec3 added) {
    for (int i = 0; i < sgfx_lightCount.y; ++i)
        sgfx_addListedLight(i, N, V, albedo, f0, roughness, color, added);
    ivec2 tile = ivec2(gl_FragCoord.xy) / sgfx_lightCount.w;
    int t = tile.y * sgfx_lightCount.z + tile.x;
    uint first = sgfx_lightTiles[2 * t], count = sgfx_lightTiles[2 * t + 1];
    for (uint k = 0u; k < count; ++k)
        sgfx_addListedLight(int(sgfx_lightTiles[first + k]), N, V, albedo, f0, roughness, color, added);
}
#endif
#endif

#if !defined(SGFX_VERTEX_LIGHTING) || defined(SGFX_ENVIRONMENT)
vec3 surfaceNormal() {
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
#if defined(SGFX_NORMAL_MAP) && defined(SGFX_TEXCOORDS)
    vec3 T, B;
#ifdef SGFX_TANGENTS
    T = normalize(v_worldTangent.xyz - N * dot(N, v_worldTangent.xyz));
    B = cross(N, T) * v_worldTangent.w;
#else
    // Tangent frame from screen-space derivatives of position and texcoord.
    vec3 dpdx = dFdx(v_worldPos), dpdy = dFdy(v_worldPos);
    vec2 dtx = dFdx(sgfx_uv(2)), dty = dFdy(sgfx_uv(2));
    // T = dP/du. glTF's bitangent points up the image, where v falls (v = 0 is the top row), so
    // B = -dP/dv: the same frame as supplied TANGENTs with MikkTSpace's rules.
    float det = dtx.x * dty.y - dty.x * dtx.y;
    vec3 t = (dpdx * dty.y - dpdy * dtx.y) * (det < 0.0 ? -1.0 : 1.0);
    T = normalize(t - N * dot(N, t));
    B = cross(N, T) * (det < 0.0 ? 1.0 : -1.0);
#endif
    vec3 m = texture(sgfx_normalMap, sgfx_uv(2)).xyz * 2.0 - 1.0;
    m.xy *= sgfx_normalScale;
    N = normalize(mat3(T, B, N) * m);
#endif
    return gl_FrontFacing ? N : -N;
}
#endif

void main() {
    vec4 base = sgfx_matDiffuse;
    vec3 ambientColor = sgfx_matAmbient;
#ifdef SGFX_VERTEX_COLOR
    base *= v_color;
    ambientColor *= v_color.rgb;
#endif
#if defined(SGFX_BASE_MAP) && defined(SGFX_TEXCOORDS)
    vec4 t = texture(sgfx_baseColorMap, sgfx_uv(0));
    base *= t;
    ambientColor *= t.rgb;
#endif
#if defined(SGFX_ALPHA_MAP) && defined(SGFX_TEXCOORDS)
    base.a *= texture(sgfx_alphaMap, sgfx_uv(1)).r;
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
    if (texture(sgfx_alphaMap, sgfx_uv(1)).r < 1.0 / 255.0) discard;
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
#ifdef SGFX_METALLIC_ROUGHNESS
    float metallic = sgfx_matMetallicRoughness.x;
    float roughness = sgfx_matMetallicRoughness.y;
#ifdef SGFX_METAL_ROUGH_MAP
    vec4 metalRough = texture(sgfx_metalRoughMap, sgfx_uv(3));
    roughness *= metalRough.g;
    metallic *= metalRough.b;
#endif
    vec3 diffuseColor = mix(base.rgb, vec3(0.0), metallic);
    vec3 f0 = mix(vec3(0.04), base.rgb, metallic);
    // Ambient light has no direction: it lights the diffuse colour plus F0 as a mirror would.
    ambientColor = diffuseColor + f0;
#endif
#ifdef SGFX_OCCLUSION_MAP
    // glTF occlusion: darkens indirect (ambient and environment) light only.
    sgfx_indirect *= 1.0 + sgfx_occlusionStrength * (texture(sgfx_occlusionMap, sgfx_uv(4)).r - 1.0);
#endif
    // Light the surface scatters (scaled by its coverage when the output is premultiplied) and
    // light it adds on top (emission, specular reflection: glass keeps its highlights).
    vec3 color = sgfx_indirect * sgfx_ambient * ambientColor;
    vec3 added = sgfx_matEmissive;
#ifdef SGFX_EMISSIVE_MAP
    added *= texture(sgfx_emissiveMap, sgfx_uv(5)).rgb;
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
#ifdef SGFX_METALLIC_ROUGHNESS
    vec3 albedo = diffuseColor;
#else
    vec3 albedo = base.rgb, f0 = vec3(0.0);
    float roughness = 0.0;
#endif
#ifdef SGFX_LIGHT_LIST
    sgfx_addLightList(N, V, albedo, f0, roughness, color, added);
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
        sgfx_addLight(E, L, N, V, albedo, f0, roughness, color, added);
    }
#endif
#endif
#ifdef SGFX_ENVIRONMENT
#ifdef SGFX_VERTEX_LIGHTING
    vec3 envN = surfaceNormal();
#else
    vec3 envN = N;
#endif
    vec3 envColor = vec3(0.0), envAdded = vec3(0.0);
#ifdef SGFX_METALLIC_ROUGHNESS
    environmentMetallicRoughness(envN, normalize(sgfx_eye.xyz - v_worldPos), diffuseColor, f0, roughness, envColor,
                                 envAdded);
#else
    environmentBlinnPhong(envN, normalize(sgfx_eye.xyz - v_worldPos), base.rgb, sgfx_matSpecular, sgfx_matShininess,
                          envColor, envAdded);
#endif
    color += sgfx_indirect * envColor;
    added += sgfx_indirect * envAdded;
#endif
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

#version 450 core
// Built-in material, vertex stage. Effects hook in at @sgfx:vertex with the world position,
// world normal and view position in hand. SGFX_* feature defines select what is passed on, so
// a plain material interpolates no attribute it does not use.
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec4 a_tangent;
layout(location = 3) in vec2 a_texcoord;
layout(location = 4) in vec4 a_color;
layout(location = 5) in vec2 a_texcoord1;
#ifdef SGFX_INSTANCED
layout(location = 6) in mat4 a_instance; // Geometry::instances, applied before sgfx_model
#endif
#ifdef SGFX_BATCHED
// Automatic instance batches: the renderer draws repeated meshes in one call, their model
// matrices in this buffer (binding = sgfx::kBatchBinding).
layout(std430, binding = 7) readonly buffer SgfxBatchModels {
    mat4 sgfx_batchModels[];
};
uniform int sgfx_batchBase;
#endif

uniform mat4 sgfx_model;
uniform mat3 sgfx_normalMatrix;

#ifdef SGFX_TRANSMISSION
flat out vec3 v_modelScale; // transmission.glsl: the volume's thickness scales with the model
#endif
#ifdef SGFX_WORLD_POSITION
out vec3 v_worldPos;
#endif
#ifdef SGFX_NORMALS
out vec3 v_worldNormal;
#endif
#ifdef SGFX_TANGENTS
out vec4 v_worldTangent;
#endif
#ifdef SGFX_TEXCOORDS
out vec2 v_texcoord;
#endif
#ifdef SGFX_TEXCOORDS1
out vec2 v_texcoord1;
#endif
#ifdef SGFX_VERTEX_COLOR
out vec4 v_color;
#endif

#include "lights.glsl"
#include "pose.glsl"

#ifdef SGFX_VERTEX_LIGHTING
// Gouraud option: light sums per vertex, for both faces (two-sided surfaces pick per fragment).
// With the light list (SGFX_LIGHT_LIST) every listed light is summed: a vertex has no tile.
uniform float sgfx_matShininess;
out vec3 v_diffuseFront;
out vec3 v_diffuseBack;
#ifdef SGFX_SPECULAR
out vec3 v_specularFront;
out vec3 v_specularBack;
#endif
// One light: E, its colour times its attenuation, arriving along the unit vector L.
void vertexLight(vec3 E, vec3 L, vec3 N, vec3 V) {
    float d = dot(N, L);
    v_diffuseFront += E * max(d, 0.0);
    v_diffuseBack += E * max(-d, 0.0);
#ifdef SGFX_SPECULAR
    float h = dot(N, normalize(L + V));
    v_specularFront += d > 0.0 ? E * pow(max(h, 0.0), sgfx_matShininess) : vec3(0.0);
    v_specularBack += d < 0.0 ? E * pow(max(-h, 0.0), sgfx_matShininess) : vec3(0.0);
#endif
}
void vertexLighting(vec3 P, vec3 N) {
    v_diffuseFront = vec3(0.0);
    v_diffuseBack = vec3(0.0);
#ifdef SGFX_SPECULAR
    v_specularFront = vec3(0.0);
    v_specularBack = vec3(0.0);
    vec3 V = normalize(sgfx_eye.xyz - P);
#else
    vec3 V = vec3(0.0);
#endif
#ifdef SGFX_LIGHT_LIST
    for (int i = 0; i < sgfx_lights.length(); ++i) {
        vec3 L;
        float k = sgfx_lightFactor(sgfx_lights[i].vector, sgfx_lights[i].color, sgfx_lights[i].spot,
                                   sgfx_lights[i].params, P, L);
        if (k > 0.0) vertexLight(sgfx_lights[i].color.rgb * k, L, N, V);
    }
#else
    for (int i = 0; i < SGFX_LIGHT_COUNT; ++i) {
        vec4 lv = sgfx_lightVector[i];
#ifdef SGFX_LIGHT_ATTENUATION
        vec3 L;
        vec3 E = sgfx_lightColor[i].rgb *
                 sgfx_lightFactor(lv, sgfx_lights[i].color, sgfx_lights[i].spot, sgfx_lights[i].params, P, L);
#else
        vec3 L = normalize(lv.xyz - lv.w * P);
        vec3 E = sgfx_lightColor[i].rgb;
#endif
        vertexLight(E, L, N, V);
    }
#endif
}
#endif

// @sgfx:vertex_decl

void main() {
#if defined(SGFX_INSTANCED) || defined(SGFX_BATCHED)
#ifdef SGFX_BATCHED
    mat4 model = sgfx_batchModels[sgfx_batchBase + gl_InstanceID];
#else
    mat4 model = sgfx_model * a_instance;
#endif
    // Normals by the cofactor matrix (the inverse transpose up to a positive scale): instances
    // may scale unevenly or mirror, and a per-vertex inverse would cost far more.
    mat3 m = mat3(model);
    mat3 normalMatrix = mat3(cross(m[1], m[2]), cross(m[2], m[0]), cross(m[0], m[1])) *
                        (determinant(m) < 0.0 ? -1.0 : 1.0);
#else
    mat4 model = sgfx_model;
    mat3 normalMatrix = sgfx_normalMatrix;
#endif
    // Skinned and morphed meshes are posed in mesh space first (pose.glsl).
    vec3 sgfx_meshPos = a_position, sgfx_meshNormal = a_normal, sgfx_meshTangent = a_tangent.xyz;
#if defined(SGFX_SKINNED) || defined(SGFX_MORPHED)
    sgfx_pose(sgfx_meshPos, sgfx_meshNormal, sgfx_meshTangent);
#endif
    vec3 sgfx_worldPos = (model * vec4(sgfx_meshPos, 1.0)).xyz;
    vec3 sgfx_worldNormal = normalMatrix * sgfx_meshNormal;
    vec4 sgfx_viewPos = sgfx_view * vec4(sgfx_worldPos, 1.0);
    // @sgfx:vertex
#ifdef SGFX_WORLD_POSITION
    v_worldPos = sgfx_worldPos;
#endif
#ifdef SGFX_TRANSMISSION
    v_modelScale = vec3(length(model[0].xyz), length(model[1].xyz), length(model[2].xyz));
#endif
#ifdef SGFX_VERTEX_LIGHTING
    vertexLighting(sgfx_worldPos, normalize(sgfx_worldNormal));
#endif
#ifdef SGFX_NORMALS
    v_worldNormal = sgfx_worldNormal;
#endif
#ifdef SGFX_TANGENTS
    // A mirroring model flips the frame's handedness: the fragment's cross(N, T) * w needs w times
    // the determinant's sign to give the mirrored bitangent (glTF 2.0, Meshes: TANGENT.w is the
    // bitangent's sign).
    v_worldTangent = vec4(mat3(model) * sgfx_meshTangent, a_tangent.w * (determinant(mat3(model)) < 0.0 ? -1.0 : 1.0));
#endif
#ifdef SGFX_TEXCOORDS
    v_texcoord = a_texcoord;
#endif
#ifdef SGFX_TEXCOORDS1
    v_texcoord1 = a_texcoord1;
#endif
#ifdef SGFX_VERTEX_COLOR
    v_color = a_color;
#endif
    gl_Position = sgfx_projection * sgfx_viewPos;
}

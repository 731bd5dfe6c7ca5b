#version 450 core
// Built-in Blinn-Phong material, fragment stage, in linear colour.
// Hooks: @sgfx:ambient may change sgfx_ambient; @sgfx:color may change sgfx_color.
in vec3 v_worldPos;
in vec3 v_worldNormal;
in vec4 v_worldTangent;
in vec2 v_texcoord;
in vec4 v_color;

uniform vec3 sgfx_matAmbient;
uniform vec4 sgfx_matDiffuse;
uniform vec3 sgfx_matSpecular;
uniform float sgfx_matShininess;
uniform vec3 sgfx_matEmissive;
uniform float sgfx_alphaCutoff; // < 0: no alpha mask
uniform int sgfx_flags;

layout(binding = 0) uniform sampler2D sgfx_baseColorMap;
layout(binding = 1) uniform sampler2D sgfx_alphaMap;
layout(binding = 2) uniform sampler2D sgfx_normalMap;

layout(location = 0) out vec4 sgfx_fragColor;

const int FLAG_BASE_MAP = 1;
const int FLAG_ALPHA_MAP = 2;
const int FLAG_NORMAL_MAP = 4;
const int FLAG_VERTEX_COLOR = 8;
const int FLAG_NORMALS = 16;
const int FLAG_TANGENTS = 32;

// @sgfx:fragment_decl

vec3 surfaceNormal() {
    vec3 dpdx = dFdx(v_worldPos);
    vec3 dpdy = dFdy(v_worldPos);
    vec3 N = (sgfx_flags & FLAG_NORMALS) != 0 ? normalize(v_worldNormal) : normalize(cross(dpdx, dpdy));
    if ((sgfx_flags & FLAG_NORMAL_MAP) != 0) {
        vec3 T, B;
        if ((sgfx_flags & FLAG_TANGENTS) != 0) {
            T = normalize(v_worldTangent.xyz - N * dot(N, v_worldTangent.xyz));
            B = cross(N, T) * v_worldTangent.w;
        } else {
            // Tangent frame from screen-space derivatives of position and texcoord.
            vec2 dtx = dFdx(v_texcoord), dty = dFdy(v_texcoord);
            vec3 t = dpdx * dty.y - dpdy * dtx.y;
            T = normalize(t - N * dot(N, t));
            B = cross(N, T) * (dtx.x * dty.y - dty.x * dtx.y < 0.0 ? -1.0 : 1.0);
        }
        vec3 m = texture(sgfx_normalMap, v_texcoord).xyz * 2.0 - 1.0;
        N = normalize(mat3(T, B, N) * m);
    }
    return gl_FrontFacing ? N : -N;
}

void main() {
    vec4 base = sgfx_matDiffuse;
    vec3 ambientColor = sgfx_matAmbient;
    if ((sgfx_flags & FLAG_VERTEX_COLOR) != 0) base *= v_color;
    if ((sgfx_flags & FLAG_BASE_MAP) != 0) {
        vec4 t = texture(sgfx_baseColorMap, v_texcoord);
        base *= t;
        ambientColor *= t.rgb;
    }
    if ((sgfx_flags & FLAG_ALPHA_MAP) != 0) base.a *= texture(sgfx_alphaMap, v_texcoord).r;
    if (sgfx_alphaCutoff >= 0.0) {
        // Alpha mask (glTF MASK): a fragment is either cut or fully opaque, so no partial alpha
        // from the mask's edges or coarse mip levels reaches the target (and a captured PNG).
        if (base.a < sgfx_alphaCutoff) discard;
        base.a = 1.0;
    }

    vec3 N = surfaceNormal();
    vec3 V = normalize(sgfx_eye.xyz - v_worldPos);
    vec3 sgfx_ambient = sgfx_ambientLight.rgb;
    vec3 sgfx_worldPos = v_worldPos;
    vec3 sgfx_eyePos = sgfx_eye.xyz;
    // @sgfx:ambient
    vec3 color = sgfx_matEmissive + sgfx_ambient * ambientColor;
    for (int i = 0; i < sgfx_lightCount.x; ++i) {
        vec4 lv = sgfx_lightVector[i];
        vec3 L = lv.w == 0.0 ? normalize(lv.xyz) : normalize(lv.xyz - v_worldPos);
        float NdotL = max(dot(N, L), 0.0);
        vec3 H = normalize(L + V);
        float spec = NdotL > 0.0 ? pow(max(dot(N, H), 0.0), sgfx_matShininess) : 0.0;
        color += sgfx_lightColor[i].rgb * (base.rgb * NdotL + sgfx_matSpecular * spec);
    }
    vec4 sgfx_color = vec4(color, base.a);
    // @sgfx:color
    sgfx_fragColor = sgfx_color;
}

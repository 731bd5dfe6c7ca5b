// The fixed-function emulation program: what OSG content asks of OpenGL 1.x that the built-in
// material does not do (TexGen SPHERE_MAP, TexEnv DECAL with alpha and BLEND), as a foreign
// GLSL 450 program, so the composer's wrap still applies fog, OIT and the rest. It lights with
// sgfx's lights like the built-in Blinn-Phong and opts into AO and shadows.
#include "OsgConvert.h"

#include <osg/Material>
#include <osg/TexEnv>
#include <osg/TexGen>
#include <osg/TextureCubeMap>

namespace sgfx::osgbridge {

namespace {

const char* const kFrameBlock = R"(layout(std140, binding = 0) uniform SgfxFrame {
    mat4 sgfx_view; mat4 sgfx_projection; mat4 sgfx_viewProjection; mat4 sgfx_invViewProjection;
    vec4 sgfx_eye; vec4 sgfx_viewport; vec4 sgfx_ambientLight; vec4 sgfx_time; ivec4 sgfx_lightCount;
    vec4 sgfx_lightVector[8]; vec4 sgfx_lightColor[8];
};
)";

const char* const kVertex = R"(
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 3) in vec2 a_uv;
layout(location = 4) in vec4 a_color;
uniform mat4 sgfx_model;
uniform mat3 sgfx_normalMatrix;
out vec3 v_worldPos;
out vec3 v_worldNormal;
out vec2 v_uv;
out vec4 v_color;
void main() {
    vec4 w = sgfx_model * vec4(a_position, 1.0);
    v_worldPos = w.xyz;
    v_worldNormal = sgfx_normalMatrix * a_normal;
    v_uv = a_uv;
    v_color = a_color;
    gl_Position = sgfx_viewProjection * w;
}
)";

const char* const kFragment = R"(
#ifdef SGFX_AMBIENT_OCCLUSION
float sgfx_ambientOcclusion();
#endif
#ifdef SGFX_LIGHT_VISIBILITY
float sgfx_lightVisibility(int light, vec3 worldPos, vec3 worldNormal);
#endif
in vec3 v_worldPos;
in vec3 v_worldNormal;
in vec2 v_uv;
in vec4 v_color;
uniform vec3 osgff_ambient;
uniform vec4 osgff_diffuse;
uniform vec3 osgff_specular;
uniform vec3 osgff_emission;
uniform float osgff_shininess;
uniform vec3 osgff_backAmbient; // osg::Material's BACK face, for back faces
uniform vec4 osgff_backDiffuse;
uniform vec3 osgff_backSpecular;
uniform vec3 osgff_backEmission;
uniform float osgff_backShininess;
uniform int osgff_hasColors;
uniform sampler2D osgff_texture0;
layout(location = 0) out vec4 fragColor;

vec3 surfaceNormal() {
    float len = length(v_worldNormal);
    vec3 n = len > 1e-8 ? v_worldNormal / len : vec3(0.0, 0.0, 1.0); // no normals: facing up
    return gl_FrontFacing ? n : -n;
}

// OpenGL 2.1 §2.12.4: sphere-map coordinates from the eye-space reflection of the view ray.
vec2 sphereMap(vec3 worldNormal) {
    vec3 u = normalize((sgfx_view * vec4(v_worldPos, 1.0)).xyz);
    vec3 r = reflect(u, normalize(mat3(sgfx_view) * worldNormal));
    float m = 2.0 * sqrt(r.x * r.x + r.y * r.y + (r.z + 1.0) * (r.z + 1.0));
    return r.xy / m + 0.5;
}

// The cube map's panorama (OsgState.cpp, cubeToPanorama): azimuth across, polar angle down.
vec2 panoramaUv(vec3 d) {
    d = normalize(d);
    return vec2(atan(d.y, d.x) / 6.28318530718 + 0.5, acos(clamp(d.z, -1.0, 1.0)) / 3.14159265359);
}

// TexGen REFLECTION_MAP / NORMAL_MAP: the eye-space reflection of the view ray, or the normal.
vec3 cubeDirection(vec3 worldNormal) {
    vec3 n = normalize(mat3(sgfx_view) * worldNormal);
#ifdef OSGFF_NORMAL_MAP
    return n;
#else
    return reflect(normalize((sgfx_view * vec4(v_worldPos, 1.0)).xyz), n);
#endif
}

void main() {
    vec4 vertexColor = osgff_hasColors != 0 ? v_color : vec4(1.0);
    bool front = gl_FrontFacing;
    vec4 base = (front ? osgff_diffuse : osgff_backDiffuse) * vertexColor;
    vec3 N = surfaceNormal();
#ifdef OSGFF_LIGHTING
    vec3 V = normalize(sgfx_eye.xyz - v_worldPos);
    vec3 ambient = sgfx_ambientLight.rgb * (front ? osgff_ambient : osgff_backAmbient) *
                   (osgff_hasColors != 0 ? vertexColor.rgb : vec3(1.0));
#ifdef SGFX_AMBIENT_OCCLUSION
    ambient *= 1.0 - sgfx_ambientOcclusion();
#endif
    vec3 color = (front ? osgff_emission : osgff_backEmission) + ambient;
    vec3 specular = front ? osgff_specular : osgff_backSpecular;
    float shininess = front ? osgff_shininess : osgff_backShininess;
    for (int i = 0; i < min(sgfx_lightCount.x, 8); ++i) {
        vec4 lv = sgfx_lightVector[i];
        vec3 L = normalize(lv.w == 0.0 ? lv.xyz : lv.xyz - v_worldPos);
        float nl = max(dot(N, L), 0.0);
        float spec = nl > 0.0 ? pow(max(dot(N, normalize(L + V)), 0.0), shininess) : 0.0;
        vec3 c = sgfx_lightColor[i].rgb * (base.rgb * nl + specular * spec);
#ifdef SGFX_LIGHT_VISIBILITY
        c *= sgfx_lightVisibility(i, v_worldPos, N);
#endif
        color += c;
    }
    vec4 frag = vec4(color, base.a);
#else
    vec4 frag = base;
#endif
#ifdef OSGFF_TEXTURE
#if defined(OSGFF_SPHERE_MAP)
    vec4 t = texture(osgff_texture0, sphereMap(N));
#elif defined(OSGFF_CUBE)
    vec4 t = textureLod(osgff_texture0, panoramaUv(cubeDirection(N)), 0.0); // no seam from derivatives
#else
    vec4 t = texture(osgff_texture0, v_uv);
#endif
#if OSGFF_TEXENV == 1
    frag = vec4(t.rgb, frag.a * t.a); // REPLACE (RGBA texture)
#elif OSGFF_TEXENV == 2
    frag.rgb = mix(frag.rgb, t.rgb, t.a); // DECAL
#elif OSGFF_TEXENV == 3
    frag = vec4(mix(frag.rgb, vec3(0.0), t.rgb), frag.a * t.a); // BLEND with a black environment colour
#else
    frag *= t; // MODULATE
#endif
#endif
    fragColor = frag;
}
)";

} // namespace

bool isCube(const FixedState& state) {
    return dynamic_cast<const osg::TextureCubeMap*>(state.texture0) != nullptr;
}

/// The Material's faces differ (OpenGL lights back faces with the BACK material).
bool twoFaced(const FixedState& state) {
    const auto* m = state.material;
    if (!m || !state.lighting) return false;
    using M = osg::Material;
    return m->getAmbient(M::FRONT) != m->getAmbient(M::BACK) ||
           m->getDiffuse(M::FRONT) != m->getDiffuse(M::BACK) ||
           m->getSpecular(M::FRONT) != m->getSpecular(M::BACK) ||
           m->getEmission(M::FRONT) != m->getEmission(M::BACK) ||
           m->getShininess(M::FRONT) != m->getShininess(M::BACK);
}

bool needsFixedFunctionProgram(const FixedState& state) {
    if (twoFaced(state)) return true;
    if (!state.texture0) return false;
    return state.texGen == osg::TexGen::SPHERE_MAP || isCube(state) || state.texEnv == GL_DECAL ||
           state.texEnv == GL_BLEND;
}

std::shared_ptr<ShaderProgram> fixedFunctionProgram(const FixedState& state) {
    std::string defines;
    if (state.lighting) defines += "#define OSGFF_LIGHTING\n";
    if (state.texture0) defines += "#define OSGFF_TEXTURE\n";
    if (state.texGen == osg::TexGen::SPHERE_MAP) defines += "#define OSGFF_SPHERE_MAP\n";
    if (isCube(state)) defines += "#define OSGFF_CUBE\n";
    if (isCube(state) && state.texGen == osg::TexGen::NORMAL_MAP) defines += "#define OSGFF_NORMAL_MAP\n";
    const int env = state.texEnv == GL_REPLACE ? 1
                    : state.texEnv == GL_DECAL ? 2
                    : state.texEnv == GL_BLEND ? 3
                                               : 0;
    defines += "#define OSGFF_TEXENV " + std::to_string(env) + "\n";
    const std::string head = std::string("#version 450 core\n") + defines + kFrameBlock;
    return ShaderProgram::create("osg_fixed_function", head + kVertex, head + kFragment);
}

} // namespace sgfx::osgbridge

#version 450 core
// Normals and linear depth from the scene depth alone (AoNormals::FromDepth, no G-buffer re-draw).
// Along x and along y, of the two neighbours the one nearer in depth gives the tangent: exact on
// planes, and a normal never spans a depth edge. Output texel q holds draw pixel q·scale.
in vec2 v_uv;
layout(location = 0) out vec4 sgfx_aoNormalOut; // view-space normal (0 = none)
layout(location = 1) out vec4 sgfx_aoDepthOut;  // linear view depth (0 = nothing drawn)
uniform sampler2D sgfx_aoSceneDepth;            // window depth, draw size
uniform int sgfx_aoScale;                       // draw pixels per output texel

#include_ao_view_position

float sgfx_aoLinear(ivec2 p) {
    float z = texelFetch(sgfx_aoSceneDepth, p, 0).r;
    if (z >= 1.0) return 0.0;
    float ndcZ = z * 2.0 - 1.0;
    return sgfx_aoPerspective() ? sgfx_projection[3][2] / (ndcZ + sgfx_projection[2][2])
                                : (sgfx_projection[3][2] - ndcZ) / sgfx_projection[2][2];
}

// The tangent along `axis` at p (P its position, d its depth); zero when neither side is drawn.
vec3 sgfx_aoTangent(ivec2 p, ivec2 axis, vec3 P, float d, vec2 size) {
    ivec2 last = ivec2(size) - 1;
    ivec2 a = p + axis, b = p - axis;
    float da = all(lessThanEqual(a, last)) ? sgfx_aoLinear(a) : 0.0;
    float db = all(greaterThanEqual(b, ivec2(0))) ? sgfx_aoLinear(b) : 0.0;
    bool useA = da > 0.0 && (db <= 0.0 || abs(da - d) <= abs(db - d));
    if (useA) return sgfx_aoPosition(a, da, size) - P;
    return db > 0.0 ? P - sgfx_aoPosition(b, db, size) : vec3(0.0);
}

void main() {
    vec2 size = vec2(textureSize(sgfx_aoSceneDepth, 0));
    ivec2 p = min(ivec2(gl_FragCoord.xy) * sgfx_aoScale, ivec2(size) - 1);
    float d = sgfx_aoLinear(p);
    sgfx_aoDepthOut = vec4(d, 0.0, 0.0, 0.0);
    sgfx_aoNormalOut = vec4(0.0);
    if (d <= 0.0) return;
    vec3 P = sgfx_aoPosition(p, d, size);
    vec3 n = cross(sgfx_aoTangent(p, ivec2(1, 0), P, d, size), sgfx_aoTangent(p, ivec2(0, 1), P, d, size));
    if (dot(n, n) > 1e-20) sgfx_aoNormalOut = vec4(normalize(n), 0.0);
}

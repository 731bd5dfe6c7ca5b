#version 450 core
// SMAA edge detection on colour (Jimenez et al. 2012, sec. 3): as the luma detector, with the
// largest per-channel step instead of the luma step, so edges between colours of equal luma
// are found too.
in vec2 v_uv;
layout(location = 0) out vec4 sgfx_smaaEdges;
layout(binding = 0) uniform sampler2D sgfx_aaSource; // linear on fetch
uniform float sgfx_smaaThreshold;

ivec2 sgfx_last;
vec3 colour(ivec2 p) {
    return sqrt(texelFetch(sgfx_aaSource, clamp(p, ivec2(0), sgfx_last), 0).rgb); // gamma-like values
}
float diff(vec3 a, vec3 b) {
    vec3 d = abs(a - b);
    return max(d.r, max(d.g, d.b));
}

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    sgfx_last = textureSize(sgfx_aaSource, 0) - 1;
    vec3 C = colour(p), left = colour(p - ivec2(1, 0)), top = colour(p + ivec2(0, 1));
    vec2 delta = vec2(diff(C, left), diff(C, top));
    vec2 edges = step(vec2(sgfx_smaaThreshold), delta);
    if (edges.x + edges.y == 0.0) discard;
    vec2 around = vec2(diff(C, colour(p + ivec2(1, 0))), diff(C, colour(p - ivec2(0, 1))));
    vec2 beyond = vec2(diff(left, colour(p - ivec2(2, 0))), diff(top, colour(p + ivec2(0, 2))));
    vec2 largest = max(max(delta, around), beyond);
    edges *= step(max(largest.x, largest.y), 2.0 * delta); // local contrast adaptation (eq. 1)
    if (edges.x + edges.y == 0.0) discard;
    sgfx_smaaEdges = vec4(edges, 0.0, 1.0);
}

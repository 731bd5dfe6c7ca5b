#version 450 core
// SMAA edge detection on luma (Jimenez et al. 2012, sec. 3): an edge on a pixel's left (R) or
// top (G) side where the luma step passes the threshold and is at least half the largest step
// around it (local contrast adaptation, the paper's eq. 1), so a weak edge beside a strong one
// is dropped. Pixels without an edge are discarded and leave the stencil unmarked.
in vec2 v_uv;
layout(location = 0) out vec4 sgfx_smaaEdges;
layout(binding = 0) uniform sampler2D sgfx_aaSource; // linear on fetch
uniform float sgfx_smaaThreshold;

ivec2 sgfx_last;
float luma(ivec2 p) {
    vec3 c = texelFetch(sgfx_aaSource, clamp(p, ivec2(0), sgfx_last), 0).rgb;
    return sqrt(dot(c, vec3(0.2126, 0.7152, 0.0722))); // thresholds are tuned for gamma values
}

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    sgfx_last = textureSize(sgfx_aaSource, 0) - 1;
    float L = luma(p);
    vec2 delta = abs(L - vec2(luma(p - ivec2(1, 0)), luma(p + ivec2(0, 1))));
    vec2 edges = step(vec2(sgfx_smaaThreshold), delta);
    if (edges.x + edges.y == 0.0) discard;
    vec2 around = abs(L - vec2(luma(p + ivec2(1, 0)), luma(p - ivec2(0, 1))));
    vec2 beyond = abs(vec2(luma(p - ivec2(1, 0)) - luma(p - ivec2(2, 0)),
                           luma(p + ivec2(0, 1)) - luma(p + ivec2(0, 2))));
    vec2 largest = max(max(delta, around), beyond);
    edges *= step(max(largest.x, largest.y), 2.0 * delta);
    if (edges.x + edges.y == 0.0) discard;
    sgfx_smaaEdges = vec4(edges, 0.0, 1.0);
}

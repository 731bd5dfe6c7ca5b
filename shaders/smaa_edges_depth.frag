#version 450 core
// SMAA edge detection on depth (Jimenez et al. 2012, sec. 3): an edge where the window depth
// jumps by more than a tenth of the colour threshold, as the reference does. It sees geometric
// edges only (not texture or shading ones) and needs no local contrast adaptation.
in vec2 v_uv;
layout(location = 0) out vec4 sgfx_smaaEdges;
layout(binding = 1) uniform sampler2D sgfx_aaDepth; // the view's shared depth
uniform float sgfx_smaaThreshold;

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy), last = textureSize(sgfx_aaDepth, 0) - 1;
    float d = texelFetch(sgfx_aaDepth, p, 0).r;
    float left = texelFetch(sgfx_aaDepth, max(p - ivec2(1, 0), ivec2(0)), 0).r;
    float top = texelFetch(sgfx_aaDepth, min(p + ivec2(0, 1), last), 0).r;
    vec2 edges = step(vec2(0.1 * sgfx_smaaThreshold), abs(d - vec2(left, top)));
    if (edges.x + edges.y == 0.0) discard;
    sgfx_smaaEdges = vec4(edges, 0.0, 1.0);
}

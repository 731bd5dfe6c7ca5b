#version 450 core
// SMAA blending weights (Jimenez et al. 2012, sec. 4), run on edge pixels only (stencil). For a
// pixel's top edge (G) and left edge (R): search along the line both ways for its ends, two
// pixels a bilinear fetch, decoded by the search texture; read the crossing edges at each end
// (one bilinear fetch gives both sides); look up the revectorised line's coverage of this pixel
// in the area texture. Output: r/g this pixel takes from above / the pixel above takes from this
// one; b/a likewise with the left neighbour.
in vec2 v_uv;
layout(location = 0) out vec4 sgfx_smaaWeights;
layout(binding = 0) uniform sampler2D sgfx_smaaEdgesTex; // RG: left, top edges; bilinear
layout(binding = 1) uniform sampler2D sgfx_smaaArea;     // SmaaTextures.h, texel fetched
layout(binding = 2) uniform sampler2D sgfx_smaaSearch;   // SmaaTextures.h, texel fetched
uniform int sgfx_smaaSteps;
uniform float sgfx_smaaCorner; // 1 − corner rounding (0.75 for the reference's 25 %), 0: off
const int kMaxDistance = 72; // smaa::kMaxDistance

vec2 sgfx_texel;
ivec2 sgfx_size;
vec2 edgesAt(vec2 pixel) { // bilinear, `pixel` in window coordinates
    return textureLod(sgfx_smaaEdgesTex, pixel * sgfx_texel, 0.0).rg;
}
// How many of a fetched pair still belong to the line (0..2), or 3: both, and it goes on.
float decode(float line, float crossing, bool farSide) {
    return texelFetch(sgfx_smaaSearch, ivec2(round(4.0 * line), round(4.0 * crossing) + (farSide ? 5 : 0)), 0).r;
}

// Walks from pixel `from` by `dir` (±1) two pixels a step; the fetch lies a quarter pixel from
// the nearer pixel's centre toward the next. Returns the last pixel on the line.
int walk(ivec2 p, bool horizontal, int from, int dir, bool farSide) {
    int size = horizontal ? sgfx_size.x : sgfx_size.y;
    for (int i = 0; i < sgfx_smaaSteps; ++i) {
        if (from < 0 || from >= size) break; // the image's border ends the line
        float at = float(from) + 0.5 + 0.25 * float(dir);
        vec2 e = horizontal ? edgesAt(vec2(at, float(p.y) + 0.5)) : edgesAt(vec2(float(p.x) + 0.5, at));
        float n = horizontal ? decode(e.g, e.r, farSide) : decode(e.r, e.g, farSide);
        if (n < 2.5) return from - dir + dir * int(n);
        from += 2 * dir;
    }
    return from - dir;
}

vec2 areaOf(float e1, float e2, int d1, int d2) {
    ivec2 t = ivec2(round(4.0 * vec2(e1, e2))) * kMaxDistance + min(ivec2(d1, d2), ivec2(kMaxDistance - 1));
    return texelFetch(sgfx_smaaArea, t, 0).rg;
}

// Corners (the reference's corner detection): where the crossing edge at the nearer end runs
// on for a second pixel, away from the edge on either side, the line ends at a real corner of
// a shape, not a step of a staircase: blend less there, so corners stay sharp. `d`: distances
// to the ends; `thisSide`, `otherSide`: the crossing edges there one more pixel out, per end.
vec2 cornerFactor(vec2 d, vec2 thisSide, vec2 otherSide) {
    if (sgfx_smaaCorner <= 0.0) return vec2(1.0);
    vec2 nearer = step(d, d.yx);
    vec2 rounding = sgfx_smaaCorner * nearer / (nearer.x + nearer.y);
    return clamp(vec2(1.0 - dot(rounding, thisSide), 1.0 - dot(rounding, otherSide)), 0.0, 1.0);
}
float edgeR(int x, int y) {
    return texelFetch(sgfx_smaaEdgesTex, clamp(ivec2(x, y), ivec2(0), sgfx_size - 1), 0).r;
}
float edgeG(int x, int y) {
    return texelFetch(sgfx_smaaEdgesTex, clamp(ivec2(x, y), ivec2(0), sgfx_size - 1), 0).g;
}

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    sgfx_size = textureSize(sgfx_smaaEdgesTex, 0);
    sgfx_texel = 1.0 / vec2(sgfx_size);
    vec2 e = texelFetch(sgfx_smaaEdgesTex, p, 0).rg;
    vec4 w = vec4(0.0);
    if (e.g > 0.0) { // a line along the top of this row: its crossings below (0.75) and above
        int left = walk(p, true, p.x, -1, true), right = walk(p, true, p.x + 1, 1, false);
        float e1 = edgesAt(vec2(float(left) + 0.5, float(p.y) + 0.75)).r;
        float e2 = right + 1 < sgfx_size.x ? edgesAt(vec2(float(right) + 1.5, float(p.y) + 0.75)).r : 0.0;
        w.rg = areaOf(e1, e2, p.x - left, right - p.x);
        w.rg *= cornerFactor(vec2(p.x - left, right - p.x),
                             vec2(edgeR(left, p.y - 1), edgeR(right + 1, p.y - 1)),
                             vec2(edgeR(left, p.y + 2), edgeR(right + 1, p.y + 2)));
    }
    if (e.r > 0.0) { // a line along the left of this column: its crossings on the right (0.75)
        int down = walk(p, false, p.y - 1, -1, false), up = walk(p, false, p.y, 1, true);
        float e1 = down > 0 ? edgesAt(vec2(float(p.x) + 0.25, float(down) - 0.5)).g : 0.0;
        float e2 = edgesAt(vec2(float(p.x) + 0.25, float(up) + 0.5)).g;
        w.ba = areaOf(e1, e2, p.y - down, up - p.y);
        w.ba *= cornerFactor(vec2(p.y - down, up - p.y), vec2(edgeG(p.x + 1, down - 1), edgeG(p.x + 1, up)),
                             vec2(edgeG(p.x - 2, down - 1), edgeG(p.x - 2, up)));
    }
    sgfx_smaaWeights = w;
}

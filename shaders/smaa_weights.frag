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
layout(binding = 3) uniform sampler2D sgfx_smaaDiagArea; // SmaaTextures.h, texel fetched
uniform int sgfx_smaaSteps;
uniform int sgfx_smaaDiagSteps; // diagonal search steps, one pixel each; 0: no diagonal patterns
uniform float sgfx_smaaCorner; // 1 − corner rounding (0.75 for the reference's 25 %), 0: off
const int kMaxDistance = 72; // smaa::kMaxDistance
const int kMaxDiagonal = 20; // smaa::kMaxDiagonal

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

// Diagonal patterns (the paper's sec. 4.2), '/' (mx = 1) or '\\' (mx = −1): a run pixel has a top
// edge and a left edge, its own ('/') or its right neighbour's ('\\'); outside the image: none.
vec2 edgeAt(ivec2 q) {
    if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, sgfx_size))) return vec2(0.0);
    return texelFetch(sgfx_smaaEdgesTex, q, 0).rg;
}
float diagLeft(ivec2 q, int mx) {
    return edgeAt(q + ivec2((1 - mx) / 2, 0)).r;
}
bool onRun(ivec2 q, int mx) {
    return edgeAt(q).g > 0.5 && diagLeft(q, mx) > 0.5;
}
int diagWalk(ivec2 p, ivec2 m, int mx) {
    int d = 0;
    while (d < sgfx_smaaDiagSteps && onRun(p + (d + 1) * m, mx)) ++d;
    return d;
}
// The run through p: its weights for p's top edge (SmaaTextures.h, diagonalArea), or −1: none.
// Ends: bit 0 the staircase goes on horizontally, bit 1 vertically.
vec2 diagonal(ivec2 p, int mx) {
    if (sgfx_smaaDiagSteps == 0 || !onRun(p, mx)) return vec2(-1.0);
    ivec2 m = ivec2(mx, 1);
    int d1 = diagWalk(p, -m, mx), d2 = diagWalk(p, m, mx);
    if (d1 + d2 < 2) return vec2(-1.0); // a shape's corner or a lone step: orthogonal
    ivec2 s = p - d1 * m, e = p + d2 * m;
    int c1 = int(edgeAt(s + ivec2(-mx, -1)).g > 0.5) + 2 * int(diagLeft(s + ivec2(0, -1), mx) > 0.5);
    int c2 = int(edgeAt(e + ivec2(mx, 0)).g > 0.5) + 2 * int(diagLeft(e + ivec2(mx, 1), mx) > 0.5);
    ivec2 t = ivec2(c1, c2) * kMaxDiagonal + min(ivec2(d1, d2), ivec2(kMaxDiagonal - 1));
    return texelFetch(sgfx_smaaDiagArea, t, 0).rg;
}

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    sgfx_size = textureSize(sgfx_smaaEdgesTex, 0);
    sgfx_texel = 1.0 / vec2(sgfx_size);
    vec2 e = texelFetch(sgfx_smaaEdgesTex, p, 0).rg;
    vec4 w = vec4(0.0);
    // A diagonal run puts all its weights on the top edges (the blend takes one direction only).
    vec2 diag = e.g > 0.0 ? diagonal(p, 1) : vec2(-1.0);
    if (e.g > 0.0 && diag.x < 0.0) diag = diagonal(p, -1);
    bool onDiagonal = diag.x >= 0.0;
    if (onDiagonal) w.rg = diag;
    if (e.g > 0.0 && !onDiagonal) { // a line along the top of this row: crossings below (0.75), above
        int left = walk(p, true, p.x, -1, true), right = walk(p, true, p.x + 1, 1, false);
        float e1 = edgesAt(vec2(float(left) + 0.5, float(p.y) + 0.75)).r;
        float e2 = right + 1 < sgfx_size.x ? edgesAt(vec2(float(right) + 1.5, float(p.y) + 0.75)).r : 0.0;
        w.rg = areaOf(e1, e2, p.x - left, right - p.x);
        w.rg *= cornerFactor(vec2(p.x - left, right - p.x),
                             vec2(edgeR(left, p.y - 1), edgeR(right + 1, p.y - 1)),
                             vec2(edgeR(left, p.y + 2), edgeR(right + 1, p.y + 2)));
    }
    // A left edge that is a '\\' run's right side is the run's: the run pixel blends it vertically.
    if (e.r > 0.0 && !onDiagonal && diagonal(p - ivec2(1, 0), -1).x < 0.0) { // crossings right (0.75)
        int down = walk(p, false, p.y - 1, -1, false), up = walk(p, false, p.y, 1, true);
        float e1 = down > 0 ? edgesAt(vec2(float(p.x) + 0.25, float(down) - 0.5)).g : 0.0;
        float e2 = edgesAt(vec2(float(p.x) + 0.25, float(up) + 0.5)).g;
        w.ba = areaOf(e1, e2, p.y - down, up - p.y);
        w.ba *= cornerFactor(vec2(p.y - down, up - p.y), vec2(edgeG(p.x + 1, down - 1), edgeG(p.x + 1, up)),
                             vec2(edgeG(p.x - 2, down - 1), edgeG(p.x - 2, up)));
    }
    sgfx_smaaWeights = w;
}

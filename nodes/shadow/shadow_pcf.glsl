// ShadowFilter::Pcf: 16 comparisons over a Poisson disc of `radius` texels (sgfx_shadowDisc, from
// ShadowMath's poissonDisc), rotated by an angle hashed from the quarter-texel cell of light space
// the point lies in: the pattern is anchored to the world, so it does not swim as the camera
// moves, and TAA sees it still. Early-out: the centre and the 4 outer probes agree (wholly lit or
// wholly shadowed), and the other 12 taps are skipped; a shadow thinner than the probes' spacing
// can be missed there (docs/effects/shadows.md).
float sgfx_shadowHash(vec2 cell) {
    uvec2 q = uvec2(ivec2(cell));
    uint h = (q.x * 1597334677u) ^ (q.y * 3812015801u);
    h = (h ^ (h >> 16)) * 2246822519u;
    h ^= h >> 13;
    return float(h) * (1.0 / 4294967296.0);
}

// The disc's rotation at world point P for texels of t metres.
mat2 sgfx_shadowTurn(vec3 P, float t) {
    vec2 cell = floor(4.0 * (sgfx_shadowRotation * P).xy / t);
    float phi = 6.28318531 * sgfx_shadowHash(cell);
    vec2 cs = vec2(cos(phi), sin(phi));
    return mat2(cs.x, cs.y, -cs.y, cs.x);
}

float sgfx_shadowPcf(vec4 tile, float t, vec2 uv, float depth, vec3 P, float radiusTexels, bool earlyOut) {
    mat2 turn = sgfx_shadowTurn(P, t);
    vec2 radius = radiusTexels * sgfx_shadowFilter.yz;
    float sum = 0.0;
    for (int k = 0; k < 4; ++k)
        sum += texture(sgfx_shadowMap, vec3(clamp(uv + radius * (turn * sgfx_shadowDisc[k]), tile.xy, tile.zw), depth));
    float centre = texture(sgfx_shadowMap, vec3(clamp(uv, tile.xy, tile.zw), depth));
    // The other 12 taps in a loop whose length is per pixel: a rasterizer that shades blocks of
    // pixels together (llvmpipe runs both sides of a branch) skips it when the whole block agrees.
    bool agree = earlyOut && (sum == 0.0 || sum == 4.0) && centre * 4.0 == sum;
    int last = agree ? 4 : 16;
    for (int k = 4; k < last; ++k)
        sum += texture(sgfx_shadowMap, vec3(clamp(uv + radius * (turn * sgfx_shadowDisc[k]), tile.xy, tile.zw), depth));
    return agree ? centre : sum * (1.0 / 16.0);
}

// ShadowFilter::Pcss: percentage-closer soft shadows (Fernando 2005) for a sun of angular radius
// α. A blocker search over the Poisson disc (plain depth reads) of radius (d_r − d_near)·tan α,
// the light's footprint at the farthest blocker possible; then PCF over ρ = (d_r − d_b)·tan α,
// half the penumbra's width w_p = 2(d_r − d_b)·tan α at the mean blocker depth d_b (plan §5,
// ShadowMath's sunPenumbraWidth), never below the PCF disc. Both radii stop at half of
// maxPenumbraTexels, which the tile margin leaves room for. No blocker found: lit.
uniform sampler2D sgfx_shadowDepth; // the atlas read plainly (nearest)
uniform vec4 sgfx_shadowPcss;       // x: tan α, y: the largest radius (texels)

float sgfx_shadowHash(vec2 cell) {
    uvec2 q = uvec2(ivec2(cell));
    uint h = (q.x * 1597334677u) ^ (q.y * 3812015801u);
    h = (h ^ (h >> 16)) * 2246822519u;
    h ^= h >> 13;
    return float(h) * (1.0 / 4294967296.0);
}

float sgfx_shadowFiltered(int i, vec2 uv, float depth, vec3 worldPos) {
    vec4 tile = sgfx_shadowTile[i];
    float t = sgfx_shadowTexel[i];
    float range = 1.0 / sgfx_shadowLight.w; // metres per unit of map depth (0 at the light's near end)
    float largest = sgfx_shadowPcss.y * t;
    vec2 cell = floor(4.0 * (sgfx_shadowRotation * worldPos).xy / t);
    float phi = 6.28318531 * sgfx_shadowHash(cell);
    vec2 cs = vec2(cos(phi), sin(phi));
    mat2 turn = mat2(cs.x, cs.y, -cs.y, cs.x);
    vec2 search = min(depth * range * sgfx_shadowPcss.x, largest) / t * sgfx_shadowFilter.yz;
    float blockers = 0.0, found = 0.0;
    for (int k = 0; k < 16; ++k) {
        float d = texture(sgfx_shadowDepth, clamp(uv + search * (turn * sgfx_shadowDisc[k]), tile.xy, tile.zw)).r;
        if (d < depth) {
            blockers += d;
            found += 1.0;
        }
    }
    if (found == 0.0) return 1.0;
    float rho = clamp((depth - blockers / found) * range * sgfx_shadowPcss.x, min(sgfx_shadowFilter.x * t, largest),
                      largest);
    vec2 radius = rho / t * sgfx_shadowFilter.yz;
    float sum = 0.0;
    for (int k = 0; k < 16; ++k)
        sum += texture(sgfx_shadowMap, vec3(clamp(uv + radius * (turn * sgfx_shadowDisc[k]), tile.xy, tile.zw), depth));
    return sum * (1.0 / 16.0);
}

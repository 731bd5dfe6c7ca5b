// ShadowFilter::Pcss: percentage-closer soft shadows (Fernando 2005) for a sun of angular radius
// α. A blocker search over the Poisson disc (plain depth reads) of radius (d_r − d_near)·tan α,
// the light's footprint at the farthest blocker possible; then PCF over ρ = (d_r − d_b)·tan α,
// half the penumbra's width w_p = 2(d_r − d_b)·tan α at the mean blocker depth d_b (plan §5,
// ShadowMath's sunPenumbraWidth), never below the PCF disc. Both radii stop at half of
// maxPenumbraTexels, which the tile margin leaves room for. No blocker found: lit. The sun only:
// spot lights take PCF.
uniform sampler2D sgfx_shadowDepth; // the atlas read plainly (nearest)
uniform vec4 sgfx_shadowPcssParams;       // x: tan α, y: the largest radius (texels)

float sgfx_shadowPcss(vec4 tile, float t, vec2 uv, float depth, vec3 worldPos) {
    float range = 1.0 / sgfx_shadowLight.w; // metres per unit of map depth (0 at the light's near end)
    float largest = sgfx_shadowPcssParams.y * t;
    mat2 turn = sgfx_shadowTurn(worldPos, t);
    vec2 search = min(depth * range * sgfx_shadowPcssParams.x, largest) / t * sgfx_shadowFilter.yz;
    float blockers = 0.0, found = 0.0;
    for (int k = 0; k < 16; ++k) {
        float d = texture(sgfx_shadowDepth, clamp(uv + search * (turn * sgfx_shadowDisc[k]), tile.xy, tile.zw)).r;
        if (d < depth) {
            blockers += d;
            found += 1.0;
        }
    }
    if (found == 0.0) return 1.0;
    float rho = clamp((depth - blockers / found) * range * sgfx_shadowPcssParams.x, min(sgfx_shadowFilter.x * t, largest),
                      largest);
    return sgfx_shadowPcf(tile, t, uv, depth, worldPos, rho / t, false);
}

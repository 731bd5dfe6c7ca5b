// ShadowFilter::Hard2x2: one hardware comparison, bilinear over the 2×2 texels around the point.
float sgfx_shadowFiltered(int i, vec2 uv, float depth, vec3 worldPos) {
    vec4 tile = sgfx_shadowTile[i];
    return texture(sgfx_shadowMap, vec3(clamp(uv, tile.xy, tile.zw), depth));
}

// ShadowFilter::Hard2x2: one hardware comparison, bilinear over the 2×2 texels around the point.
float sgfx_shadowHard(vec4 tile, vec2 uv, float depth) {
    return texture(sgfx_shadowMap, vec3(clamp(uv, tile.xy, tile.zw), depth));
}

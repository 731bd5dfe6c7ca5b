// ShadowDebugView::Cascades: each pixel tinted by the cascade that shades it.
{
    float follow;
    int cascade = sgfx_shadowSelect(-(sgfx_view * vec4(sgfx_worldPos, 1.0)).z, follow);
    const vec3 tints[5] = vec3[5](vec3(1.0, 0.35, 0.35), vec3(0.35, 1.0, 0.35), vec3(0.35, 0.35, 1.0),
                                  vec3(1.0, 1.0, 0.35), vec3(1.0));
    // Beyond the last cascade: untinted, whatever the count.
    if (sgfx_shadowSun.x >= 0) sgfx_color.rgb *= tints[cascade < sgfx_shadowSun.y ? cascade : 4];
}

// Seed §2: depth of the nearest surface of the view, from the fog's depth pre-pass.
uniform sampler2D sgfx_fogNearestDepth;

// World position of a window position and depth (seed eq. 2).
vec3 sgfx_fogWorldAt(vec2 fragXY, float depth) {
    vec4 ndc = vec4((fragXY - sgfx_viewport.xy) / sgfx_viewport.zw * 2.0 - 1.0, depth * 2.0 - 1.0, 1.0);
    vec4 w = sgfx_invViewProjection * ndc;
    return w.xyz / w.w;
}

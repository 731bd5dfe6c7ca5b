#version 450 core
// Full-screen fog: the seed's §1 post-process (SGFX_FOG_POST: every pixel, P from the depth
// texture by eq. 2) or the sky of the forward modes (drawn at depth 1 with a depth test EQUAL,
// so only pixels no geometry covered run this). Outputs (fog colour, k) for alpha blending,
// which is eq. 7 with T_rgb read by the blender instead of a texture copy.
in vec2 v_uv;
layout(location = 0) out vec4 sgfx_fragColor;

// @sgfx:fragment_decl

#ifdef SGFX_FOG_POST
uniform sampler2D sgfx_fogSceneDepth;
#endif

void main() {
    float d = 1.0;
#ifdef SGFX_FOG_POST
    d = texelFetch(sgfx_fogSceneDepth, ivec2(gl_FragCoord.xy), 0).r;
#endif
    vec4 ndc = vec4((gl_FragCoord.xy - sgfx_viewport.xy) / sgfx_viewport.zw * 2.0 - 1.0, d * 2.0 - 1.0, 1.0);
    vec4 w = sgfx_invViewProjection * ndc;
    vec3 p = w.xyz / w.w;
    if (d >= 1.0) {
#ifdef SGFX_FOG_POST
        // The sky pass runs only with a sky rule: without a discard llvmpipe tests depth before
        // shading and skips covered blocks.
        if (sgfx_fogShape.z == 0.0) discard;
#endif
        if (sgfx_fogShape.z > 0.0) p = sgfx_eye.xyz + normalize(p - sgfx_eye.xyz) * sgfx_fogShape.z;
    }
    sgfx_fragColor = vec4(sgfx_fogColor, sgfx_fogAmount(sgfx_fogOpticalDepthFromEye(p)));
}

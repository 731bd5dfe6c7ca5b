// Eq. 6's sums: target 0 adds (C·w, α·w) with C premultiplied; target 1 multiplies by (1 − α).
#ifdef SGFX_OIT_ACCUMULATE
vec4 c = clamp(sgfx_color, vec4(0.0), vec4(65504.0));
c.a = min(c.a, 1.0);
#ifndef SGFX_BLEND_PREMULTIPLIED
c.rgb *= c.a;
#endif
float z = (sgfx_view * vec4(sgfx_worldPos, 1.0)).z;
sgfx_color = c * sgfx_oitWeightOf(c.a, z, gl_FragCoord.z);
sgfx_oitRevealage = vec4(c.a);
#endif

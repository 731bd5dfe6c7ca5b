float dn = texelFetch(sgfx_fogNearestDepth, ivec2(gl_FragCoord.xy), 0).r;
vec3 pn = sgfx_fogWorldAt(gl_FragCoord.xy, dn);
float sn = distance(pn, sgfx_eyePos);
float s = distance(sgfx_worldPos, sgfx_eyePos);
// ε follows depth-buffer precision at this pixel: the distance 16 float32 depth steps span
// here, plus the float error of the interpolated position. A fixed ε fails far away.
float step16 = abs(sn - distance(sgfx_fogWorldAt(gl_FragCoord.xy, dn - 1.0 / 1048576.0), sgfx_eyePos));
float eps = step16 + 1e-5 * s + 1e-4;
float F = s - sn < eps ? sgfx_fogOpticalDepthFromEye(pn) // foreground: F_n on [O, Pn]
                       : sgfx_fogOpticalDepth(pn, sgfx_worldPos); // background: F_f on [Pn, P]
sgfx_color = sgfx_fogApply(sgfx_color, sgfx_fogAmount(F));

// SSAO seed §4: the ambient intensity times (1 − k), k being the occluded fraction; the
// material scales all indirect light by sgfx_indirect (ambient and environment light). Blended
// surfaces (glass, particles) are not in the G-buffer and are not occluded.
#ifndef SGFX_BLEND
sgfx_indirect *= 1.0 - sgfx_ambientOcclusion();
#endif

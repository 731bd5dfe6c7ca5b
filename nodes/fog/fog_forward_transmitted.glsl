// The copy a transmissive surface samples was fogged on [eye, P_behind]; the surface's own colour
// is fogged on [eye, P] at the colour hook. Fog is a mix, c' = c·(1 − k) + fog·k, so the share
// of [eye, P] comes out by inverting it, leaving the light that reaches the surface (fogged on
// [P, P_behind] only when fog is Beer–Lambert: 1 − k multiplies along a ray).
float sgfx_fogK = sgfx_fogAmount(sgfx_fogOpticalDepthFromEye(sgfx_worldPos));
sgfx_transmitted = (sgfx_transmitted - sgfx_fogColor * sgfx_fogK) / max(1.0 - sgfx_fogK, 1e-4);

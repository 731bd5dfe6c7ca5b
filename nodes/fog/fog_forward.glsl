sgfx_color = sgfx_fogApply(sgfx_color, sgfx_fogAmount(sgfx_fogOpticalDepthFromEye(sgfx_worldPos)));

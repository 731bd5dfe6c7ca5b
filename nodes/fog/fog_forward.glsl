sgfx_color = sgfx_fogApply(sgfx_color, sgfx_fogAmount(sgfx_fogOpticalDepth(sgfx_eyePos, sgfx_worldPos)));

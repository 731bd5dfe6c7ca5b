sgfx_color.rgb = mix(sgfx_color.rgb, sgfx_debugTint.rgb, sgfx_debugTint.a);

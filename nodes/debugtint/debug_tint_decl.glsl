uniform vec4 sgfx_debugTint; // rgb: linear tint colour, a: amount

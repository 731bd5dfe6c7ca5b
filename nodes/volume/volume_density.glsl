// Density ρ at box coordinates uvw ∈ [0, 1]³: a 3D texture (clamped to its edges), or the
// application's GLSL function `float volumeDensity(vec3 uvw)` compiled in.
layout(binding = SGFX_VOLUME_DENSITY_UNIT) uniform sampler3D u_density;
layout(binding = SGFX_VOLUME_DENSITY_UNIT + 1) uniform sampler3D u_densityMax; // empty-space skipping
uniform float u_densityScale;

#ifdef SGFX_VOLUME_FUNCTION
float volumeDensity(vec3 uvw);
float densityAt(vec3 uvw) { return max(volumeDensity(uvw), 0.0) * u_densityScale; }
#else
float densityAt(vec3 uvw) { return texture(u_density, uvw).r * u_densityScale; }
#endif

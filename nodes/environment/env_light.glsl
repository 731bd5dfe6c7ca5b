// Image-based light (EnvironmentLightNode): diffuse irradiance from order-2 spherical harmonics
// (Ramamoorthi and Hanrahan 2001, eq. 13), specular from the GGX-prefiltered cube map and the
// split-sum table (Karis 2013). Callable from foreign shaders under #ifdef SGFX_ENVIRONMENT.
uniform samplerCube sgfx_envSpecular; // level k: GGX roughness k / (levels - 1)
uniform sampler2D sgfx_envBrdf;       // (A, B) over (N.V, roughness)
uniform vec3 sgfx_envSh[9];           // cosine-convolved, over π, times the intensity
uniform vec2 sgfx_envParams;          // x: intensity (specular), y: highest mip level

// The light a white Lambert surface facing N reflects (irradiance over π).
vec3 sgfx_environmentDiffuse(vec3 N) {
    vec3 e = sgfx_envSh[0] * 0.282095;
    e += 0.488603 * (sgfx_envSh[1] * N.y + sgfx_envSh[2] * N.z + sgfx_envSh[3] * N.x);
    e += 1.092548 * (sgfx_envSh[4] * N.x * N.y + sgfx_envSh[5] * N.y * N.z + sgfx_envSh[7] * N.x * N.z);
    e += 0.315392 * sgfx_envSh[6] * (3.0 * N.z * N.z - 1.0) + 0.546274 * sgfx_envSh[8] * (N.x * N.x - N.y * N.y);
    return max(e, vec3(0.0));
}

// Split-sum scale and bias of F0: the lobe's directional albedo is F0 * A + B.
vec2 sgfx_environmentBrdf(float NdotV, float roughness) {
    return texture(sgfx_envBrdf, vec2(NdotV, roughness)).rg;
}

// Prefiltered radiance around the mirror direction R for a perceptual roughness.
vec3 sgfx_environmentRadiance(vec3 R, float roughness) {
    return sgfx_envParams.x * textureLod(sgfx_envSpecular, R, roughness * sgfx_envParams.y).rgb;
}

// The specular light a surface of roughness and F0 reflects towards V.
vec3 sgfx_environmentSpecular(vec3 N, vec3 V, float roughness, vec3 f0) {
    vec2 ab = sgfx_environmentBrdf(max(dot(N, V), 1e-4), roughness);
    return sgfx_environmentRadiance(reflect(-V, N), roughness) * (f0 * ab.x + ab.y);
}

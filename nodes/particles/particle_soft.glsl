// Soft particles: coverage fades where the particle comes within u_softness metres of the
// opaque surface behind it, so sprites do not show a hard line where they cut the ground.
#define SGFX_BASE_MODIFIER
uniform sampler2D sgfx_particleSceneDepth; // the scene depth, on a unit the renderer picks
uniform float sgfx_particleSoftness; // m; 0 = off

float particleLinearDepth(float windowZ) {
    float ndcZ = windowZ * 2.0 - 1.0;
    return sgfx_projection[2][3] != 0.0 ? sgfx_projection[3][2] / (ndcZ + sgfx_projection[2][2])
                                        : (sgfx_projection[3][2] - ndcZ) / sgfx_projection[2][2];
}

void sgfx_modifyBase(inout vec4 base, inout float coverage) {
    float scene = texelFetch(sgfx_particleSceneDepth, ivec2(gl_FragCoord.xy), 0).r;
    float gap = particleLinearDepth(scene) - particleLinearDepth(gl_FragCoord.z);
    coverage *= sgfx_particleSoftness > 0.0 ? clamp(gap / sgfx_particleSoftness, 0.0, 1.0) : 1.0;
}

#version 450 core
// Point-sprite path (sprites only): one vertex per particle, the rasterizer makes the square.
// The square is aligned with the screen rather than turned towards the eye as the seed's
// sprite is (the same square on the axis, a little different off it) and its side is clamped to
// the driver's largest point size; gl_PointCoord runs over it as the texture coordinate.
#include "particle_shape.glsl"

layout(location = 0) in vec4 a_state; // age, position

out vec3 v_worldPos;
out vec3 v_worldNormal;
out vec4 v_color;

// @sgfx:vertex_decl

void main() {
    float age = a_state.x;
    vec3 sgfx_worldPos = a_state.yzw;
    vec3 sgfx_worldNormal = particleTowardsEye(sgfx_worldPos); // N of the seed's sprite
    vec4 sgfx_viewPos = sgfx_view * vec4(sgfx_worldPos, 1.0);
    // @sgfx:vertex
    float life = particleLife(age);
    v_worldPos = sgfx_worldPos;
    v_worldNormal = sgfx_worldNormal;
    v_color = mix(u_colorStart, u_colorEnd, life);
    gl_Position = sgfx_projection * sgfx_viewPos;
    // Side k at view depth d: k · f / d pixels, f = projection[1][1] · height / 2; an
    // orthographic projection (projection[2][3] = 0) does not shrink with depth.
    float depth = sgfx_projection[2][3] != 0.0 ? max(-sgfx_viewPos.z, 1e-4) : 1.0;
    gl_PointSize = age < 0.0 || sgfx_viewPos.z >= 0.0
                       ? 0.0
                       : mix(u_size.x, u_size.y, life) * sgfx_projection[1][1] * 0.5 * sgfx_viewport.w / depth;
    if (age < 0.0) gl_Position = vec4(2.0, 2.0, 2.0, 1.0);
}

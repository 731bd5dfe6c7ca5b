// Per-frame data shared by every program (std140 uniform block at binding 0).
layout(std140, binding = 0) uniform SgfxFrame {
    mat4 sgfx_view;
    mat4 sgfx_projection;
    mat4 sgfx_viewProjection;
    mat4 sgfx_invViewProjection;
    vec4 sgfx_eye;          // xyz: camera position, world
    vec4 sgfx_viewport;     // x, y, width, height in pixels
    vec4 sgfx_ambientLight; // rgb: sum of ambient lights
    vec4 sgfx_time;         // x: seconds
    // x: number of lights below (at most 8: with the light list, its first 8 lights, so foreign
    // shaders keep seeing up to 8); light list only (lights.glsl): y: how many lights have no
    // range and light every tile, z: tiles per row, w: tile size in pixels
    ivec4 sgfx_lightCount;
    vec4 sgfx_lightVector[8]; // w = 0: direction towards the light; w = 1: position
    vec4 sgfx_lightColor[8];  // rgb: colour x intensity (range, cone, falloff: lights.glsl)
};

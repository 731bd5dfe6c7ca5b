// ShadowNode: the sun's cascaded shadow maps in one depth atlas (ShadowNode.cpp, applyUniforms).
uniform sampler2DShadow sgfx_shadowMap; // the atlas through a comparison sampler (LEQUAL, bilinear)
uniform vec4 sgfx_shadowCascadeMap[4]; // light space (V_L·P) to atlas: xy·scale (xy) + offset (zw)
uniform vec2 sgfx_shadowDepthMap;      // light-space z to the map's depth: z·x + y (every cascade)
uniform vec4 sgfx_shadowTile[4];        // each cascade's tile in atlas coordinates, half a texel in
uniform vec4 sgfx_shadowSplits;         // C_1..C_N: the view depth where each cascade ends
uniform vec4 sgfx_shadowBandStart;      // where each blends into the next (the last: fades out)
uniform vec4 sgfx_shadowTexel;          // t: a texel of each cascade, metres
uniform mat3 sgfx_shadowRotation;       // V_L: world to light space, rows right, up, L
uniform vec4 sgfx_shadowLight;          // xyz: unit vector towards the sun; w: 1 / depth range, metres
uniform vec4 sgfx_shadowBias;           // constant, slope, max slope, normal offset (plan §5)
uniform vec4 sgfx_shadowFilter;         // x: disc radius R_k (texels), yz: 1 / atlas size, w: density
uniform ivec4 sgfx_shadowSun;           // x: the sun's index among the view's lights (−1: none),
                                        // y: cascades, z: 1 = PCF early-out
#ifdef SGFX_SHADOW_SPOTS
// Spot lights, up to 3: perspective maps in the atlas's second row.
uniform mat4 sgfx_shadowSpotMatrix[3]; // world to atlas: xy / w in [0, 1], z / w the map's depth
uniform vec4 sgfx_shadowSpotTile[3];   // tile rectangles, as sgfx_shadowTile
uniform vec4 sgfx_shadowSpotPos[3];    // xyz: the light's position
uniform vec4 sgfx_shadowSpotAxis[3];   // xyz: the unit axis it shines along
uniform vec4 sgfx_shadowSpot[3];       // x: near, y: far, z: a texel per metre of depth (2·tan(fovy/2)/S)
uniform ivec4 sgfx_shadowSpots;        // each slot's light index in the view (−1: none)
#endif

#version 450 core
// The volume's bounding box, 36 vertices from gl_VertexID (faces wound outwards). Drawn with
// front faces culled, so each pixel's ray starts from a back face and the camera may be inside
// (lecture 12, "Volume rendering: raymarching").
uniform mat4 sgfx_model;
uniform vec3 u_boxSize;

out vec3 v_worldPos;

// @sgfx:vertex_decl

void main() {
    const int corners[36] = int[36](0, 4, 6, 0, 6, 2, 1, 3, 7, 1, 7, 5, 0, 1, 5, 0, 5, 4, 2, 6, 7, 2, 7, 3, 0, 2,
                                    3, 0, 3, 1, 4, 5, 7, 4, 7, 6);
    int c = corners[gl_VertexID];
    vec3 local = (vec3(c & 1, (c >> 1) & 1, (c >> 2) & 1) - 0.5) * u_boxSize;
    vec3 sgfx_worldPos = (sgfx_model * vec4(local, 1.0)).xyz;
    vec3 sgfx_worldNormal = vec3(0.0, 0.0, 1.0);
    vec4 sgfx_viewPos = sgfx_view * vec4(sgfx_worldPos, 1.0);
    // @sgfx:vertex
    v_worldPos = sgfx_worldPos;
    gl_Position = sgfx_projection * sgfx_viewPos;
}

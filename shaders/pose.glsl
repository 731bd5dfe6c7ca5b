// Posed vertices (issue 26), in mesh space before the model matrix: morph targets, then skinning.
// glTF 2.0, Meshes, Morph Targets: p = p0 + Σ w_i·d_i (normals and tangents likewise).
// glTF 2.0, Skins: p' = Σ_k w_k·J[j_k]·p with J = inverse(mesh world)·joint world·inverse bind.
// Included by the built-in material's vertex stage and by the wrap of a foreign vertex shader.
#ifdef SGFX_MORPHED
// Displacements, vertex-major per target: positions of target t at t·count + v, normals from
// sgfx_morphLayout.z, tangents from .w (-1: the targets have none).
layout(std430, binding = SGFX_MORPH_BINDING) readonly buffer SgfxMorph {
    vec4 sgfx_morphDeltas[];
};
layout(std430, binding = SGFX_MORPH_WEIGHTS_BINDING) readonly buffer SgfxMorphWeights {
    float sgfx_morphWeights[];
};
uniform ivec4 sgfx_morphLayout; // targets, vertices, first normal, first tangent

void sgfx_morph(inout vec3 position, inout vec3 normal, inout vec3 tangent) {
    const int targets = min(sgfx_morphLayout.x, sgfx_morphWeights.length());
    const int count = sgfx_morphLayout.y;
    for (int t = 0; t < targets; ++t) {
        const float w = sgfx_morphWeights[t];
        if (w == 0.0) continue;
        const int at = t * count + gl_VertexID;
        position += w * sgfx_morphDeltas[at].xyz;
        if (sgfx_morphLayout.z >= 0) normal += w * sgfx_morphDeltas[sgfx_morphLayout.z + at].xyz;
        if (sgfx_morphLayout.w >= 0) tangent += w * sgfx_morphDeltas[sgfx_morphLayout.w + at].xyz;
    }
}
#endif

#ifdef SGFX_SKINNED
layout(location = 10) in uvec4 a_joints0;
layout(location = 11) in vec4 a_weights0;
layout(location = 12) in uvec4 a_joints1; // absent: reads 0 with weight 0
layout(location = 13) in vec4 a_weights1;
layout(std430, binding = SGFX_JOINTS_BINDING) readonly buffer SgfxJoints {
    mat4 sgfx_jointMatrices[];
};

// The weighted sum of the vertex's joint matrices (weights sum to 1: normalised at load). Joint
// indices are checked at load; the clamp keeps a stale index inside the buffer all the same.
mat4 sgfx_joint(uint j) {
    return sgfx_jointMatrices[min(j, uint(sgfx_jointMatrices.length() - 1))];
}
mat4 sgfx_skinMatrix() {
    mat4 m = a_weights0.x * sgfx_joint(a_joints0.x) + a_weights0.y * sgfx_joint(a_joints0.y) +
             a_weights0.z * sgfx_joint(a_joints0.z) + a_weights0.w * sgfx_joint(a_joints0.w);
    if (a_weights1 != vec4(0.0))
        m += a_weights1.x * sgfx_joint(a_joints1.x) + a_weights1.y * sgfx_joint(a_joints1.y) +
             a_weights1.z * sgfx_joint(a_joints1.z) + a_weights1.w * sgfx_joint(a_joints1.w);
    return m;
}
#endif

// Poses one vertex; the normal goes through the cofactor matrix (the inverse transpose up to a
// positive scale), since joints may scale unevenly.
void sgfx_pose(inout vec3 position, inout vec3 normal, inout vec3 tangent) {
#ifdef SGFX_MORPHED
    sgfx_morph(position, normal, tangent);
#endif
#ifdef SGFX_SKINNED
    const mat4 s = sgfx_skinMatrix();
    const mat3 m = mat3(s);
    position = (s * vec4(position, 1.0)).xyz;
    normal = mat3(cross(m[1], m[2]), cross(m[2], m[0]), cross(m[0], m[1])) * normal *
             (determinant(m) < 0.0 ? -1.0 : 1.0);
    tangent = m * tangent;
#endif
}

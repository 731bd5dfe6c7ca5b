// The scene seen in direction d (display frame): the cube face of d's major axis, looked up through
// that face camera's own view-projection, so the lookup matches what the face rendered.
uniform sampler2D sphere_face0, sphere_face1, sphere_face2, sphere_face3, sphere_face4, sphere_face5;
uniform mat4 sphere_faceMatrix0, sphere_faceMatrix1, sphere_faceMatrix2, sphere_faceMatrix3,
    sphere_faceMatrix4, sphere_faceMatrix5;

vec2 sphereFaceUv(mat4 m, vec3 d) {
    vec4 clip = m * vec4(d, 1.0);
    return clip.xy / clip.w * 0.5 + 0.5;
}

vec3 sphereScene(vec3 d) {
    vec3 a = abs(d);
    if (a.x >= a.y && a.x >= a.z)
        return d.x > 0.0 ? texture(sphere_face0, sphereFaceUv(sphere_faceMatrix0, d)).rgb
                         : texture(sphere_face1, sphereFaceUv(sphere_faceMatrix1, d)).rgb;
    if (a.y >= a.z)
        return d.y > 0.0 ? texture(sphere_face2, sphereFaceUv(sphere_faceMatrix2, d)).rgb
                         : texture(sphere_face3, sphereFaceUv(sphere_faceMatrix3, d)).rgb;
    return d.z > 0.0 ? texture(sphere_face4, sphereFaceUv(sphere_faceMatrix4, d)).rgb
                     : texture(sphere_face5, sphereFaceUv(sphere_faceMatrix5, d)).rgb;
}

// View-space geometry for the occlusion pass: rebuilding positions from linear depth, projecting
// to G-buffer pixels, and the depth of a pixel's tangent plane along another view ray.
uniform sampler2D sgfx_aoGNormal;   // view-space normal
uniform sampler2D sgfx_aoGDepth;    // linear view depth (0 = nothing drawn)
uniform sampler2D sgfx_aoGPosition; // view-space position (seed's G_pos)

bool sgfx_aoPerspective() {
    return sgfx_projection[2][3] != 0.0;
}

// P_vcs of G-buffer pixel `p` whose linear depth is `d` (`size`: the G-buffer's size).
vec3 sgfx_aoPosition(ivec2 p, float d, vec2 size) {
#ifdef SGFX_AO_POSITIONS
    return texelFetch(sgfx_aoGPosition, p, 0).xyz;
#else
    vec2 ndc = (vec2(p) + 0.5) / size * 2.0 - 1.0;
    if (sgfx_aoPerspective())
        return vec3((ndc + vec2(sgfx_projection[2][0], sgfx_projection[2][1])) * d /
                        vec2(sgfx_projection[0][0], sgfx_projection[1][1]),
                    -d);
    return vec3((ndc - vec2(sgfx_projection[3][0], sgfx_projection[3][1])) /
                    vec2(sgfx_projection[0][0], sgfx_projection[1][1]),
                -d);
#endif
}

// View z of the plane through `pt` with normal `nt` where the view ray through `a` meets it
// (`a`'s own z when the plane is edge-on or behind).
float sgfx_aoPlaneDepth(vec3 pt, vec3 nt, vec3 a) {
    if (sgfx_aoPerspective()) {
        float den = dot(nt, a);
        if (abs(den) < 1e-6 * length(a)) return pt.z;
        float s = dot(nt, pt) / den;
        return s > 0.0 ? s * a.z : pt.z;
    }
    if (abs(nt.z) < 1e-4) return pt.z;
    return pt.z - (nt.x * (a.x - pt.x) + nt.y * (a.y - pt.y)) / nt.z;
}

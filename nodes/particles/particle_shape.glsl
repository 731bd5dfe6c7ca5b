// The polygons of one particle (seed, section "Визуализация массива частиц"). Each shape is a
// few triangle strips in a local frame of unit size: the sprite faces the camera, the others are
// turned by MR from the particle's angles. Shared by the geometry-shader and instanced paths.
// SGFX_PARTICLE_SHAPE is compiled in (0 sprite, 1 hexagon, 2 tetrahedron, 3 quad): a software
// rasterizer runs both sides of every branch, so no shape pays for another's code.
uniform vec2 u_size;       // k at birth and at tmax (m)
uniform vec4 u_colorStart; // colour × opacity at birth and at tmax (linear)
uniform vec4 u_colorEnd;
uniform float u_tmax;
uniform float u_krot;
uniform float u_stretch;   // tetrahedra: lengthened along v by 1 + stretch·|v|

#if SGFX_PARTICLE_SHAPE == 2
const int kShapeStrips = 4, kShapeStripLength = 3;
#elif SGFX_PARTICLE_SHAPE == 1
const int kShapeStrips = 1, kShapeStripLength = 6;
#else
const int kShapeStrips = 1, kShapeStripLength = 4;
#endif

// Corner `k` of strip `strip`: position (units of k), outward normal, texture coordinate.
void shapeCorner(int strip, int k, out vec3 local, out vec3 normal, out vec2 uv) {
#if SGFX_PARTICLE_SHAPE == 1
    // Hexagon of circumradius ½ as one strip: corners 0 1 5 2 4 3.
    const int order[6] = int[6](0, 1, 5, 2, 4, 3);
    float a = float(order[k]) * (6.28318530717958647692 / 6.0);
    local = 0.5 * vec3(cos(a), sin(a), 0.0);
    normal = vec3(0.0, 0.0, 1.0);
    uv = local.xy + 0.5;
#elif SGFX_PARTICLE_SHAPE == 2
    // Regular tetrahedron of edge 1; strip `strip` is the face opposite corner `strip`.
    const vec3 corners[4] = vec3[4](vec3(1, 1, 1), vec3(1, -1, -1), vec3(-1, 1, -1), vec3(-1, -1, 1));
    int c = k < strip ? k : k + 1;
    local = corners[c] * 0.35355339059327373; // 1 / (2·√2)
    normal = -normalize(corners[strip]);
    uv = vec2(k == 1 ? 1.0 : 0.0, k == 2 ? 1.0 : 0.0);
#else
    // Sprite and quad: V0 = ½(A − B), V1 = V0 + B, V2 = V0 − A, V3 = V1 − A (seed).
    vec2 ab = vec2((k & 2) != 0 ? -0.5 : 0.5, (k & 1) != 0 ? 0.5 : -0.5);
    local = vec3(ab, 0.0);
    normal = vec3(0.0, 0.0, 1.0);
    uv = ab + 0.5;
#endif
}

mat3 rotationX(float a) { return mat3(1, 0, 0, 0, cos(a), sin(a), 0, -sin(a), cos(a)); }
mat3 rotationY(float a) { return mat3(cos(a), 0, -sin(a), 0, 1, 0, sin(a), 0, cos(a)); }
mat3 rotationZ(float a) { return mat3(cos(a), sin(a), 0, -sin(a), cos(a), 0, 0, 0, 1); }

// The seed's sprite normal N: towards the eye. A particle at the eye has no direction to it, so
// the view's own back axis stands in rather than normalising a zero vector.
vec3 particleTowardsEye(vec3 position) {
    vec3 toEye = sgfx_eye.xyz - position;
    return dot(toEye, toEye) > 1e-12 ? normalize(toEye) : vec3(sgfx_view[0][2], sgfx_view[1][2], sgfx_view[2][2]);
}

// The frame a particle's corners are given in: for the sprite the seed's A, B, N (N towards the
// eye, A = Y×N/|Y×N|, B = N×A); otherwise MR = Mx(α)·My(β)·Mz(γ), α = r0x + (|rx| − krot), ...
mat3 particleFrame(vec3 position, vec3 angles0, vec3 angles) {
#if SGFX_PARTICLE_SHAPE == 0
    vec3 N = particleTowardsEye(position);
    vec3 Y = vec3(sgfx_view[0][1], sgfx_view[1][1], sgfx_view[2][1]); // view Y in world
    vec3 across = cross(Y, N); // zero for a particle straight above the eye: the view's X stands in
    vec3 A = dot(across, across) > 1e-12 ? normalize(across) : vec3(sgfx_view[0][0], sgfx_view[1][0], sgfx_view[2][0]);
    vec3 B = cross(N, A); // unit: N ⟂ A
    return mat3(A, B, N);
#else
    vec3 turn = angles0 + (abs(angles) - u_krot);
    return rotationX(turn.x) * rotationY(turn.y) * rotationZ(turn.z);
#endif
}

// World position of a corner; tetrahedra are lengthened along the velocity (streaks).
vec3 particleCorner(vec3 position, vec3 velocity, mat3 frame, float size, vec3 local) {
    vec3 w = frame * (local * size);
#if SGFX_PARTICLE_SHAPE == 2
    float speed = length(velocity);
    if (u_stretch > 0.0 && speed > 0.0) {
        vec3 d = velocity / speed;
        w += d * dot(w, d) * (u_stretch * speed);
    }
#endif
    return position + w;
}

float particleLife(float age) { return clamp(age / u_tmax, 0.0, 1.0); }

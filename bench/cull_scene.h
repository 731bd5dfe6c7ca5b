#pragma once
// The cull-traversal scene shared by the sgfx side (cull_bench, sgfx_cull) and the OpenSceneGraph
// peer (osg_cull), so both cull exactly the same graph from exactly the same camera. Plain C++ on
// purpose: no sgfx or OSG types, each side builds its own nodes through the callbacks below.
//
// Scene: N leaves on an nx × ny × nz grid (Z up), each a small box under its own translation
// Transform; above them a balanced tree of Groups with fan-out 8 over the leaves in Morton order
// (so each Group holds a compact block of space).
// Camera: looks along +x+y from -y, yawed so the frustum's left plane runs between the two middle
// x columns: exactly the nx/2 far columns are in view (half the leaves when nx is even), and the
// other planes hold all of them, with each box >= 2 px in radius (so OSG's default small-feature
// culling drops none).
//
// Mixed-state variant (--mixed, both sides): each leaf Transform also rotates its box about a
// tilted axis and scales it non-uniformly (factors in [0.7, 1], so every bounding sphere shrinks
// and the camera keeps exactly the same leaves: leafMatrix), and the leaves use 8 distinct boxes,
// each with its own material (StateSet): stateOf.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

namespace cullscene {

constexpr float kBoxSize = 1.2f; // full edge; bounding-sphere radius = kBoxSize * sqrt(3) / 2
constexpr float kSpacing = 1.5f; // distance between neighbouring box centres
constexpr int kWidth = 1920, kHeight = 1080;
constexpr float kPi = 3.14159265358979f;

struct Dims {
    int nx, ny, nz;
    long count() const { return long(nx) * ny * nz; }
};

// The three sizes of the issue exactly (nx even), anything else roughly cubic.
inline Dims dims(long n) {
    if (n == 10000) return {20, 25, 20};
    if (n == 100000) return {50, 40, 50};
    if (n == 1000000) return {100, 100, 100};
    int nx = std::max(2, 2 * int(std::lround(std::cbrt(double(n)) / 2)));
    const int ny = std::max(1, int(std::lround(std::sqrt(double(n) / nx))));
    const int nz = std::max(1, int((n + long(nx) * ny - 1) / (long(nx) * ny)));
    return {nx, ny, nz};
}

inline float boxRadius() {
    return kBoxSize * std::sqrt(3.0f) * 0.5f;
}

// Centre of cell (i, j, k).
inline void cellCenter(int i, int j, int k, float out[3]) {
    out[0] = float(i) * kSpacing;
    out[1] = float(j) * kSpacing;
    out[2] = float(k) * kSpacing;
}

// --mixed: which of the 8 boxes (StateSets) cell (i, j, k) uses.
constexpr int kStates = 8;
inline int stateOf(int i, int j, int k) {
    return (i + 3 * j + 5 * k) % kStates;
}

// The leaf matrix of cell (i, j, k), column-major (OpenGL's and osg::Matrixf's memory layout):
// translate(centre) * rotate(angle, axis) * scale(s) when mixed, else the translation alone.
inline void leafMatrix(int i, int j, int k, bool mixed, float m[16]) {
    float c[3];
    cellCenter(i, j, k, c);
    float r[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}; // rotation * scale, column-major 3x3
    if (mixed) {
        const float angle = 2.0f * kPi * float((7 * i + 13 * j + 17 * k) % 31) / 31.0f;
        const float len = std::sqrt(14.0f), x = 1.0f / len, y = 2.0f / len, z = 3.0f / len;
        const float co = std::cos(angle), si = std::sin(angle), t = 1.0f - co;
        // Rodrigues' rotation matrix about (x, y, z), column-major.
        const float rot[9] = {t * x * x + co,     t * x * y + si * z, t * x * z - si * y,
                              t * x * y - si * z, t * y * y + co,     t * y * z + si * x,
                              t * x * z + si * y, t * y * z - si * x, t * z * z + co};
        const float s[3] = {0.7f + 0.1f * float((5 * i + k) % 4), 0.7f + 0.1f * float((3 * j + i) % 4),
                            0.7f + 0.1f * float((7 * k + j) % 4)};
        for (int col = 0; col < 3; ++col)
            for (int row = 0; row < 3; ++row)
                r[col * 3 + row] = rot[col * 3 + row] * s[col];
    }
    for (int col = 0; col < 3; ++col) {
        for (int row = 0; row < 3; ++row)
            m[col * 4 + row] = r[col * 3 + row];
        m[col * 4 + 3] = 0.0f;
    }
    m[12] = c[0], m[13] = c[1], m[14] = c[2], m[15] = 1.0f;
}

// The colour of box `state` under --mixed (each box its own material).
inline void stateColour(int state, float rgb[3]) {
    for (int c = 0; c < 3; ++c)
        rgb[c] = 0.3f + 0.4f * float((state >> c) & 1);
}

struct View {
    float eye[3], center[3], up[3];
    float fovyDegrees, aspect, zNear, zFar;
    int width, height;
};

inline View view(const Dims& d) {
    const float r = boxRadius();
    // Left plane: just outside the spheres of column nx/2 - 1, so that column is culled and
    // column nx/2 (its centre kSpacing - r - 0.05 inside) is kept.
    const float xm = float(d.nx / 2 - 1) * kSpacing + r + 0.05f;
    const float zc = float(d.nz - 1) * kSpacing * 0.5f;
    const float hz = zc + r; // half height of the grid, spheres included
    // 45° horizontal half-angle, so yawing by 45° puts the left plane on x = xm and the right
    // plane on y = eye.y. tan(vertical half-angle) = 1 / aspect.
    const float aspect = float(kWidth) / float(kHeight);
    const float tanV = 1.0f / aspect;
    const float s = std::sqrt(0.5f);
    // Nearest depth of any kept sphere is s * D; the grid's height must fit there.
    const float dist = 1.1f * hz / (s * tanV) + 2.0f;
    View v{};
    v.eye[0] = xm;
    v.eye[1] = -dist;
    v.eye[2] = zc;
    v.center[0] = xm + s;
    v.center[1] = -dist + s;
    v.center[2] = zc;
    v.up[0] = 0, v.up[1] = 0, v.up[2] = 1;
    v.fovyDegrees = 2.0f * std::atan(tanV) * 180.0f / kPi;
    v.aspect = aspect;
    v.zNear = 1.0f;
    const float farX = float(d.nx - 1) * kSpacing - xm, farY = float(d.ny - 1) * kSpacing + dist;
    v.zFar = 1.1f * (s * (farX + farY) + r) + 10.0f;
    v.width = kWidth;
    v.height = kHeight;
    return v;
}

// Morton code of a cell: neighbours in space are neighbours in the code.
inline unsigned long long morton(int i, int j, int k) {
    unsigned long long code = 0;
    for (int b = 0; b < 21; ++b)
        code |= (((unsigned long long)(i >> b) & 1u) << (3 * b)) |
                (((unsigned long long)(j >> b) & 1u) << (3 * b + 1)) |
                (((unsigned long long)(k >> b) & 1u) << (3 * b + 2));
    return code;
}

// Builds the tree bottom-up: the leaves in Morton order, packed 8 to a Group, those Groups 8 to
// a Group, and so on up to one root (fan-out 8 everywhere but the last Group of each level).
// makeLeaf(i, j, k) returns the leaf Transform of a cell, makeGroup(std::vector<NodeT>&&) a
// Group holding the given children.
template <class NodeT, class MakeGroup, class MakeLeaf>
NodeT build(const Dims& d, MakeGroup&& makeGroup, MakeLeaf&& makeLeaf) {
    struct Cell {
        unsigned long long code;
        int i, j, k;
    };
    std::vector<Cell> cells;
    cells.reserve(std::size_t(d.count()));
    for (int k = 0; k < d.nz; ++k)
        for (int j = 0; j < d.ny; ++j)
            for (int i = 0; i < d.nx; ++i)
                cells.push_back({morton(i, j, k), i, j, k});
    std::sort(cells.begin(), cells.end(), [](const Cell& a, const Cell& b) { return a.code < b.code; });
    std::vector<NodeT> level;
    level.reserve(cells.size());
    for (const Cell& c : cells)
        level.push_back(makeLeaf(c.i, c.j, c.k));
    do {
        std::vector<NodeT> up;
        up.reserve(level.size() / 8 + 1);
        for (std::size_t b = 0; b < level.size(); b += 8) {
            std::vector<NodeT> children;
            for (std::size_t c = b; c < std::min(level.size(), b + 8); ++c)
                children.push_back(std::move(level[c]));
            up.push_back(makeGroup(std::move(children)));
        }
        level = std::move(up);
    } while (level.size() > 1);
    return std::move(level.front());
}

// Frames to time at a size: about 3·10^6 leaf visits, at least 7.
inline int defaultFrames(long n) {
    return int(std::clamp(3000000L / std::max(1L, n), 7L, 300L));
}

// The command line both sides take: --n N, --frames F, --no-memory, --mixed, and (OSG only)
// --no-geode.
struct Args {
    long n = 10000;
    int frames = 0; // 0: defaultFrames(n)
    bool memory = true, geode = true, mixed = false;
};
// Returns false (after printing the usage) for an unknown option or a bad number.
inline bool parseArgs(int argc, char** argv, const char* program, bool geodeOption, Args& a) {
    for (int i = 1; i < argc; ++i) {
        char* end = nullptr;
        if (!std::strcmp(argv[i], "--n") && i + 1 < argc) {
            a.n = std::strtol(argv[++i], &end, 10);
            if (*end || a.n < 1) a.n = -1;
        } else if (!std::strcmp(argv[i], "--frames") && i + 1 < argc) {
            a.frames = int(std::strtol(argv[++i], &end, 10));
            if (*end || a.frames < 0) a.n = -1;
        } else if (!std::strcmp(argv[i], "--no-memory")) {
            a.memory = false;
        } else if (!std::strcmp(argv[i], "--mixed")) {
            a.mixed = true;
        } else if (geodeOption && !std::strcmp(argv[i], "--no-geode")) {
            a.geode = false;
        } else {
            a.n = -1;
        }
        if (a.n < 0) {
            std::fprintf(stderr, "usage: %s [--n N] [--frames F] [--no-memory] [--mixed]%s\n", program,
                         geodeOption ? " [--no-geode]" : "");
            return false;
        }
    }
    if (a.frames == 0) a.frames = defaultFrames(a.n);
    return true;
}

// Median of a sample (sorted in place).
inline double median(std::vector<double>& v) {
    std::sort(v.begin(), v.end());
    const std::size_t m = v.size() / 2;
    return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

} // namespace cullscene

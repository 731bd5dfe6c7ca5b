// Levels of detail made at load with meshoptimizer's simplifier, and the independent measure of
// their error that sets their ranges (MeshOptimize.h).
#include "sgfx/MeshOptimize.h"

#include <sgfx/Group.h>
#include <sgfx/Math.h>
#include <sgfx/TriangleBvh.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>
#include <unordered_set>

#if SGFX_HAVE_MESHOPTIMIZER
#include <meshoptimizer.h>
#endif

namespace sgfx {

namespace {

float boxDistance2(glm::vec3 p, glm::vec3 lo, glm::vec3 hi) {
    const glm::vec3 d = glm::max(glm::max(lo - p, p - hi), glm::vec3(0.0f));
    return glm::dot(d, d);
}

float triangleDistance2(const std::vector<glm::vec3>& corners, std::uint32_t t, glm::vec3 p) {
    const glm::vec3 a = corners[3 * t], b = corners[3 * t + 1], c = corners[3 * t + 2];
    const glm::vec3 w = closestOnTriangle(p, a, b, c);
    const glm::vec3 q = w.x * a + w.y * b + w.z * c;
    return glm::dot(p - q, p - q);
}

// Squared distance from p to the nearest triangle of the BVH (depth-first, nearer child first).
// `hint` is the triangle nearest to the previous, nearby sample: starting from its distance prunes
// most of the tree at once; it becomes this sample's nearest.
float surfaceDistance2(const TriangleBvh& bvh, glm::vec3 p, std::uint32_t& hint) {
    const auto& nodes = bvh.bvh().nodes;
    const auto& corners = bvh.corners();
    float best = std::numeric_limits<float>::max();
    if (nodes.empty()) return best;
    if (3 * std::size_t(hint) + 2 < corners.size()) best = triangleDistance2(corners, hint, p);
    std::uint32_t stack[64];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
        const auto& n = nodes[stack[--top]];
        if (boxDistance2(p, n.min, n.max) >= best) continue;
        if (n.count > 0) {
            for (std::uint32_t t = n.first; t < n.first + n.count; ++t) {
                const float d2 = triangleDistance2(corners, t, p);
                if (d2 < best) best = d2, hint = t;
            }
            continue;
        }
        const std::uint32_t a = std::uint32_t(&n - nodes.data()) + 1, b = n.first;
        const bool aNear =
            boxDistance2(p, nodes[a].min, nodes[a].max) <= boxDistance2(p, nodes[b].min, nodes[b].max);
        if (top + 2 > 64) continue; // deeper than any SAH tree over 2^32 triangles
        stack[top++] = aNear ? b : a;
        stack[top++] = aNear ? a : b;
    }
    return best;
}

// Largest distance from a sample of `from`'s triangles to `to`'s surface.
float oneSided(const Geometry& from, const TriangleBvh& to) {
    static const glm::vec3 weights[8] = {{1, 0, 0},
                                         {0, 1, 0},
                                         {0, 0, 1},
                                         {0.5f, 0.5f, 0},
                                         {0, 0.5f, 0.5f},
                                         {0.5f, 0, 0.5f},
                                         {1.0f / 3, 1.0f / 3, 1.0f / 3},
                                         {2.0f / 3, 1.0f / 6, 1.0f / 6}};
    float worst = 0.0f;
    std::uint32_t hint = 0;
    for (const auto& t : triangleIndices(from)) {
        const glm::vec3 a = from.positions[t[0]], b = from.positions[t[1]], c = from.positions[t[2]];
        for (const glm::vec3& w : weights)
            worst = std::max(worst, surfaceDistance2(to, w.x * a + w.y * b + w.z * c, hint));
    }
    return std::sqrt(worst);
}

std::string refusal(const Geometry& g, const AutoLodOptions& o) {
    if (!meshOptimizerAvailable()) return "sgfx was built without meshoptimizer (libmeshoptimizer-dev)";
    if (g.mode != PrimitiveMode::Triangles || g.indices.empty())
        return "not indexed PrimitiveMode::Triangles";
    if (g.posed() || !g.joints0.empty() || !g.morphTargets.empty()) return "skinned or morphed";
    if (!g.instances.empty()) return "instanced (the LOD's sphere would not hold the instances)";
    if (g.triangleCount() < 2 * std::max<std::size_t>(o.minTriangles, 1)) return "too few triangles";
    if (!std::isfinite(o.errorPixels) || o.errorPixels <= 0.0f || !std::isfinite(o.focalPixels) ||
        o.focalPixels <= 0.0f)
        return "AutoLodOptions errorPixels and focalPixels must be finite and > 0";
    return "";
}

#if SGFX_HAVE_MESHOPTIMIZER
// A copy of `full` drawing `indices`, with only the vertices they use, in fetch order.
std::shared_ptr<Geometry> compacted(const Geometry& full, std::vector<unsigned> indices) {
    auto g = Geometry::create();
    g->name = full.name;
    g->setStateSet(full.stateSet());
    const std::size_t n = full.positions.size();
    meshopt_optimizeVertexCache(indices.data(), indices.data(), indices.size(), n);
    std::vector<unsigned> remap(n);
    const std::size_t used =
        meshopt_optimizeVertexFetchRemap(remap.data(), indices.data(), indices.size(), n);
    auto copy = [&](auto& dst, const auto& src) {
        if (src.empty()) return;
        dst.resize(used);
        meshopt_remapVertexBuffer(dst.data(), src.data(), n, sizeof(src[0]), remap.data());
    };
    copy(g->positions, full.positions), copy(g->normals, full.normals), copy(g->tangents, full.tangents);
    copy(g->texcoords, full.texcoords), copy(g->texcoords1, full.texcoords1), copy(g->colors, full.colors);
    meshopt_remapIndexBuffer(indices.data(), indices.data(), indices.size(), remap.data());
    g->indices = std::move(indices);
    return g;
}

// Levels of ½, ¼, ... of full's triangles, each simplified from full, with both errors.
std::vector<AutoLodLevel> simplifiedLevels(const Geometry& full, const AutoLodOptions& o) {
    const std::size_t n = full.indices.size(), vertices = full.positions.size();
    const float* pos = &full.positions[0].x;
    const float scale = meshopt_simplifyScale(pos, vertices, sizeof(glm::vec3));
    std::vector<AutoLodLevel> levels;
    std::size_t previous = n / 3;
    for (std::size_t target = n / 6; target >= o.minTriangles; target /= 2) {
        std::vector<unsigned> out(n);
        float error = 0.0f; // relative; target_error 1 lets the count decide
        out.resize(meshopt_simplify(out.data(), full.indices.data(), n, pos, vertices, sizeof(glm::vec3),
                                    target * 3, 1.0f,
                                    o.lockBorder ? unsigned(meshopt_SimplifyLockBorder) : 0u, &error));
        const std::size_t triangles = out.size() / 3;
        if (triangles < o.minTriangles || 5 * triangles > 4 * previous) break; // stuck or too coarse
        previous = triangles;
        AutoLodLevel level;
        level.geometry = compacted(full, std::move(out));
        level.simplifierError = error * scale;
        level.measuredError = hausdorffDistance(*level.geometry, full);
        levels.push_back(std::move(level));
    }
    return levels;
}
#endif

} // namespace

float hausdorffDistance(const Geometry& a, const Geometry& b) {
    const auto bvhA = a.triangleBvh(), bvhB = b.triangleBvh();
    return std::max(oneSided(a, *bvhB), oneSided(b, *bvhA));
}

std::shared_ptr<LOD> makeErrorLod(const std::shared_ptr<Geometry>& full, const AutoLodOptions& o,
                                  std::vector<AutoLodLevel>* levelsOut, std::string* reason) {
    std::string why = full ? refusal(*full, o) : "no geometry";
    std::vector<AutoLodLevel> levels;
#if SGFX_HAVE_MESHOPTIMIZER
    if (why.empty()) levels = simplifiedLevels(*full, o);
#endif
    if (why.empty() && levels.empty()) why = "no level removes a fifth of the triangles";
    if (reason) *reason = why;
    if (!why.empty()) return nullptr;
    const BoundingSphere sphere = full->bound();
    const float r = std::max(sphere.radius, 1e-6f), f = o.focalPixels;
    // p <= 2f / (1 + e f / (r t)): at p = 2 r f / d an error e seen from the sphere's nearest
    // point, d - r away, spans e f / (d - r) <= t pixels.
    auto largest = [&](float e) { return 2.0f * f / (1.0f + e * f / (r * o.errorPixels)); };
    float e = 0.0f;
    for (AutoLodLevel& level : levels) {
        e = std::max({e, level.simplifierError, level.measuredError});
        level.maxPixels = largest(e);
    }
    auto lod = LOD::create();
    lod->name = full->name + " (auto LOD)";
    lod->setUserSphere(sphere.center, r);
    lod->addChild(full, levels.front().maxPixels, std::numeric_limits<float>::infinity());
    for (std::size_t i = 0; i < levels.size(); ++i) {
        levels[i].minPixels = i + 1 < levels.size() ? levels[i + 1].maxPixels : 0.0f;
        lod->addChild(levels[i].geometry, levels[i].minPixels, levels[i].maxPixels);
    }
    if (levelsOut) *levelsOut = std::move(levels);
    return lod;
}

std::size_t addAutoLods(Node& root, const AutoLodOptions& o) {
    std::unordered_map<const Geometry*, std::shared_ptr<LOD>> made;
    std::unordered_set<const Node*> seen;
    std::size_t count = 0;
    auto visit = [&](auto& self, Node& node) -> void {
        auto* group = dynamic_cast<Group*>(&node);
        if (!group || dynamic_cast<LOD*>(&node) || !seen.insert(&node).second) return;
        for (std::size_t i = 0; i < group->numChildren(); ++i) {
            const NodePtr child = group->child(i);
            if (auto g = std::dynamic_pointer_cast<Geometry>(child)) {
                auto [it, added] = made.emplace(g.get(), nullptr);
                if (added) {
                    it->second = makeErrorLod(g, o);
                    count += it->second != nullptr;
                }
                if (it->second) group->replaceChild(i, it->second);
            } else if (child) {
                self(self, *child);
            }
        }
    };
    visit(visit, root);
    return count;
}

} // namespace sgfx

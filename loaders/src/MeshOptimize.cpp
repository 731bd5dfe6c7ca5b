#include "sgfx/MeshOptimize.h"

#include <sgfx/Group.h>
#include <sgfx/StateSet.h>

#include <cstdio>
#include <mutex>
#include <unordered_map>
#include <vector>

#if SGFX_HAVE_MESHOPTIMIZER
#include <meshoptimizer.h>
#endif

namespace sgfx {

namespace {

// Why the order of this geometry's triangles cannot change, or "" when it can.
std::string refusal(const Geometry& g) {
    if (!meshOptimizerAvailable()) return "sgfx was built without meshoptimizer (libmeshoptimizer-dev)";
    if (g.mode != PrimitiveMode::Triangles) return "not PrimitiveMode::Triangles";
    if (!g.joints0.empty() || !g.joints1.empty() || !g.weights0.empty() || !g.weights1.empty() ||
        !g.morphTargets.empty() || g.skin)
        return "skinned or morphed (its pose data is per vertex)";
    if (g.elementCount() % 3 != 0) return "its element count is not a multiple of 3";
    if (g.elementCount() < 6) return "fewer than two triangles";
    return "";
}

// Blending shows the triangle order, and so does drawing without a depth test or depth writes.
bool orderVisible(const ResolvedState& s) {
    const DepthState depth = s.depth.value.value_or(DepthState{});
    return s.transparent() || !depth.test || !depth.write;
}

#if SGFX_HAVE_MESHOPTIMIZER
template <class T> void addStream(std::vector<meshopt_Stream>& streams, std::vector<T>& v) {
    if (!v.empty()) streams.push_back({v.data(), sizeof(T), sizeof(T)});
}

template <class T>
void remapStream(std::vector<T>& v, const std::vector<unsigned>& remap, std::size_t oldCount,
                 std::size_t newCount) {
    if (v.empty()) return;
    std::vector<T> out(newCount);
    meshopt_remapVertexBuffer(out.data(), v.data(), oldCount, sizeof(T), remap.data());
    v = std::move(out);
}

void remapAll(Geometry& g, const std::vector<unsigned>& remap, std::size_t oldCount, std::size_t newCount) {
    remapStream(g.positions, remap, oldCount, newCount);
    remapStream(g.normals, remap, oldCount, newCount);
    remapStream(g.tangents, remap, oldCount, newCount);
    remapStream(g.texcoords, remap, oldCount, newCount);
    remapStream(g.texcoords1, remap, oldCount, newCount);
    remapStream(g.colors, remap, oldCount, newCount);
}

void reorder(Geometry& g, const MeshOrderOptions& o) {
    const std::size_t n = g.elementCount(), vertices = g.positions.size();
    // Weld vertices whose records are equal in every stream (an unindexed mesh gets indices here).
    std::vector<meshopt_Stream> streams;
    addStream(streams, g.positions);
    addStream(streams, g.normals);
    addStream(streams, g.tangents);
    addStream(streams, g.texcoords);
    addStream(streams, g.texcoords1);
    addStream(streams, g.colors);
    std::vector<unsigned> remap(vertices);
    const unsigned* source = g.indices.empty() ? nullptr : g.indices.data();
    const std::size_t unique =
        meshopt_generateVertexRemapMulti(remap.data(), source, n, vertices, streams.data(), streams.size());
    std::vector<unsigned> indices(n);
    meshopt_remapIndexBuffer(indices.data(), source, n, remap.data());
    remapAll(g, remap, vertices, unique);
    std::vector<unsigned> tmp(n);
    if (o.vertexCache) {
        meshopt_optimizeVertexCache(tmp.data(), indices.data(), n, unique);
        indices.swap(tmp);
    }
    if (o.overdrawThreshold > 0.0f) {
        meshopt_optimizeOverdraw(tmp.data(), indices.data(), n, &g.positions[0].x, unique, sizeof(glm::vec3),
                                 o.overdrawThreshold);
        indices.swap(tmp);
    }
    std::size_t used = unique;
    if (o.vertexFetch) {
        remap.assign(unique, 0);
        used = meshopt_optimizeVertexFetchRemap(remap.data(), indices.data(), n, unique);
        meshopt_remapIndexBuffer(indices.data(), indices.data(), n, remap.data());
        remapAll(g, remap, unique, used);
    }
    g.indices.assign(indices.begin(), indices.end());
    g.dirty();
}
#endif

void noticeOnce() {
    static std::once_flag once;
    std::call_once(once, [] {
        std::fprintf(stderr, "sgfx: meshoptimizer is not built in (libmeshoptimizer-dev): loaded meshes "
                             "keep their triangle order\n");
    });
}

void collect(Node& node, const ResolvedState& parent, std::unordered_map<Geometry*, bool>& geometries,
             std::unordered_map<const Node*, unsigned>& seen) {
    const ResolvedState state = node.stateSet() ? parent.merged(*node.stateSet()) : parent;
    const bool visible = orderVisible(state);
    // Each node once per kind of path (order visible or not) keeps shared subgraphs linear.
    unsigned& mask = seen[&node];
    if (mask & (visible ? 2u : 1u)) return;
    mask |= visible ? 2u : 1u;
    if (auto* g = dynamic_cast<Geometry*>(&node)) {
        auto [it, added] = geometries.emplace(g, visible);
        if (!added) it->second = it->second || visible;
    }
    if (auto* group = dynamic_cast<Group*>(&node))
        for (const NodePtr& child : group->children())
            if (child) collect(*child, state, geometries, seen);
}

} // namespace

bool meshOptimizerAvailable() {
    return SGFX_HAVE_MESHOPTIMIZER != 0;
}

bool optimizeMesh(Geometry& geometry, const MeshOrderOptions& options, std::string* reason) {
    (void)options; // unused without meshoptimizer
    std::string why = refusal(geometry);
    if (why.empty() && geometry.stateSet() &&
        orderVisible(ResolvedState::defaults().merged(*geometry.stateSet())))
        why = "its StateSet blends or draws without depth test or depth writes (the order is visible)";
    if (why.empty()) {
        geometry.validate(); // indices in range before meshoptimizer reads them
#if SGFX_HAVE_MESHOPTIMIZER
        reorder(geometry, options);
#endif
    }
    if (reason) *reason = why;
    return why.empty();
}

std::size_t optimizeMeshes(Node& root, const MeshOrderOptions& options) {
    if (!meshOptimizerAvailable()) {
        noticeOnce();
        return 0;
    }
    std::unordered_map<Geometry*, bool> geometries;
    std::unordered_map<const Node*, unsigned> seen;
    collect(root, ResolvedState::defaults(), geometries, seen);
    std::size_t done = 0;
    for (const auto& [g, visible] : geometries)
        if (!visible && optimizeMesh(*g, options)) ++done;
    return done;
}

} // namespace sgfx

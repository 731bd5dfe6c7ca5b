// Scene queries on the exported proving ground, sgfx side of bench/query_table.sh (osg_query is the
// OpenSceneGraph peer): the workloads of bench/query_workload.h through sgfx::LineSegmentIntersector
// and sgfx::IntersectionVisitor, one intersector and one visitor per query as an application asks.
//
//   query_bench FILE.obj [--terrain N] [--sight N] [--no-subtree-index] [--model FILE]
//     --no-subtree-index  walk the graph node by node (IntersectionVisitor::useSubtreeIndex off)
//     --model FILE        query FILE (the same scene in another format: `polygon --export-gltf`
//                         keeps its 4336 meshes apart, where the OBJ loader merges them per
//                         material); the workloads still come from FILE.obj's box
//
// Prints a BUILD line (sgfx::prepareForQueries timed after the load, and the BVHs' bytes per
// triangle) and one QUERY line per workload.
#include "query_workload.h"

#include <sgfx/Geometry.h>
#include <sgfx/Group.h>
#include <sgfx/Intersection.h>
#include <sgfx/ModelLoader.h>
#include <sgfx/NodeVisitor.h>
#include <sgfx/Queries.h>
#include <sgfx/TriangleBvh.h>

#include <cstdio>
#include <exception>
#include <string>
#include <unordered_set>
#include <vector>

namespace {

namespace qw = queryworkload;

// Triangles, and what the per-geometry BVHs hold (TriangleBvh::memoryBytes: nodes, leaf order and
// the triangle list), the geometry's own arrays left out as on the OSG side.
struct BvhBytes : sgfx::NodeVisitor {
    void apply(sgfx::Geometry& g) override {
        if (!seen.insert(&g).second) return; // a shared geometry has one BVH
        ++geometries;
        triangles += g.triangleCount() / g.instanceCount(); // one BVH serves every instance
        if (const auto bvh = g.triangleBvh()) {
            trees += bvh->triangles().empty() ? 0 : 1;
            indexed += bvh->triangles().size();
            nodes += bvh->bvh().nodes.size();
            bytes += bvh->memoryBytes();
        }
    }
    std::unordered_set<const sgfx::Geometry*> seen;
    std::size_t geometries = 0, trees = 0, triangles = 0, indexed = 0, nodes = 0, bytes = 0;
};

glm::dvec3 vec(const qw::Vec3& p) {
    return {p.x, p.y, p.z};
}

qw::Result run(sgfx::Node& scene, const std::vector<qw::Segment>& segments, sgfx::Intersector::Limit limit,
               bool subtreeIndex) {
    qw::Result r;
    r.rays = segments.size();
    const qw::Stopwatch watch;
    for (const qw::Segment& s : segments) {
        sgfx::LineSegmentIntersector lsi(vec(s.start), vec(s.end));
        lsi.limit = limit;
        sgfx::IntersectionVisitor iv(lsi);
        iv.useSubtreeIndex = subtreeIndex;
        iv.visit(scene);
        if (const sgfx::Intersection* hit = lsi.nearest()) {
            ++r.hits;
            if (limit == sgfx::Intersector::Limit::Nearest) r.hitZSum += hit->point.z;
        }
    }
    r.seconds = watch.wall();
    r.cpuSeconds = watch.cpu();
    return r;
}

} // namespace

int main(int argc, char** argv) {
    bool subtreeIndex = true;
    std::string model;
    // --no-subtree-index and --model are ours; the rest is query_workload.h's.
    std::vector<char*> rest;
    for (int i = 0; i < argc; ++i) {
        if (std::string(argv[i]) == "--no-subtree-index")
            subtreeIndex = false;
        else if (std::string(argv[i]) == "--model" && i + 1 < argc)
            model = argv[++i];
        else
            rest.push_back(argv[i]);
    }
    qw::Args args;
    if (!qw::parseArgs(int(rest.size()), rest.data(), "query_bench", args)) return 2;
    const qw::Box box = qw::objBounds(args.file);
    if (!box.valid()) {
        std::fprintf(stderr, "query_bench: no vertices in %s\n", args.file.c_str());
        return 1;
    }
    const std::string side =
        std::string("sgfx") + (model.empty() ? "" : "-model") + (subtreeIndex ? "" : "-walk");
    try {
        const std::shared_ptr<sgfx::Group> scene = sgfx::loadModel(model.empty() ? args.file : model);
        const qw::Stopwatch watch;
        sgfx::prepareForQueries(*scene);
        const double seconds = watch.wall(), cpuSeconds = watch.cpu();
        BvhBytes m;
        scene->accept(m);
        // The subtree indexes (the root's and the nested ones, built by prepareForQueries) count too.
        const sgfx::QueryMemory memory = sgfx::queryMemory(*scene);
        const std::size_t subtreeBytes = memory.indexBytes;
        m.bytes += subtreeBytes;
        std::printf(
            "BUILD side=%s seconds=%.4f cpu_seconds=%.4f bytes_per_triangle=%.2f triangles=%zu "
            "indexed_triangles=%zu bytes=%zu subtree_index_bytes=%zu geometries=%zu trees=%zu tree_nodes=%zu "
            "sizeof_node=%zu\n",
            side.c_str(), seconds, cpuSeconds, double(m.bytes) / double(m.triangles), m.triangles, m.indexed,
            m.bytes, subtreeBytes, m.geometries, m.trees, m.nodes, sizeof(sgfx::BvhNodes::Node));
        std::printf("BOX min=%.3f,%.3f,%.3f max=%.3f,%.3f,%.3f\n", box.min.x, box.min.y, box.min.z, box.max.x,
                    box.max.y, box.max.z);

        using Limit = sgfx::Intersector::Limit;
        // Warm-up on other points: caches, page faults, the CPU's clock.
        run(*scene, qw::terrainSegments(box, 1000, qw::kSeed + 100), Limit::Nearest, subtreeIndex);

        const auto terrain = qw::terrainSegments(box, args.terrainRays);
        qw::print(side.c_str(), "terrain", terrain, run(*scene, terrain, Limit::Nearest, subtreeIndex));
        const auto sight = qw::sightSegments(box, args.sightRays);
        qw::print(side.c_str(), "sight", sight, run(*scene, sight, Limit::Any, subtreeIndex));
    } catch (const std::exception& e) {
        std::fprintf(stderr, "query_bench: %s\n", e.what());
        return 1;
    }
    return 0;
}

// OpenSceneGraph 3.6 peer of query_bench: the same queries (bench/query_workload.h) on the same
// exported OBJ, through osgUtil::LineSegmentIntersector and osgUtil::IntersectionVisitor, as an
// OSG application asks them: one intersector and one visitor per query, kd-trees built at load
// (osgDB::Options::BUILD_KDTREES). No GL context: queries never touch GL.
//
//   osg_query FILE.obj [--terrain N] [--sight N] [--merge]
//     --merge  query a copy whose geometries osgUtil::Optimizer merged (MERGE_GEODES,
//              MERGE_GEOMETRY), kd-trees built after: OSG with fewer, larger drawables
//
// Prints a BUILD line (osg::KdTreeBuilder timed on a second copy loaded without the hint, and the
// kd-trees' bytes per triangle) and one QUERY line per workload.
#include "query_workload.h"

#include <osg/Geometry>
#include <osg/KdTree>
#include <osg/NodeVisitor>
#include <osg/TriangleFunctor>
#include <osgDB/Options>
#include <osgDB/ReadFile>
#include <osgUtil/IntersectionVisitor>
#include <osgUtil/LineSegmentIntersector>
#include <osgUtil/Optimizer>

#include <cstdio>
#include <string>
#include <vector>

namespace {

namespace qw = queryworkload;

struct TriangleCounter {
    std::size_t n = 0;
    void operator()(const osg::Vec3&, const osg::Vec3&, const osg::Vec3&) { ++n; }
};

// Triangles, and what the kd-trees hold: nodes plus their two index arrays (KdTree.h), which is
// all a kd-tree adds to the geometry (its vertex array is the geometry's own).
struct KdTreeBytes : osg::NodeVisitor {
    KdTreeBytes()
        : osg::NodeVisitor(TRAVERSE_ALL_CHILDREN) {}
    void apply(osg::Geometry& g) override {
        ++geometries;
        osg::TriangleFunctor<TriangleCounter> count;
        g.accept(count);
        triangles += count.n;
        if (const auto* kd = dynamic_cast<const osg::KdTree*>(g.getShape())) {
            ++trees;
            kdNodes += kd->getNodes().size();
            indexed += kd->getPrimitiveIndices().size();
            bytes += kd->getNodes().size() * sizeof(osg::KdTree::KdNode) +
                     kd->getVertexIndices().size() * sizeof(unsigned int) +
                     kd->getPrimitiveIndices().size() * sizeof(unsigned int);
        }
    }
    std::size_t geometries = 0, trees = 0, triangles = 0, indexed = 0, kdNodes = 0, bytes = 0;
};

osg::ref_ptr<osg::Node> load(const std::string& file, bool kdTrees) {
    // "noRotation": the OBJ is Z up already (the plugin turns Y up into Z up by default).
    osg::ref_ptr<osgDB::Options> options = new osgDB::Options("noRotation");
    if (kdTrees) options->setBuildKdTreesHint(osgDB::Options::BUILD_KDTREES);
    osg::ref_ptr<osg::Node> node = osgDB::readRefNodeFile(file, options.get());
    if (!node) std::fprintf(stderr, "osg_query: cannot load %s\n", file.c_str());
    return node;
}

osg::Vec3d vec(const qw::Vec3& p) {
    return {p.x, p.y, p.z};
}

qw::Result run(osg::Node& scene, const std::vector<qw::Segment>& segments, bool nearest) {
    qw::Result r;
    r.rays = segments.size();
    const qw::Stopwatch watch;
    for (const qw::Segment& s : segments) {
        osg::ref_ptr<osgUtil::LineSegmentIntersector> lsi =
            new osgUtil::LineSegmentIntersector(vec(s.start), vec(s.end));
        lsi->setIntersectionLimit(nearest ? osgUtil::Intersector::LIMIT_NEAREST
                                          : osgUtil::Intersector::LIMIT_ONE);
        osgUtil::IntersectionVisitor iv(lsi.get());
        scene.accept(iv);
        if (lsi->containsIntersections()) {
            ++r.hits;
            if (nearest) r.hitZSum += lsi->getFirstIntersection().getWorldIntersectPoint().z();
        }
    }
    r.seconds = watch.wall();
    r.cpuSeconds = watch.cpu();
    return r;
}

} // namespace

int main(int argc, char** argv) {
    bool merge = false;
    // --merge is ours; the rest is query_workload.h's.
    std::vector<char*> rest;
    for (int i = 0; i < argc; ++i) {
        if (std::string(argv[i]) == "--merge")
            merge = true;
        else
            rest.push_back(argv[i]);
    }
    qw::Args args;
    if (!qw::parseArgs(int(rest.size()), rest.data(), "osg_query", args)) return 2;
    const qw::Box box = qw::objBounds(args.file);
    if (!box.valid()) {
        std::fprintf(stderr, "osg_query: no vertices in %s\n", args.file.c_str());
        return 1;
    }
    const char* side = merge ? "osg-merged" : "osg";

    // Build: kd-trees built as the hint would build them, over a copy loaded without it (with
    // --merge, the copy that is queried, once the Optimizer has merged its geometries).
    osg::ref_ptr<osg::Node> bare = load(args.file, false);
    if (!bare) return 1;
    if (merge) {
        osgUtil::Optimizer optimizer;
        optimizer.optimize(bare.get(), osgUtil::Optimizer::FLATTEN_STATIC_TRANSFORMS |
                                           osgUtil::Optimizer::REMOVE_REDUNDANT_NODES |
                                           osgUtil::Optimizer::MERGE_GEODES |
                                           osgUtil::Optimizer::MERGE_GEOMETRY);
    }
    KdTreeBytes before;
    bare->accept(before);
    if (before.trees != 0) { // OSG_BUILD_KDTREES in the environment, say: nothing left to time
        std::fprintf(stderr, "osg_query: %zu kd-trees were built at load without the hint\n", before.trees);
        return 1;
    }
    osg::ref_ptr<osg::KdTreeBuilder> builder = new osg::KdTreeBuilder;
    const qw::Stopwatch watch;
    bare->accept(*builder);
    const double seconds = watch.wall(), cpuSeconds = watch.cpu();
    KdTreeBytes m;
    bare->accept(m);
    std::printf("BUILD side=%s seconds=%.4f cpu_seconds=%.4f bytes_per_triangle=%.2f triangles=%zu "
                "indexed_triangles=%zu bytes=%zu geometries=%zu trees=%zu tree_nodes=%zu sizeof_node=%zu\n",
                side, seconds, cpuSeconds, double(m.bytes) / double(m.triangles), m.triangles, m.indexed,
                m.bytes, m.geometries, m.trees, m.kdNodes, sizeof(osg::KdTree::KdNode));

    // The queries run on a copy loaded with the hint, as an application gets it from osgDB.
    osg::ref_ptr<osg::Node> scene = merge ? bare : load(args.file, true);
    if (!merge) bare = nullptr;
    if (!scene) return 1;
    std::printf("BOX min=%.3f,%.3f,%.3f max=%.3f,%.3f,%.3f\n", box.min.x, box.min.y, box.min.z, box.max.x,
                box.max.y, box.max.z);
    // Warm-up on other points: caches, page faults, the CPU's clock.
    run(*scene, qw::terrainSegments(box, 1000, qw::kSeed + 100), true);

    const auto terrain = qw::terrainSegments(box, args.terrainRays);
    qw::print(side, "terrain", terrain, run(*scene, terrain, true));
    const auto sight = qw::sightSegments(box, args.sightRays);
    qw::print(side, "sight", sight, run(*scene, sight, false));
    return 0;
}

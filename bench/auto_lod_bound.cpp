// How hausdorffBound sets the auto-LOD levels' errors on a loaded model:
// `auto_lod_bound FILE [--sample | --mesh NAME]`. Loads FILE as GltfOptions::autoLod would see it (ordered,
// no LODs), runs makeErrorLod on every distinct mesh, and prints per level the bound, its own lower bound
// (the largest distance found at a point), the looseness (bound - lower) / (0.1 lower + abs slack) that the
// slack allows up to 1, and which path settled the pieces; with --sample also the 8-point sampled distance
// (hausdorffDistance); with --mesh only the mesh NAME, each level's two one-sided bounds and the piece that
// set the larger (its path, depth and corners). CPU seconds of the makeErrorLod calls at the end.
#include <sgfx/Group.h>
#include <sgfx/MeshOptimize.h>
#include <sgfx/ModelLoader.h>

#include <algorithm>
#include <cstdio>
#include <ctime>
#include <string>
#include <unordered_set>
#include <vector>

namespace {

const char* pathName(int p) {
    static const char* names[] = {"projection", "convex", "lipschitz", "inherited", "exact"};
    return names[p];
}

void collect(const sgfx::NodePtr& n, std::vector<std::shared_ptr<sgfx::Geometry>>& out,
             std::unordered_set<const sgfx::Node*>& seen) {
    if (!n || !seen.insert(n.get()).second) return;
    if (auto g = std::dynamic_pointer_cast<sgfx::Geometry>(n)) out.push_back(g);
    if (auto group = std::dynamic_pointer_cast<sgfx::Group>(n))
        for (std::size_t i = 0; i < group->numChildren(); ++i)
            collect(group->child(i), out, seen);
}

} // namespace

int main(int argc, char** argv) {
    const bool usageOk = argc == 2 || (argc == 3 && std::string(argv[2]) == "--sample") ||
                         (argc == 4 && std::string(argv[2]) == "--mesh" && argv[3][0] != '\0');
    if (!usageOk) {
        std::fprintf(stderr, "usage: auto_lod_bound FILE [--sample | --mesh NAME]\n");
        return 2;
    }
    const bool sample = argc > 2 && std::string(argv[2]) == "--sample";
    const std::string only = argc > 3 && std::string(argv[2]) == "--mesh" ? argv[3] : "";
    sgfx::GltfOptions load;
    load.optimizeOrder = true;
    std::vector<std::shared_ptr<sgfx::Geometry>> meshes;
    std::unordered_set<const sgfx::Node*> seen;
    collect(sgfx::loadModel(argv[1], load), meshes, seen);
    const sgfx::AutoLodOptions options;
    sgfx::HausdorffBoundStats total;
    struct Row {
        float looseness, ratio, bound, lower, sampled, slack;
        std::size_t triangles;
        int path;
        std::string name;
    };
    std::vector<Row> rows;
    double cpu = 0.0;
    std::size_t lods = 0;
    for (const auto& g : meshes) {
        if (!only.empty() && g->name != only) continue;
        std::vector<sgfx::AutoLodLevel> levels;
        const std::clock_t start = std::clock();
        lods += sgfx::makeErrorLod(g, options, &levels) != nullptr;
        cpu += double(std::clock() - start) / CLOCKS_PER_SEC;
        const float abs = 0.25f * g->bound().radius * options.errorPixels / options.focalPixels;
        float floor = 0.0f;
        for (const auto& level : levels) {
            const auto& s = level.boundStats;
            total.add(s);
            total.upper = 0.0f;
            // Looseness against the bound's own lower bound, or against the finer level's error
            // when the bound stopped refining below it.
            const float reference = std::max(s.lower * 1.1f + abs, floor);
            const float sampled = sample ? sgfx::hausdorffDistance(*level.geometry, *g) : 0.0f;
            rows.push_back({(level.measuredError - s.lower) / (0.1f * s.lower + abs),
                            level.measuredError / std::max(s.lower, 1e-9f), level.measuredError, s.lower,
                            sampled, reference, level.geometry->triangleCount(), int(s.worst), g->name});
            floor = std::max(floor, level.measuredError);
            if (!only.empty()) {
                const auto& w = s.worstPiece;
                std::printf(
                    "%zu triangles: sides %.4f %.4f lower %.4f; worst piece (%s, depth %d) edges %.3f "
                    "%.3f %.3f corners (%.3f %.3f %.3f) (%.3f %.3f %.3f) (%.3f %.3f %.3f)\n",
                    level.geometry->triangleCount(), s.sides[0], s.sides[1], s.lower, pathName(int(s.worst)),
                    s.worstDepth, glm::length(w[1] - w[0]), glm::length(w[2] - w[1]),
                    glm::length(w[0] - w[2]), w[0].x, w[0].y, w[0].z, w[1].x, w[1].y, w[1].z, w[2].x, w[2].y,
                    w[2].z);
            }
        }
    }
    std::printf("meshes %zu, LODs %zu, levels %zu, makeErrorLod CPU %.2f s\n", meshes.size(), lods,
                rows.size(), cpu);
    std::printf("settled pieces:");
    for (int p = 0; p < sgfx::HausdorffBoundStats::Paths; ++p)
        std::printf(" %s %zu", pathName(p), total.settled[std::size_t(p)]);
    std::printf("\nat max depth %zu, queries %zu, projections %zu (failed: degenerate %zu, uncovered %zu, "
                "overlap %zu, still cut %zu; crack margins > abs/4: %zu)\n",
                total.atMaxDepth, total.queries, total.projections, total.degenerate, total.uncovered,
                total.overlap, total.cut, total.crackMargins);
    std::vector<int> worstPaths(sgfx::HausdorffBoundStats::Paths);
    for (const Row& r : rows)
        ++worstPaths[std::size_t(r.path)];
    std::printf("path that set each level's bound:");
    for (int p = 0; p < sgfx::HausdorffBoundStats::Paths; ++p)
        std::printf(" %s %d", pathName(p), worstPaths[std::size_t(p)]);
    auto quantiles = [&](const char* what, auto key) {
        std::vector<float> v;
        for (const Row& r : rows)
            v.push_back(key(r));
        std::sort(v.begin(), v.end());
        if (v.empty()) return;
        auto q = [&](double f) { return v[std::min(v.size() - 1, std::size_t(f * double(v.size())))]; };
        std::printf("\n%s: min %.3f, median %.3f, p90 %.3f, p99 %.3f, max %.3f", what, v.front(), q(0.5),
                    q(0.9), q(0.99), v.back());
    };
    quantiles("looseness (bound - lower) / (0.1 lower + abs)", [](const Row& r) { return r.looseness; });
    quantiles("bound / lower", [](const Row& r) { return r.ratio; });
    quantiles("bound / max(1.1 lower + abs, finer level's bound)",
              [](const Row& r) { return r.bound / r.slack; });
    if (sample)
        quantiles("bound / sampled", [](const Row& r) { return r.bound / std::max(r.sampled, 1e-9f); });
    std::sort(rows.begin(), rows.end(), [](const Row& a, const Row& b) { return a.looseness > b.looseness; });
    std::printf("\nloosest levels:\n");
    for (std::size_t i = 0; i < std::min<std::size_t>(rows.size(), 8); ++i)
        std::printf("  %s %zu triangles: bound %.4f lower %.4f sampled %.4f looseness %.2f (%s)\n",
                    rows[i].name.c_str(), rows[i].triangles, rows[i].bound, rows[i].lower, rows[i].sampled,
                    rows[i].looseness, pathName(rows[i].path));
    return 0;
}

// Cost of the transparent stage's CPU work (Google Benchmark): sorting N transparent items per
// frame, and re-sorting a 10^5-triangle self-overlapping mesh. Run: build/bench/transparency_bench
#include <sgfx/Geometry.h>
#include <sgfx/Material.h>
#include <sgfx/RenderQueue.h>
#include <sgfx/Shapes.h>
#include <sgfx/TriangleSort.h>
#include <sgfx/Viewer.h>

#include <sgfx_glad/gl.h>

#include <benchmark/benchmark.h>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <random>

namespace {

// N items in cull order with random depths (a few share a depth, a few have an explicit order).
std::vector<sgfx::RenderItem> items(std::size_t n) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> depth(1.0f, 5000.0f);
    std::vector<sgfx::RenderItem> v(n);
    for (std::size_t i = 0; i < n; ++i) {
        v[i].depth = i % 16 == 0 && i > 0 ? v[i - 1].depth : depth(rng);
        v[i].order = i % 100 == 0 ? 1 : 0;
        v[i].sequence = std::uint32_t(i);
    }
    return v;
}

void SortTransparentItems(benchmark::State& state) {
    const auto n = std::size_t(state.range(0));
    const std::vector<sgfx::RenderItem> culled = items(n);
    sgfx::RenderQueue q;
    for (auto _ : state) {
        q.transparent.assign(culled.begin(), culled.end()); // what a cull leaves
        q.sort();
        benchmark::DoNotOptimize(q.transparent.data());
    }
    state.SetItemsProcessed(state.iterations() * std::int64_t(n));
    state.counters["ns_per_item"] =
        benchmark::Counter(double(n), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}
BENCHMARK(SortTransparentItems)->Arg(1000)->Arg(10000)->Arg(100000)->Unit(benchmark::kMicrosecond);

// The cull-order copy alone, to subtract from the figures above.
void CopyTransparentItems(benchmark::State& state) {
    const auto n = std::size_t(state.range(0));
    const std::vector<sgfx::RenderItem> culled = items(n);
    sgfx::RenderQueue q;
    for (auto _ : state) {
        q.transparent.assign(culled.begin(), culled.end());
        benchmark::DoNotOptimize(q.transparent.data());
    }
    state.counters["ns_per_item"] =
        benchmark::Counter(double(n), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}
BENCHMARK(CopyTransparentItems)->Arg(1000)->Arg(10000)->Arg(100000)->Unit(benchmark::kMicrosecond);

// A 224×224-cell height field: 100,352 triangles, every one re-sorted per iteration as the view
// turns (threshold 0), as happens when the camera swings past the resort angle.
void ResortTriangles(benchmark::State& state) {
    auto mesh = sgfx::shapes::heightfield(0, 0, 100, 100, 225, 225, [](float x, float y) {
        return 3.0f * std::sin(x * 0.3f) * std::cos(y * 0.2f);
    });
    sgfx::TriangleDepthSort sort(*mesh);
    float angle = 0.0f;
    for (auto _ : state) {
        angle += 0.1f;
        const glm::vec3 eye(50.0f + 80.0f * std::cos(angle), 50.0f + 80.0f * std::sin(angle), 40.0f);
        sort.update(glm::lookAt(eye, glm::vec3(50, 50, 0), glm::vec3(0, 0, 1)), 0.0f);
        benchmark::DoNotOptimize(sort.indices().data());
    }
    state.counters["triangles"] = double(sort.triangleCount());
    state.counters["ns_per_triangle"] = benchmark::Counter(
        double(sort.triangleCount()), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}
BENCHMARK(ResortTriangles)->Unit(benchmark::kMillisecond);

// The same keys through std::sort, for comparison with the radix sort TriangleDepthSort uses.
void ResortTrianglesStdSort(benchmark::State& state) {
    auto mesh = sgfx::shapes::heightfield(0, 0, 100, 100, 225, 225, [](float x, float y) {
        return 3.0f * std::sin(x * 0.3f) * std::cos(y * 0.2f);
    });
    std::vector<glm::vec3> centroids;
    for (std::size_t t = 0; t + 2 < mesh->indices.size(); t += 3)
        centroids.push_back((mesh->positions[mesh->indices[t]] + mesh->positions[mesh->indices[t + 1]] +
                             mesh->positions[mesh->indices[t + 2]]) /
                            3.0f);
    std::vector<std::pair<float, std::uint32_t>> keys(centroids.size());
    std::vector<std::uint32_t> sorted(mesh->indices.size());
    float angle = 0.0f;
    for (auto _ : state) {
        angle += 0.1f;
        const glm::vec3 eye(50.0f + 80.0f * std::cos(angle), 50.0f + 80.0f * std::sin(angle), 40.0f);
        const glm::mat4 mv = glm::lookAt(eye, glm::vec3(50, 50, 0), glm::vec3(0, 0, 1));
        const glm::vec3 row(mv[0][2], mv[1][2], mv[2][2]);
        for (std::size_t i = 0; i < centroids.size(); ++i)
            keys[i] = {glm::dot(row, centroids[i]), std::uint32_t(i)};
        std::sort(keys.begin(), keys.end());
        for (std::size_t i = 0; i < keys.size(); ++i)
            std::copy_n(mesh->indices.begin() + std::ptrdiff_t(3 * keys[i].second), 3,
                        sorted.begin() + std::ptrdiff_t(3 * i));
        benchmark::DoNotOptimize(sorted.data());
    }
    state.counters["ns_per_triangle"] = benchmark::Counter(
        double(centroids.size()), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}
BENCHMARK(ResortTrianglesStdSort)->Unit(benchmark::kMillisecond);

// A whole frame (OSMesa, 256×256) of a 10^5-triangle transparent height field while the camera
// orbits 10° per frame, without (0) and with (1) per-triangle sorting: the difference is the
// in-frame cost of re-sorting and uploading the index buffer every frame, and of drawing in depth
// order rather than mesh order (2: sorted once, never re-sorted, isolates the latter).
void FrameWithTriangleSort(benchmark::State& state) {
    auto viewer = sgfx::Viewer::createHeadless(256, 256);
    auto mesh = sgfx::shapes::heightfield(0, 0, 100, 100, 225, 225, [](float x, float y) {
        return 3.0f * std::sin(x * 0.3f) * std::cos(y * 0.2f);
    });
    auto m = sgfx::Material::create();
    m->diffuse = glm::vec4(0.3f, 0.6f, 0.8f, 0.4f);
    auto& ss = mesh->getOrCreateStateSet();
    ss.material.set(m);
    ss.blend.set(sgfx::BlendMode::Alpha);
    ss.cullFace.set(sgfx::CullFace::None);
    sgfx::TransparencyDetails d;
    d.sortTriangles = state.range(0) != 0;
    d.twoPass = false;
    if (state.range(0) == 2) d.resortAngle = 180.0f; // sorted once: the order's own drawing cost
    ss.transparency.set(d);
    viewer->setSceneData(mesh);
    viewer->camera()->setPerspective(50.0f, 1.0f, 1000.0f);
    float angle = 0.0f;
    std::size_t sorts = 0;
    for (auto _ : state) {
        angle += glm::radians(10.0f);
        viewer->camera()->setLookAt({50.0f + 120.0f * std::cos(angle), 50.0f + 120.0f * std::sin(angle), 60.0f},
                                    {50, 50, 0});
        viewer->frame();
        glFinish();
        sorts += viewer->renderer().stats().triangleSorts;
    }
    state.counters["resorts_per_frame"] = double(sorts) / double(state.iterations());
}
BENCHMARK(FrameWithTriangleSort)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);

} // namespace

BENCHMARK_MAIN();

// Cull-side CPU work of a frame (Google Benchmark), on the scene of bench/cull_scene.h (the one the
// OpenSceneGraph peer osg_cull culls): the cull traversal alone at 10^4..10^6 leaves, the opaque
// queue sort, and the program/material changes a sorted queue leaves. Run: build/bench/cull_bench
// (bench/cull_table.sh compares with OSG in one run).
#include "alloc_count.h"
#include "sgfx_cull_scene.h"

#include <sgfx/CullVisitor.h>
#include <sgfx/Renderer.h>

#include <benchmark/benchmark.h>

#include <algorithm>
#include <map>
#include <random>

namespace {

// One scene at a time (the 10^6 one is large); rebuilt when the size changes.
const cullscene::SgfxScene& scene(long n) {
    static std::unique_ptr<cullscene::SgfxScene> s;
    if (!s || s->dims.count() != cullscene::dims(n).count()) {
        s.reset();
        s = std::make_unique<cullscene::SgfxScene>(cullscene::buildSgfxScene(n, true));
    }
    return *s;
}

// What Renderer::renderView does before sorting, timed alone: the queue is reused across frames.
void BM_Cull(benchmark::State& state) {
    const cullscene::SgfxScene& s = scene(state.range(0));
    sgfx::RenderQueue queue;
    sgfx::FramePlan plan;
    std::size_t culled = 0;
    for (auto _ : state) {
        queue.clear();
        plan.clear();
        sgfx::CullVisitor cull(*s.camera, queue, &plan);
        cull.run(*s.camera);
        culled = cull.culledNodes;
        benchmark::DoNotOptimize(queue.opaque.data());
    }
    const double leaves = double(s.dims.count());
    state.counters["nodes/s"] =
        benchmark::Counter(double(s.nodes()), benchmark::Counter::kIsIterationInvariantRate);
    state.counters["queued_fraction"] = double(queue.size()) / leaves;
    state.counters["culled_nodes"] = double(culled);
    state.counters["heap_B_per_leaf"] = s.heapBytes / leaves;
    state.counters["peak_rss_MB"] = cullscene::peakRssMb();
}
BENCHMARK(BM_Cull)->Arg(10000)->Arg(100000)->Arg(1000000)->Unit(benchmark::kMillisecond);

// A realistic opaque queue in cull order: the culled half of the scene, its leaves spread over
// 16 materials and 4 program variants (as a loaded model would have).
struct OpaqueQueue {
    std::vector<sgfx::RenderItem> items;
    std::deque<sgfx::ResolvedState> states;
};

const OpaqueQueue& opaqueQueue(long n) {
    static std::map<long, OpaqueQueue> cache;
    auto it = cache.find(n);
    if (it != cache.end()) return it->second;
    OpaqueQueue& q = cache[n];
    const cullscene::SgfxScene& s = scene(n);
    sgfx::RenderQueue queue;
    sgfx::CullVisitor cull(*s.camera, queue);
    cull.run(*s.camera);
    for (int m = 0; m < 16; ++m) {
        sgfx::StateSet set;
        set.material.set(sgfx::Material::create());
        q.states.push_back(sgfx::ResolvedState::defaults().merged(set));
    }
    std::mt19937 rng(11);
    q.items = queue.opaque;
    for (sgfx::RenderItem& item : q.items) {
        item.state = &q.states[rng() % 16];
        item.programKey = sgfx::ProgramKey().with(sgfx::ProgramKey::Effects, rng() % 4); // 4 programs
    }
    return q;
}

void BM_QueueSort(benchmark::State& state) {
    const OpaqueQueue& q = opaqueQueue(state.range(0));
    sgfx::RenderQueue queue;
    for (auto _ : state) {
        queue.opaque.assign(q.items.begin(), q.items.end()); // what a cull leaves
        queue.sort();
        benchmark::DoNotOptimize(queue.opaque.data());
    }
    state.counters["items"] = double(q.items.size());
    state.counters["items/s"] =
        benchmark::Counter(double(q.items.size()), benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_QueueSort)->Arg(10000)->Arg(100000)->Arg(1000000)->Unit(benchmark::kMillisecond);

// The cull-order copy alone, to subtract from BM_QueueSort.
void BM_QueueCopy(benchmark::State& state) {
    const OpaqueQueue& q = opaqueQueue(state.range(0));
    sgfx::RenderQueue queue;
    for (auto _ : state) {
        queue.opaque.assign(q.items.begin(), q.items.end());
        benchmark::DoNotOptimize(queue.opaque.data());
    }
    state.counters["items/s"] =
        benchmark::Counter(double(q.items.size()), benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_QueueCopy)->Arg(10000)->Arg(100000)->Arg(1000000)->Unit(benchmark::kMillisecond);

// Program and material switches the renderer's draw loop makes over a queue (its own counters,
// RendererStats::programChanges / stateChanges, live in the GL draw code): the same rule on the CPU.
struct Changes {
    std::size_t program = 0, material = 0;
};
Changes countChanges(const std::vector<sgfx::RenderItem>& items) {
    Changes c;
    sgfx::ProgramKey program = sgfx::ProgramKey::none();
    const sgfx::Material* material = nullptr;
    bool first = true;
    for (const sgfx::RenderItem& it : items) {
        const sgfx::Material* m = it.state->material.value ? it.state->material.value->get() : nullptr;
        if (first || it.programKey != program) ++c.program, program = it.programKey, material = nullptr;
        if (first || m != material) ++c.material, material = m;
        first = false;
    }
    return c;
}

void BM_StateChanges(benchmark::State& state) {
    const OpaqueQueue& q = opaqueQueue(state.range(0));
    sgfx::RenderQueue queue;
    queue.opaque = q.items;
    queue.sort();
    Changes sorted;
    for (auto _ : state) {
        sorted = countChanges(queue.opaque);
        benchmark::DoNotOptimize(sorted);
    }
    const Changes unsorted = countChanges(q.items);
    state.counters["program_changes"] = double(sorted.program);
    state.counters["material_changes"] = double(sorted.material);
    state.counters["unsorted_program_changes"] = double(unsorted.program);
    state.counters["unsorted_material_changes"] = double(unsorted.material);
    state.counters["items/s"] =
        benchmark::Counter(double(q.items.size()), benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_StateChanges)->Arg(10000)->Arg(100000)->Arg(1000000)->Unit(benchmark::kMillisecond);

// Live heap per node (see sgfx_cull_scene.h), and sizeof, as counters.
void BM_NodeBytes(benchmark::State& state) {
    cullscene::NodeBytes b;
    for (auto _ : state)
        b = cullscene::measureSgfxNodes();
    state.counters["group_bytes"] = b.group;
    state.counters["transform_bytes"] = b.transform;
    state.counters["sizeof_group"] = double(sizeof(sgfx::Group));
    state.counters["sizeof_transform"] = double(sizeof(sgfx::Transform));
}
BENCHMARK(BM_NodeBytes)->Iterations(1)->Unit(benchmark::kMillisecond);

} // namespace

BENCHMARK_MAIN();

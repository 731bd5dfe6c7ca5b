// Cull traversal of the shared scene (bench/cull_scene.h) as the renderer runs it each frame
// (queue.clear, plan.clear, CullVisitor::run; the queue is reused across frames), timed alone;
// the opaque sort is timed separately. Prints one CULL line in the format osg_cull prints, so
// bench/cull_table.sh compares like with like. No GL context: culling never touches GL.
//
//   sgfx_cull [--n N] [--frames F] [--no-memory] [--mixed]   (--mixed: cull_scene.h's mixed-state scene)
#include "alloc_count.h"
#include "sgfx_cull_scene.h"

#include <sgfx/CullVisitor.h>
#include <sgfx/Renderer.h>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <string>

int main(int argc, char** argv) {
    cullscene::Args args;
    if (!cullscene::parseArgs(argc, argv, "sgfx_cull", false, args)) return 2;
    const long n = args.n;
    const int frames = args.frames;
    const bool memory = args.memory;

    cullscene::NodeBytes nodeBytes;
    if (memory) nodeBytes = cullscene::measureSgfxNodes();
    const cullscene::SgfxScene scene = cullscene::buildSgfxScene(n, memory, args.mixed);
    sgfx::Camera& camera = *scene.camera;

    sgfx::RenderQueue queue;
    sgfx::FramePlan plan;
    // CPU time of this thread as well: robust to other load on the machine (preemption).
    auto cpuMs = [] {
        timespec ts{};
        clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
        return double(ts.tv_sec) * 1e3 + double(ts.tv_nsec) * 1e-6;
    };
    std::vector<double> cullMs, sortMs, cullCpuMs;
    std::size_t queued = 0;
    float nearPlane = 0, farPlane = 0;
    using clock = std::chrono::steady_clock;
    for (int f = -3; f < frames; ++f) { // 3 warm-up frames
        const double c0 = cpuMs();
        const auto t0 = clock::now();
        queue.clear();
        plan.clear();
        sgfx::CullVisitor cull(camera, queue, &plan);
        cull.run(camera);
        const auto t1 = clock::now();
        const double c1 = cpuMs();
        queue.sort();
        const auto t2 = clock::now();
        queued = queue.size();
        nearPlane = cull.computedNear;
        farPlane = cull.computedFar;
        if (f < 0) continue;
        cullMs.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
        cullCpuMs.push_back(c1 - c0);
        sortMs.push_back(std::chrono::duration<double, std::milli>(t2 - t1).count());
    }
    const double ms = cullscene::median(cullMs);
    const long leaves = scene.dims.count();
    std::printf("CULL side=sgfx n=%ld groups=%ld frames=%d ms_median=%.4f ms_min=%.4f cpu_ms_median=%.4f "
                "nodes_per_s=%.4g "
                "queued=%zu fraction=%.4f sort_ms=%.4f near=%.3f far=%.3f peak_rss_mb=%.1f "
                "scene_bytes_per_leaf=%.1f group_bytes=%.1f transform_bytes=%.1f sizeof_group=%zu "
                "sizeof_transform=%zu mixed=%d\n",
                leaves, scene.groups, frames, ms, cullMs.front(), cullscene::median(cullCpuMs),
                double(scene.nodes()) / (ms * 1e-3), queued, double(queued) / double(leaves),
                cullscene::median(sortMs), double(nearPlane), double(farPlane), cullscene::peakRssMb(),
                memory ? scene.heapBytes / double(leaves) : 0.0, nodeBytes.group, nodeBytes.transform,
                sizeof(sgfx::Group), sizeof(sgfx::Transform), int(args.mixed));
    return 0;
}

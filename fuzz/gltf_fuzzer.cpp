// libFuzzer target for the glTF loader (scripts/fuzz.sh builds and runs it). Any input must end in
// a scene or a LoadError: another exception, a crash, a leak or a sanitizer report is a loader bug.
// The loader makes CPU data only (GL objects are created at first draw), so no context is needed.
#include <sgfx/GltfLoader.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <span>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    // SGFX_FUZZ_VERBOSE=1 with files as arguments says what each did (to check the seeds).
    static const bool verbose = std::getenv("SGFX_FUZZ_VERBOSE") != nullptr;
    sgfx::GltfOptions options;
    // Small enough that the limit, not libFuzzer's -rss_limit_mb, stops a file declaring huge data.
    options.memoryLimit = std::size_t(64) << 20;
    try {
        sgfx::GltfStats stats;
        (void)sgfx::loadGltfFromMemory(std::as_bytes(std::span(data, size)), "fuzz-input", options, &stats);
        if (verbose) std::printf("loaded: %zu triangles, %zu nodes\n", stats.triangles, stats.nodes);
    } catch (const sgfx::LoadError& e) {
        // Expected for most inputs.
        if (verbose) std::printf("LoadError: %s\n", e.what());
    }
    return 0;
}

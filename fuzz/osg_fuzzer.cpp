// libFuzzer target for the OpenSceneGraph bridge (scripts/fuzz.sh): the first byte picks the
// format (.osgt, .osgb, .osgx, .ive, .osg, .flt), the rest is the file. Any input must end in a
// scene or a LoadError: another exception, a crash, a leak or a sanitizer report is a bug, in the
// bridge or in the osgDB plugin it calls (which scripts/fuzz.sh then names).
#include <sgfx/OsgLoader.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <span>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    static const bool verbose = std::getenv("SGFX_FUZZ_VERBOSE") != nullptr;
    static const char* const formats[] = {".osgt", ".osgb", ".osgx", ".ive", ".osg", ".flt"};
    if (size == 0) return 0;
    const char* ext = formats[data[0] % 6];
    sgfx::OsgOptions options;
    options.memoryLimit = std::size_t(64) << 20;
    options.readTimeout = 5.0; // a reader that hangs is a finding of its own (the parent reads too)
    try {
        sgfx::OsgStats stats;
        (void)sgfx::loadOsgFromMemory(std::as_bytes(std::span(data + 1, size - 1)), ext, "fuzz-input",
                                      options, &stats);
        if (verbose) std::printf("%s loaded: %zu triangles\n", ext, stats.triangles);
    } catch (const sgfx::LoadError& e) {
        if (verbose) std::printf("%s LoadError: %s\n", ext, e.what());
    }
    return 0;
}

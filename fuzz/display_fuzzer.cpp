// libFuzzer target for the display descriptions' reader (scripts/fuzz.sh): any input must end in a
// DisplayConfig or a LoadError; another exception, a crash or a sanitizer report is a reader bug.
#include <sgfx/DisplayConfig.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    static const bool verbose = std::getenv("SGFX_FUZZ_VERBOSE") != nullptr;
    try {
        const auto config = sgfx::DisplayConfig::parse(
            std::string_view(reinterpret_cast<const char*>(data), size), "fuzz-input");
        if (verbose) std::printf("read: %s, %zu channels\n", config.layout.c_str(), config.channels.size());
    } catch (const sgfx::LoadError& e) {
        if (verbose) std::printf("LoadError: %s\n", e.what());
    }
    return 0;
}

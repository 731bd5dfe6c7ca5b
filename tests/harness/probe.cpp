// A program that misbehaves on purpose after printing its success line, run the way the demos are,
// to prove the test harness fails each misbehaviour (tests/CMakeLists.txt registers them WILL_FAIL).
#include <climits>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

namespace {
void* volatile sink = nullptr;

// Allocates and drops the only pointer: unreachable at exit, so LeakSanitizer reports it.
[[gnu::noinline]] void leak() {
    sink = std::malloc(4096);
    std::memset(sink, 1, 4096);
    sink = nullptr;
}

// Reads one byte past a heap block: AddressSanitizer's heap-buffer-overflow.
[[gnu::noinline]] int overflow() {
    char* volatile p = static_cast<char*>(std::malloc(16));
    std::memset(p, 0, 16);
    const int v = p[16];
    std::free(p);
    return v;
}

// Signed overflow: UndefinedBehaviorSanitizer's "runtime error".
[[gnu::noinline]] int undefined() {
    volatile int big = INT_MAX;
    return big + 1;
}
} // namespace

int main(int argc, char** argv) {
    const std::string mode = argc > 1 ? argv[1] : "ok";
    std::printf("probe: ok\n");
    std::fflush(stdout);
    if (mode == "ok") return 0;
    if (mode == "exit") return 3;
    if (mode == "say-asan") { // the report's text alone, with exit status 0
        std::fprintf(stderr, "==1==ERROR: AddressSanitizer: heap-use-after-free (printed by the probe)\n");
        return 0;
    }
    if (mode == "leak")
        leak();
    else if (mode == "overflow")
        return overflow() == 12345;
    else if (mode == "undefined")
        return undefined() == 0;
    else {
        std::fprintf(stderr, "probe: unknown mode '%s'\n", mode.c_str());
        return 2;
    }
    return 0;
}

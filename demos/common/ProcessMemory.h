#pragma once
// Resident memory of this process (Linux /proc), for soak runs and memory-bound tests.
#include <cstdio>
#include <unistd.h>

namespace sgfxdemo {

inline long residentKb() {
    long pages = 0, resident = 0;
    if (FILE* f = std::fopen("/proc/self/statm", "r")) {
        if (std::fscanf(f, "%ld %ld", &pages, &resident) != 2) resident = 0;
        std::fclose(f);
    }
    return resident * (sysconf(_SC_PAGESIZE) / 1024);
}

} // namespace sgfxdemo

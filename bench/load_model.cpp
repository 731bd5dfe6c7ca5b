// Load time and peak memory of one model file: `load_model FILE [--repeat N]`. Run one file per
// process, so the peak resident size is this file's (the baseline before loading is printed too).
#include <sgfx/ModelLoader.h>
#include <sgfx/Visitors.h>

#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace {
double peakRssMb() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return double(u.ru_maxrss) / 1024.0; // kB on Linux
}
} // namespace

int main(int argc, char** argv) {
    if (argc < 2 || std::string(argv[1]) == "-h" || std::string(argv[1]) == "--help") {
        std::fprintf(stderr, "usage: load_model FILE [--repeat N]\n");
        return argc < 2 ? 2 : 0;
    }
    int repeat = 1;
    if (argc == 4 && std::string(argv[2]) == "--repeat") repeat = std::atoi(argv[3]);
    if (repeat < 1 || repeat > 1000 || (argc != 2 && argc != 4)) {
        std::fprintf(stderr, "load_model: --repeat takes 1..1000\n");
        return 2;
    }
    const double baseline = peakRssMb();
    std::vector<double> ms;
    sgfx::StatsVisitor stats;
    try {
        for (int i = 0; i < repeat; ++i) {
            const auto start = std::chrono::steady_clock::now();
            const auto model = sgfx::loadModel(argv[1]);
            ms.push_back(
                std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
            if (i == 0) model->accept(stats);
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "%s\n", e.what());
        return 1;
    }
    std::sort(ms.begin(), ms.end());
    std::printf("LOAD file=%s ms_median=%.1f ms_min=%.1f triangles=%zu vertices=%zu nodes=%zu "
                "rss_before_mb=%.1f peak_rss_mb=%.1f\n",
                argv[1], ms[ms.size() / 2], ms.front(), stats.triangles, stats.vertices, stats.nodes,
                baseline, peakRssMb());
    return 0;
}

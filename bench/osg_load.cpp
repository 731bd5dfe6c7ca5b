// Load time and memory of an OSG file: osgDB::readNodeFile alone (OpenSceneGraph's own load) against
// sgfx::loadOsg with OsgOptions::isolateReader on (the file read first in a child process, then for
// real, then converted) and off (read once, converted). bench/osg_load_table.sh runs it with the
// malloc pin of bench/common.sh and writes the table of docs/coming-from-osg.md.
//
//   osg_load FILE [--rounds N] [--memory-runs M]
//
// Memory first: for each loader, M fresh processes (forked before this process has read anything,
// so no osgDB plugin is loaded and no heap is reused) each do one load and keep the result; the
// growth of the resident set (/proc/self/statm, pages x page size) across that load is what a
// process pays for its first load of the file, osgDB plugins and images included. With
// isolateReader the reading child's memory is not counted (it is another process).
// Then time, in this process: one warm-up load of each, then N interleaved rounds (osg, isolated,
// direct, the order rotating each round); medians of each, and medians of the per-round ratios to
// OSG's own load (each round's loads see the same machine state).
#include <sgfx/OsgLoader.h>

#include <osgDB/ReadFile>

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

namespace {

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n == 0 ? 0.0 : n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// Resident set size in bytes (statm's second field, in pages).
double residentBytes() {
    std::ifstream in("/proc/self/statm");
    long size = 0, resident = 0;
    in >> size >> resident;
    return double(resident) * double(sysconf(_SC_PAGESIZE));
}

struct Loader {
    const char* name;
    std::function<bool(const std::string&)> load; // keeps nothing: the result is dropped on return
    std::function<bool(const std::string&)> loadAndKeep;
};

// One load in a fresh child process: its resident growth in bytes, or -1 on failure.
double memoryInChild(const Loader& l, const std::string& file) {
    int fd[2];
    if (pipe(fd) != 0) return -1;
    std::fflush(nullptr);
    const pid_t pid = fork();
    if (pid < 0) return -1;
    if (pid == 0) {
        close(fd[0]);
        const double before = residentBytes();
        const bool ok = l.loadAndKeep(file);
        const double growth = ok ? residentBytes() - before : -1.0;
        if (write(fd[1], &growth, sizeof growth) != sizeof growth) _exit(1);
        _exit(0);
    }
    close(fd[1]);
    double growth = -1.0;
    if (read(fd[0], &growth, sizeof growth) != sizeof growth) growth = -1.0;
    close(fd[0]);
    int status = 0;
    waitpid(pid, &status, 0);
    return growth;
}

} // namespace

int main(int argc, char** argv) {
    std::string file;
    int rounds = 11, memoryRuns = 3;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if ((a == "--rounds" || a == "--memory-runs") && i + 1 < argc) {
            (a == "--rounds" ? rounds : memoryRuns) = std::atoi(argv[++i]);
        } else if (a == "-h" || a == "--help") {
            std::printf("usage: osg_load FILE [--rounds N (11)] [--memory-runs M (3)]\n");
            return 0;
        } else if (a[0] != '-' && file.empty()) {
            file = a;
        } else {
            std::fprintf(stderr, "osg_load: unexpected argument %s\n", a.c_str());
            return 2;
        }
    }
    if (file.empty() || rounds < 1 || memoryRuns < 1) {
        std::fprintf(stderr, "usage: osg_load FILE [--rounds N (11)] [--memory-runs M (3)]\n");
        return 2;
    }

    // Kept results of the memory children (never freed there: the child exits).
    static std::vector<osg::ref_ptr<osg::Node>> keptOsg;
    static std::vector<std::shared_ptr<sgfx::Group>> keptSgfx;
    const auto osgLoad = [](const std::string& f) { return osgDB::readRefNodeFile(f).valid(); };
    const auto sgfxLoad = [](bool isolate) {
        return [isolate](const std::string& f) {
            sgfx::OsgOptions o;
            o.isolateReader = isolate;
            sgfx::OsgStats stats; // warnings collected, not printed
            return sgfx::loadOsg(f, o, &stats) != nullptr;
        };
    };
    const Loader loaders[3] = {
        {"osgDB::readNodeFile", osgLoad,
         [](const std::string& f) {
             keptOsg.push_back(osgDB::readRefNodeFile(f));
             return keptOsg.back().valid();
         }},
        {"sgfx::loadOsg isolateReader on", sgfxLoad(true),
         [](const std::string& f) {
             sgfx::OsgStats stats;
             keptSgfx.push_back(sgfx::loadOsg(f, {}, &stats));
             return keptSgfx.back() != nullptr;
         }},
        {"sgfx::loadOsg isolateReader off", sgfxLoad(false),
         [](const std::string& f) {
             sgfx::OsgOptions o;
             o.isolateReader = false;
             sgfx::OsgStats stats;
             keptSgfx.push_back(sgfx::loadOsg(f, o, &stats));
             return keptSgfx.back() != nullptr;
         }},
    };

    // ---- memory: fresh children, interleaved
    std::vector<double> growth[3];
    for (int r = 0; r < memoryRuns; ++r)
        for (int k = 0; k < 3; ++k) {
            const double g = memoryInChild(loaders[k], file);
            if (g < 0) {
                std::fprintf(stderr, "osg_load: %s failed on %s\n", loaders[k].name, file.c_str());
                return 1;
            }
            growth[k].push_back(g);
        }

    // ---- time: warm-up, then interleaved rounds in rotating order
    using clock = std::chrono::steady_clock;
    std::vector<double> ms[3], ratio[3];
    for (const Loader& l : loaders)
        if (!l.load(file)) {
            std::fprintf(stderr, "osg_load: %s failed on %s\n", l.name, file.c_str());
            return 1;
        }
    for (int r = 0; r < rounds; ++r) {
        double t[3] = {};
        for (int j = 0; j < 3; ++j) {
            const int k = (r + j) % 3;
            const auto t0 = clock::now();
            loaders[k].load(file);
            t[k] = std::chrono::duration<double, std::milli>(clock::now() - t0).count();
        }
        for (int k = 0; k < 3; ++k) {
            ms[k].push_back(t[k]);
            ratio[k].push_back(t[k] / t[0]);
        }
    }

    const char* base = std::strrchr(file.c_str(), '/');
    base = base ? base + 1 : file.c_str();
    std::printf("%s: %d timed rounds (after one warm-up load each), memory over %d fresh processes each\n",
                base, rounds, memoryRuns);
    for (int k = 0; k < 3; ++k)
        std::printf("OSG_LOAD file=%s loader=%d name=\"%s\" median_ms=%.2f min_ms=%.2f ratio_to_osg=%.3f "
                    "rss_growth_mib=%.2f\n",
                    base, k, loaders[k].name, median(ms[k]), *std::min_element(ms[k].begin(), ms[k].end()),
                    median(ratio[k]), median(growth[k]) / (1024.0 * 1024.0));
    return 0;
}

#pragma once
// The scene-query workloads of bench/query_table.sh, shared by query_bench (sgfx) and osg_query
// (OpenSceneGraph 3.6) so both ask exactly the same questions: the same box, the same splitmix64
// stream, the same arithmetic. Depends on neither library.
#include <time.h>

#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

namespace queryworkload {

struct Vec3 {
    double x = 0, y = 0, z = 0;
};

struct Box {
    Vec3 min{1e300, 1e300, 1e300};
    Vec3 max{-1e300, -1e300, -1e300};
    bool valid() const { return min.x <= max.x; }
};

struct Segment {
    Vec3 start, end;
};

// The box of the OBJ's vertex lines. The export is in world coordinates, so this is the scene's
// world box; reading it from the file (not from each side's loaded scene) makes it bit-identical
// on both sides whatever the loaders do with unused vertices.
inline Box objBounds(const std::string& path) {
    std::ifstream in(path);
    Box b;
    std::string line;
    while (std::getline(in, line)) {
        if (line.size() < 2 || line[0] != 'v' || !std::isspace(static_cast<unsigned char>(line[1]))) continue;
        const char* p = line.c_str() + 1;
        char* e = nullptr;
        double v[3];
        for (double& c : v) {
            // Parsed as float first: the loaders keep float positions, so the box holds them exactly.
            c = double(std::strtof(p, &e));
            p = e;
        }
        b.min = {std::fmin(b.min.x, v[0]), std::fmin(b.min.y, v[1]), std::fmin(b.min.z, v[2])};
        b.max = {std::fmax(b.max.x, v[0]), std::fmax(b.max.y, v[1]), std::fmax(b.max.z, v[2])};
    }
    return b;
}

// splitmix64 (Steele, Lea, Flood 2014): tiny, and the same stream on every compiler.
struct SplitMix64 {
    std::uint64_t state;
    std::uint64_t next() {
        std::uint64_t z = (state += 0x9e3779b97f4a7c15ull);
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
        return z ^ (z >> 31);
    }
    // Uniform in [0, 1): the top 53 bits.
    double unit() { return double(next() >> 11) * 0x1.0p-53; }
    double uniform(double lo, double hi) { return lo + (hi - lo) * unit(); }
};

constexpr std::uint64_t kSeed = 20240530;

// Terrain following: vertical segments from 1 m above the box to 1 m below it, x and y uniform
// over the box's xy extent shrunk by 5% (so the scene's ragged rim is left out).
inline std::vector<Segment> terrainSegments(const Box& box, std::size_t n, std::uint64_t seed = kSeed) {
    SplitMix64 rng{seed};
    const double mx = 0.025 * (box.max.x - box.min.x), my = 0.025 * (box.max.y - box.min.y);
    std::vector<Segment> out(n);
    for (Segment& s : out) {
        const double x = rng.uniform(box.min.x + mx, box.max.x - mx);
        const double y = rng.uniform(box.min.y + my, box.max.y - my);
        s = {{x, y, box.max.z + 1.0}, {x, y, box.min.z - 1.0}};
    }
    return out;
}

// Line of sight: between two random points over the same xy area at heights in the lowest 30% of
// the box (from 2 m above its bottom), where terrain, buildings and trees get in the way.
inline std::vector<Segment> sightSegments(const Box& box, std::size_t n, std::uint64_t seed = kSeed + 1) {
    SplitMix64 rng{seed};
    const double mx = 0.025 * (box.max.x - box.min.x), my = 0.025 * (box.max.y - box.min.y);
    const double z0 = box.min.z + 2.0, z1 = box.min.z + 0.3 * (box.max.z - box.min.z);
    std::vector<Segment> out(n);
    for (Segment& s : out) {
        for (Vec3* p : {&s.start, &s.end}) {
            p->x = rng.uniform(box.min.x + mx, box.max.x - mx);
            p->y = rng.uniform(box.min.y + my, box.max.y - my);
            p->z = rng.uniform(z0, z1);
        }
    }
    return out;
}

// FNV-1a over the segments' bits: equal on both sides only if the questions are.
inline std::uint64_t checksum(const std::vector<Segment>& segments) {
    std::uint64_t h = 0xcbf29ce484222325ull;
    for (const Segment& s : segments) {
        for (double d : {s.start.x, s.start.y, s.start.z, s.end.x, s.end.y, s.end.z}) {
            std::uint64_t bits;
            std::memcpy(&bits, &d, sizeof bits);
            for (int i = 0; i < 8; ++i) {
                h ^= (bits >> (8 * i)) & 0xffu;
                h *= 0x100000001b3ull;
            }
        }
    }
    return h;
}

// Wall time, and the process's CPU time: on a shared machine (2 cores, builds beside) the CPU
// time leaves out the moments the program waited for a core; the table reads it.
struct Stopwatch {
    static double cpuNow() {
        timespec t{};
        clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
        return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
    }
    std::chrono::steady_clock::time_point wall0 = std::chrono::steady_clock::now();
    double cpu0 = cpuNow();
    double wall() const {
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
    }
    double cpu() const { return cpuNow() - cpu0; }
};

// Where each side reports its results: one line per workload, parsed by bench/query_table.sh.
struct Result {
    std::size_t rays = 0;
    double seconds = 0, cpuSeconds = 0;
    std::size_t hits = 0; // terrain: segments that hit; sight: segments that are blocked
    double hitZSum = 0;   // terrain: sum of the nearest hits' z
};

inline void print(const char* side, const char* workload, const std::vector<Segment>& segments,
                  const Result& r) {
    std::printf("QUERY side=%s workload=%s rays=%zu seconds=%.4f cpu_seconds=%.4f rays_per_s=%.1f "
                "rays_per_cpu_s=%.1f us_per_ray=%.3f hits=%zu hit_z_sum=%.3f queries=%016llx\n",
                side, workload, r.rays, r.seconds, r.cpuSeconds, double(r.rays) / r.seconds,
                double(r.rays) / r.cpuSeconds, 1e6 * r.seconds / double(r.rays), r.hits, r.hitZSum,
                static_cast<unsigned long long>(checksum(segments)));
}

struct Args {
    std::string file;
    std::size_t terrainRays = 100000;
    std::size_t sightRays = 10000;
};

// FILE [--terrain N] [--sight N]
inline bool parseArgs(int argc, char** argv, const char* program, Args& a) {
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        if ((arg == "--terrain" || arg == "--sight") && i + 1 < argc) {
            const long long n = std::atoll(argv[++i]);
            if (n < 1) return false;
            (arg == "--terrain" ? a.terrainRays : a.sightRays) = std::size_t(n);
        } else if (arg == "-h" || arg == "--help" || !a.file.empty() || arg.empty() || arg[0] == '-') {
            std::fprintf(stderr, "usage: %s FILE.obj [--terrain N] [--sight N]\n", program);
            return false;
        } else {
            a.file = arg;
        }
    }
    if (a.file.empty()) std::fprintf(stderr, "usage: %s FILE.obj [--terrain N] [--sight N]\n", program);
    return !a.file.empty();
}

} // namespace queryworkload

// A three-level paged terrain flown through headless (OSMesa/llvmpipe): the measurement behind
// PagedLOD and DatabasePager's promise that no frame waits on a load and that memory returns when
// the camera leaves. Level 0 is one 1024 m tile, level 1 four, level 2 sixteen; each a height-field
// grid (GRID x GRID quads, its level's colour) written as a .glb file into a temporary folder. The
// root PagedLOD is built in memory; the loader turns "L<level>_<x>_<y>.tile" into the four tiles of
// that cell (PagedLODs for level 1, meshes for level 2), read with loadModel, after --load-delay
// ms of sleep (a slow disk). The camera starts far (level 0 only), comes down over the terrain
// (level 1 and 2 stream in), crosses it, climbs far away and stays there until every tile expired.
// Each frame's wall time is Viewer::frame plus glFinish (llvmpipe's drawing counted in its frame);
// frames are "streaming" when a load was pending before or after them, else "idle". Memory: RSS
// (/proc/self/statm), the heap in use (mallinfo2, every arena) and sgfx's live GL objects, at the
// start (before the first request), the peak and the end. Prints a report and one PAGED line.
//   paged_terrain [--size WxH] [--grid N] [--frames N] [--load-delay MS] [--expiry-frames N]
//                 [--expiry-s S]
#include <sgfx/Camera.h>
#include <sgfx/DatabasePager.h>
#include <sgfx/Geometry.h>
#include <sgfx/GltfWriter.h>
#include <sgfx/Group.h>
#include <sgfx/ModelLoader.h>
#include <sgfx/PagedLOD.h>
#include <sgfx/Shapes.h>
#include <sgfx/Viewer.h>
#include <sgfx/gl/Objects.h>

#include <sgfx_glad/gl.h>

#include <CLI/CLI.hpp>
#include <malloc.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <thread>
#include <vector>

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kWorld = 1024.0f;                       // level 0's edge, m
constexpr std::array<float, 2> kRange{1400.0f, 700.0f}; // level L's children within this distance
const std::array<glm::vec3, 3> kColour{glm::vec3(0.80f, 0.45f, 0.30f), glm::vec3(0.35f, 0.70f, 0.30f),
                                       glm::vec3(0.30f, 0.50f, 0.85f)};

struct Options {
    int width = 640, height = 360, grid = 64, frames = 600, loadDelayMs = 0, expiryFrames = 30;
    double expirySeconds = 0.5;
};

float edgeOf(int level) {
    return kWorld / float(1 << level);
}
glm::vec3 centreOf(int level, int ix, int iy) {
    const float e = edgeOf(level);
    return {-0.5f * kWorld + e * (float(ix) + 0.5f), -0.5f * kWorld + e * (float(iy) + 0.5f), 0.0f};
}
float terrainHeight(float x, float y) {
    return 45.0f * std::sin(x * 0.011f) * std::cos(y * 0.013f) + 18.0f * std::sin((x + 2.0f * y) * 0.031f) +
           6.0f * std::cos((3.0f * x - y) * 0.07f);
}
fs::path tileFile(const fs::path& dir, int level, int ix, int iy) {
    return dir /
           ("tile_" + std::to_string(level) + "_" + std::to_string(ix) + "_" + std::to_string(iy) + ".glb");
}

// One tile's mesh, its level's colour darkened in the valleys.
std::shared_ptr<sgfx::Geometry> tileMesh(int level, int ix, int iy, int grid) {
    const glm::vec3 c = centreOf(level, ix, iy);
    const float e = edgeOf(level);
    auto g = sgfx::shapes::heightfield(c.x - 0.5f * e, c.y - 0.5f * e, e, e, grid, grid, terrainHeight);
    g->name = "tile " + std::to_string(level) + " " + std::to_string(ix) + " " + std::to_string(iy);
    g->colors.reserve(g->positions.size());
    for (const glm::vec3& p : g->positions)
        g->colors.emplace_back(kColour[std::size_t(level)] * (0.65f + 0.35f * (p.z + 70.0f) / 140.0f), 1.0f);
    return g;
}

void writeTiles(const fs::path& dir, int grid) {
    for (int level = 0; level < 3; ++level)
        for (int iy = 0; iy < (1 << level); ++iy)
            for (int ix = 0; ix < (1 << level); ++ix)
                sgfx::writeGltf(*tileMesh(level, ix, iy, grid), tileFile(dir, level, ix, iy));
}

// Tile (level, ix, iy) as a PagedLOD: its mesh beyond kRange[level], its four children's file within.
std::shared_ptr<sgfx::PagedLOD> pagedTile(int level, int ix, int iy, const fs::path& dir) {
    auto lod = sgfx::PagedLOD::create();
    lod->name = "paged " + std::to_string(level) + " " + std::to_string(ix) + " " + std::to_string(iy);
    lod->setRangeMode(sgfx::LOD::RangeMode::DistanceFromEye);
    lod->setDatabasePath(dir);
    lod->setUserSphere(centreOf(level, ix, iy), edgeOf(level) * 0.75f);
    lod->addChild(sgfx::loadModel(tileFile(dir, level, ix, iy)), kRange[std::size_t(level)], kInf);
    lod->addChild("L" + std::to_string(level + 1) + "_" + std::to_string(ix) + "_" + std::to_string(iy) +
                      ".tile",
                  0.0f, kRange[std::size_t(level)]);
    return lod;
}

// The loader: "L<level>_<px>_<py>.tile" is the four level-<level> tiles of parent cell (px, py).
sgfx::NodePtr loadTiles(const fs::path& file, int delayMs) {
    if (delayMs > 0) std::this_thread::sleep_for(std::chrono::milliseconds(delayMs));
    int level = 0, px = 0, py = 0;
    if (std::sscanf(file.filename().string().c_str(), "L%d_%d_%d.tile", &level, &px, &py) != 3 || level < 1 ||
        level > 2)
        throw std::runtime_error("not a tile name: " + file.string());
    auto group = sgfx::Group::create();
    for (int k = 0; k < 4; ++k) {
        const int ix = 2 * px + (k & 1), iy = 2 * py + (k >> 1);
        if (level < 2)
            group->addChild(pagedTile(level, ix, iy, file.parent_path()));
        else
            group->addChild(sgfx::loadModel(tileFile(file.parent_path(), level, ix, iy)));
    }
    return group;
}

// The camera path: eye and target at keyframes, each reached at a fraction of the frames.
struct Key {
    double at;
    glm::vec3 eye, target;
};
const std::array<Key, 7> kPath{{
    {0.00, {0, -4000, 1500}, {0, 0, 0}},    // far: level 0 alone
    {0.10, {0, -4000, 1500}, {0, 0, 0}},    // (held)
    {0.30, {0, -900, 400}, {0, 0, 0}},      // level 1 wanted
    {0.45, {-400, -400, 150}, {0, 0, 0}},   // low over tile (0, 0): its level 2
    {0.75, {400, 400, 150}, {700, 700, 0}}, // across: every level-1 tile's children
    {0.85, {3000, 3000, 3000}, {0, 0, 0}},  // climbing away
    {1.00, {3000, 3000, 3000}, {0, 0, 0}},  // far, until every tile expired
}};

void placeCamera(sgfx::Camera& cam, double t) {
    std::size_t k = 1;
    while (k + 1 < kPath.size() && kPath[k].at < t)
        ++k;
    const Key &a = kPath[k - 1], &b = kPath[k];
    const float s = float(std::clamp((t - a.at) / std::max(b.at - a.at, 1e-9), 0.0, 1.0));
    cam.setLookAt(glm::mix(a.eye, b.eye, s), glm::mix(a.target, b.target, s), {0, 0, 1});
}

// Memory and GL objects at one moment.
struct Snapshot {
    double rssMb = 0, heapMb = 0;
    long buffers = 0, textures = 0, vaos = 0;
};

Snapshot snapshot() {
    Snapshot s;
    long pages = 0, resident = 0;
    if (std::ifstream statm("/proc/self/statm"); statm >> pages >> resident)
        s.rssMb = double(resident) * double(::sysconf(_SC_PAGESIZE)) / 1048576.0;
    const struct mallinfo2 mi = ::mallinfo2();
    s.heapMb = double(mi.uordblks + mi.hblkhd) / 1048576.0;
    s.buffers = sgfx::gl::liveObjects()[sgfx::gl::Kind::Buffer];
    s.textures = sgfx::gl::liveObjects()[sgfx::gl::Kind::Texture];
    s.vaos = sgfx::gl::liveObjects()[sgfx::gl::Kind::VertexArray];
    return s;
}

Snapshot peakOf(const Snapshot& a, const Snapshot& b) {
    return {std::max(a.rssMb, b.rssMb), std::max(a.heapMb, b.heapMb), std::max(a.buffers, b.buffers),
            std::max(a.textures, b.textures), std::max(a.vaos, b.vaos)};
}

struct Frame {
    double ms = 0;
    bool streaming = false; ///< a load pending before or after it
    bool attach = false;    ///< a loaded subgraph attached in its update (drawn, so uploaded, in it)
};
struct Run {
    std::vector<Frame> frames;
    Snapshot start, peak, end;
    sgfx::DatabasePager::Stats stats;
    std::size_t errors = 0;
    int tailFrames = 0;
};

// One frame along the path: timed, classified, memory tracked.
void timedFrame(sgfx::Viewer& v, Run& r, bool& started) {
    const sgfx::DatabasePager::Stats before = v.databasePager()->stats();
    const auto t0 = Clock::now();
    v.frame(1.0 / 60.0);
    glFinish();
    const double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    const sgfx::DatabasePager::Stats s = v.databasePager()->stats();
    r.frames.push_back({ms, before.pending > 0 || s.pending > 0, s.loaded > before.loaded});
    const Snapshot now = snapshot();
    if (!started && s.requested == 0) r.start = now;
    started = started || s.requested > 0;
    r.peak = peakOf(r.peak, now);
}

Run fly(const Options& o, const fs::path& dir) {
    auto v = sgfx::Viewer::createHeadless(o.width, o.height);
    v->databasePager()->setLoader([delay = o.loadDelayMs](const fs::path& f) { return loadTiles(f, delay); });
    v->databasePager()->setExpiry(std::uint64_t(o.expiryFrames), o.expirySeconds);
    v->camera()->setPerspective(50.0f, 1.0f, 20000.0f);
    auto scene = sgfx::Group::create();
    auto sun = sgfx::Light::create(sgfx::LightType::Directional);
    sun->direction = glm::normalize(glm::vec3(-0.4f, -0.3f, -0.85f));
    auto sky = sgfx::Light::create(sgfx::LightType::Ambient);
    sky->intensity = 0.35f;
    scene->addChild(sun);
    scene->addChild(sky);
    scene->addChild(pagedTile(0, 0, 0, dir));
    v->setSceneData(scene);
    placeCamera(*v->camera(), 0.0);
    for (int f = 0; f < 3; ++f) // untimed: programs compiled, level 0 uploaded
        v->frame(1.0 / 60.0);
    Run r;
    bool started = false;
    for (int f = 0; f < o.frames; ++f) {
        placeCamera(*v->camera(), double(f) / double(std::max(o.frames - 1, 1)));
        timedFrame(*v, r, started);
    }
    // Far away: on until nothing is pending or loaded (a bound, not a timing check).
    const int tailLimit = 20 * (o.expiryFrames + int(o.expirySeconds * 60.0)) + 6000;
    for (; r.tailFrames < tailLimit; ++r.tailFrames) {
        const sgfx::DatabasePager::Stats s = v->databasePager()->stats();
        if (s.pending == 0 && s.live == 0) break;
        timedFrame(*v, r, started);
        if (s.pending > 0) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    r.stats = v->databasePager()->stats();
    r.errors = v->databasePager()->errors().size();
    std::printf("GL_RENDERER: %s\n", reinterpret_cast<const char*>(glGetString(GL_RENDERER)));
    r.end = snapshot(); // the viewer and level 0 still alive, as at the start
    return r;
}

struct Summary {
    double median = 0, p95 = 0, max = 0;
};
Summary summarise(std::vector<double> v) {
    Summary s;
    if (v.empty()) return s;
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    s.median = n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
    s.p95 = v[std::min(n - 1, std::size_t(std::ceil(0.95 * double(n))) - 1)];
    s.max = v.back();
    return s;
}

// Frame times: streaming, idle, and the streaming frames that attached.
struct Split {
    std::vector<double> streaming, idle, attach;
};
Split split(const std::vector<Frame>& frames) {
    Split s;
    for (const Frame& f : frames) {
        (f.streaming ? s.streaming : s.idle).push_back(f.ms);
        if (f.attach) s.attach.push_back(f.ms);
    }
    return s;
}

// The largest ratio of a streaming frame to the median of the 31 frames around it (the camera,
// hence what is drawn, nearly the same).
double worstLocalRatio(const std::vector<Frame>& frames) {
    double worst = 0;
    for (std::size_t i = 0; i < frames.size(); ++i) {
        if (!frames[i].streaming) continue;
        std::vector<double> around;
        for (std::size_t j = i > 15 ? i - 15 : 0; j < std::min(frames.size(), i + 16); ++j)
            around.push_back(frames[j].ms);
        worst = std::max(worst, frames[i].ms / std::max(summarise(around).median, 1e-9));
    }
    return worst;
}

void report(const Options& o, const Run& r) {
    const auto [streaming, idle, attach] = split(r.frames);
    const Summary st = summarise(streaming), id = summarise(idle), at = summarise(attach);
    std::vector<double> all = streaming;
    all.insert(all.end(), idle.begin(), idle.end());
    const double ratio = st.max / std::max(summarise(all).median, 1e-9), local = worstLocalRatio(r.frames);
    const bool returned = r.stats.pending == 0 && r.stats.live == 0 && r.errors == 0 && r.stats.failed == 0 &&
                          r.end.buffers == r.start.buffers && r.end.textures == r.start.textures &&
                          r.end.vaos == r.start.vaos;
    std::printf(
        "paged_terrain: %dx%d, %dx%d quads per tile, 21 tiles, load delay %d ms, %d frames on the path + "
        "%d until expiry\n",
        o.width, o.height, o.grid, o.grid, o.loadDelayMs, o.frames, r.tailFrames);
    std::printf("  frames     count  median ms  p95 ms  max ms\n");
    std::printf("  streaming  %5zu  %9.2f  %6.2f  %6.2f\n", streaming.size(), st.median, st.p95, st.max);
    std::printf("  idle       %5zu  %9.2f  %6.2f  %6.2f\n", idle.size(), id.median, id.p95, id.max);
    std::printf("  attaching  %5zu  %9.2f  %6.2f  %6.2f  (streaming frames whose update attached a file)\n",
                attach.size(), at.median, at.p95, at.max);
    std::printf("  largest streaming frame / median frame: %.2f; / median of the 31 frames around it: %.2f\n",
                ratio, local);
    std::printf("  loads %zu (%zu tiles), expired %zu, live %zu, pending %zu, failed %zu\n", r.stats.loaded,
                4 * r.stats.loaded, r.stats.expired, r.stats.live, r.stats.pending, r.stats.failed);
    std::printf("             start    peak     end\n");
    std::printf("  RSS MB   %7.1f %7.1f %7.1f\n", r.start.rssMb, r.peak.rssMb, r.end.rssMb);
    std::printf("  heap MB  %7.1f %7.1f %7.1f\n", r.start.heapMb, r.peak.heapMb, r.end.heapMb);
    std::printf("  buffers  %7ld %7ld %7ld\n", r.start.buffers, r.peak.buffers, r.end.buffers);
    std::printf("  textures %7ld %7ld %7ld\n", r.start.textures, r.peak.textures, r.end.textures);
    std::printf("  VAOs     %7ld %7ld %7ld\n", r.start.vaos, r.peak.vaos, r.end.vaos);
    std::printf(
        "PAGED size=%dx%d grid=%d delay_ms=%d stream_frames=%zu stream_median_ms=%.2f stream_p95_ms=%.2f "
        "stream_max_ms=%.2f idle_frames=%zu idle_median_ms=%.2f idle_p95_ms=%.2f idle_max_ms=%.2f "
        "attach_frames=%zu attach_max_ms=%.2f max_stream_ratio=%.2f local_ratio=%.2f loaded=%zu expired=%zu "
        "live=%zu pending=%zu rss_start_mb=%.1f "
        "rss_peak_mb=%.1f rss_end_mb=%.1f heap_start_mb=%.1f heap_peak_mb=%.1f heap_end_mb=%.1f "
        "buffers_start=%ld buffers_peak=%ld buffers_end=%ld textures_start=%ld textures_peak=%ld "
        "textures_end=%ld vaos_start=%ld vaos_peak=%ld vaos_end=%ld returned=%s\n",
        o.width, o.height, o.grid, o.loadDelayMs, streaming.size(), st.median, st.p95, st.max, idle.size(),
        id.median, id.p95, id.max, attach.size(), at.max, ratio, local, r.stats.loaded, r.stats.expired,
        r.stats.live, r.stats.pending, r.start.rssMb, r.peak.rssMb, r.end.rssMb, r.start.heapMb,
        r.peak.heapMb, r.end.heapMb, r.start.buffers, r.peak.buffers, r.end.buffers, r.start.textures,
        r.peak.textures, r.end.textures, r.start.vaos, r.peak.vaos, r.end.vaos, returned ? "yes" : "no");
}

// A temporary folder, removed with everything in it.
struct TempDir {
    fs::path path = fs::temp_directory_path() / ("sgfx_paged_terrain_" + std::to_string(::getpid()));
    TempDir() { fs::create_directories(path); }
    ~TempDir() {
        std::error_code ec;
        fs::remove_all(path, ec);
    }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;
};

} // namespace

int main(int argc, char** argv) {
    Options o;
    CLI::App app{"paged_terrain: flies a camera over a three-level paged terrain headless and reports frame "
                 "times while tiles stream, tiles loaded and expired, and memory and GL objects"};
    std::string size = "640x360";
    app.add_option("--size", size, "viewport WxH (default 640x360)");
    app.add_option("--grid", o.grid, "quads along each tile's side (default 64)")->check(CLI::Range(1, 1024));
    app.add_option("--frames", o.frames, "frames along the camera path (default 600)")
        ->check(CLI::Range(2, 1000000));
    app.add_option("--load-delay", o.loadDelayMs, "ms the loader sleeps per file (default 0)")
        ->check(CLI::Range(0, 60000));
    app.add_option("--expiry-frames", o.expiryFrames, "pager expiry frames (default 30)")
        ->check(CLI::Range(0, 100000));
    app.add_option("--expiry-s", o.expirySeconds, "pager expiry seconds of simulation time (default 0.5)")
        ->check(CLI::Range(0.0, 3600.0));
    CLI11_PARSE(app, argc, argv);
    if (std::sscanf(size.c_str(), "%dx%d", &o.width, &o.height) != 2 || o.width < 1 || o.height < 1) {
        std::fprintf(stderr, "paged_terrain: --size: expected WxH, got '%s'\n", size.c_str());
        return 2;
    }
    try {
        TempDir dir;
        writeTiles(dir.path, o.grid);
        report(o, fly(o, dir.path));
    } catch (const std::exception& e) {
        std::fprintf(stderr, "paged_terrain: %s\n", e.what());
        return 1;
    }
    return 0;
}

// Per-pixel cost ladder (docs/performance.md, "Per-pixel cost on foreign content"): a model loaded
// with loadModel and orbited as in issue 24 (eye at 1.5× the bounding radius, 30° elevation, 60°
// vertical field of view, the orbit angle advancing every frame), one sun and an ambient light, no
// effects. Run it at two sizes: the frame at 1280×720 minus the frame at 320×180 is the per-pixel
// cost. The toggles are profiling-only RendererOptions that change the image:
//
//   pixel_cost FILE [--size 1280x720] [--frames 40] [--target srgb8|unorm8] [--submit-triangles N]
//              [--lighting pixel|vertex] [--shading full|constant] [--count-fragments] [--turn]
//   pixel_cost FILE --ladder ROUNDS
//
// Each frame's wall time is Viewer::frame plus glFinish (llvmpipe's rasterising counted in its
// frame). Prints one line: BENCH median_ms=... p25_ms=... p75_ms=... triangles=... draws=...
// [fragments=... per_pixel=...]. --cpu-time times by the CPU time of all threads instead (steadier
// on a shared machine). --ladder runs every toggle of kLadder at 1280×720 and 320×180 in
// the same process, one frame of each per round at the round's orbit angle (after an untimed one,
// so a size change's reallocation is not timed), and prints per toggle LADDER lines with the
// medians over rounds of both frames, of their difference (the per-pixel cost) and of its
// per-round ratio to the first toggle's: a busy machine slows every toggle of a round alike.
// --turn (not with --ladder) takes the views of `osg_view --orbit` and `sgfx-view --orbit` instead
// (a full turn over the timed frames from yaw 30°, near 0.01 and far 4 bounding radii), so that
// bench/pixel_vs_osg.sh compares sgfx and OSG on the same views.
#include <sgfx/Camera.h>
#include <sgfx/Group.h>
#include <sgfx/ModelLoader.h>
#include <sgfx/Renderer.h>
#include <sgfx/Viewer.h>
#include <sgfx/Visitors.h>

#include <CLI/CLI.hpp>
#include <sgfx_glad/gl.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <exception>
#include <string>
#include <vector>

namespace {

struct Options {
    std::string file;
    std::string size = "1280x720";
    int frames = 40;
    std::string target = "srgb8";
    std::uint64_t submitTriangles = sgfx::RendererOptions{}.submitTriangles;
    std::string lighting = "pixel";
    std::string shading = "full";
    bool countFragments = false;
    int ladder = 0;
    bool cpuTime = false;
    bool turn = false;
};

struct Toggle {
    const char* name;
    const char* target;
    std::uint64_t submitTriangles;
    const char* lighting;
    const char* shading;
};
// The ladder: each toggle removes one per-fragment cost (or all of them: the floor).
constexpr Toggle kLadder[] = {
    {"default", "srgb8", 20000, "pixel", "full"},      {"unorm8", "unorm8", 20000, "pixel", "full"},
    {"submit0", "srgb8", 0, "pixel", "full"},          {"per-vertex", "srgb8", 20000, "vertex", "full"},
    {"constant", "srgb8", 20000, "pixel", "constant"}, {"floor", "unorm8", 0, "pixel", "constant"}};

double percentile(std::vector<double> v, double p) {
    std::sort(v.begin(), v.end());
    const double at = p * double(v.size() - 1);
    const auto lo = std::size_t(at);
    const std::size_t hi = std::min(lo + 1, v.size() - 1);
    return v[lo] + (v[hi] - v[lo]) * (at - double(lo));
}

void applyOptions(const Options& o, sgfx::RendererOptions& r) {
    using T = sgfx::RendererOptions::ColorTarget;
    if (o.target != "srgb8" && o.target != "unorm8")
        throw CLI::ValidationError("--target", "srgb8 or unorm8");
    r.colorTarget = o.target == "unorm8" ? T::Unorm8Debug : T::Srgb8;
    r.submitTriangles = o.submitTriangles;
    if (o.lighting != "pixel" && o.lighting != "vertex")
        throw CLI::ValidationError("--lighting", "pixel or vertex");
    r.lighting = o.lighting == "vertex" ? sgfx::RendererOptions::Lighting::PerVertex
                                        : sgfx::RendererOptions::Lighting::PerPixel;
    if (o.shading != "full" && o.shading != "constant")
        throw CLI::ValidationError("--shading", "full or constant");
    r.debugConstantShading = o.shading == "constant";
    r.countFragments = o.countFragments;
}

// CPU time of every thread of the process (llvmpipe's rasterizer threads included): the work a
// frame did, whatever else the machine runs (wall time on a shared machine counts the waits too).
double processCpuMs() {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return double(t.tv_sec) * 1e3 + double(t.tv_nsec) * 1e-6;
}

// The model under a sun and an ambient light, on the orbit of issue 24.
struct Bench {
    std::unique_ptr<sgfx::Viewer> viewer;
    glm::vec3 centre{0.0f};
    float distance = 1.0f;
    bool cpuTime = false;
    int turnFrames = 0; // > 0: osg_view --orbit's views, a full turn over this many frames

    Bench(const std::string& file, int width, int height) {
        auto model = sgfx::loadModel(file);
        sgfx::ComputeBoundsVisitor bounds;
        model->accept(bounds);
        if (!bounds.valid()) throw std::runtime_error(file + ": no geometry");
        centre = 0.5f * (bounds.min + bounds.max);
        distance = 1.5f * std::max(0.5f * glm::length(bounds.max - bounds.min), 1e-3f);
        viewer = sgfx::Viewer::createHeadless(width, height);
        auto root = sgfx::Group::create();
        auto sun = sgfx::Light::create(sgfx::LightType::Directional);
        sun->direction = glm::normalize(glm::vec3(-0.4f, -0.3f, -0.85f));
        sun->color = glm::vec3(0.9f);
        auto sky = sgfx::Light::create(sgfx::LightType::Ambient);
        sky->intensity = 0.35f;
        root->addChild(sun);
        root->addChild(sky);
        root->addChild(model);
        viewer->setSceneData(root);
        viewer->camera()->setPerspective(60.0f, distance * 0.01f, distance * 4.0f);
    }
    // Wall time of the frame at orbit step `step` (1.5° a step, 30° elevation), glFinish included.
    double frame(int step) {
        // osg_view's yaw (30° + 360° i / N, looking along +Y at yaw 0) is this azimuth less 90°.
        const float angle = turnFrames > 0 ? glm::radians(360.0f * float(step) / float(turnFrames) - 60.0f)
                                           : glm::radians(1.5f * float(step));
        const float elevation = glm::radians(30.0f);
        const glm::vec3 dir(std::cos(elevation) * std::cos(angle), std::cos(elevation) * std::sin(angle),
                            std::sin(elevation));
        viewer->camera()->setLookAt(centre + distance * dir, centre, {0, 0, 1});
        const auto t0 = std::chrono::steady_clock::now();
        const double c0 = processCpuMs();
        viewer->frame(1.0 / 60.0);
        glFinish();
        if (cpuTime) return processCpuMs() - c0;
        return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    }
};

void runSingle(const Options& o, int width, int height) {
    Bench b(o.file, width, height);
    b.cpuTime = o.cpuTime;
    applyOptions(o, b.viewer->renderer().options());
    if (o.turn) {
        b.turnFrames = o.frames;
        const float radius = b.distance / 1.5f;
        b.viewer->camera()->setPerspective(60.0f, 0.01f * radius, 4.0f * radius);
    }
    const int first = o.turn ? 0 : 3; // osg_view warms up at its first view
    for (int f = 0; f < 3; ++f) // untimed: programs compiled, meshes uploaded
        b.frame(o.turn ? 0 : f);
    std::vector<double> ms;
    std::uint64_t fragments = 0;
    for (int f = 0; f < o.frames; ++f) {
        ms.push_back(b.frame(first + f));
        fragments += b.viewer->stats().fragments;
    }
    const sgfx::FrameStats& s = b.viewer->stats();
    std::printf("BENCH size=%dx%d median_ms=%.3f p25_ms=%.3f p75_ms=%.3f triangles=%zu draws=%zu", width,
                height, percentile(ms, 0.5), percentile(ms, 0.25), percentile(ms, 0.75), s.triangles,
                s.drawCalls);
    if (o.countFragments)
        std::printf(" fragments=%.0f per_pixel=%.3f", double(fragments) / o.frames,
                    double(fragments) / o.frames / (double(width) * height));
    std::printf("\n");
}

void runLadder(const Options& o) {
    Bench b(o.file, 1280, 720);
    b.cpuTime = o.cpuTime;
    constexpr std::size_t n = std::size(kLadder);
    std::vector<double> big[n], small[n], cost[n], ratio[n];
    for (int round = -1; round < o.ladder; ++round) { // round -1 compiles every variant
        double baseCost = 0.0;
        for (std::size_t t = 0; t < n; ++t) {
            Options to = o;
            to.target = kLadder[t].target;
            to.submitTriangles = kLadder[t].submitTriangles;
            to.lighting = kLadder[t].lighting;
            to.shading = kLadder[t].shading;
            applyOptions(to, b.viewer->renderer().options());
            double ms[2];
            for (int size = 0; size < 2; ++size) {
                b.viewer->camera()->setViewport(0, 0, size ? 320 : 1280, size ? 180 : 720);
                b.frame(round);
                ms[size] = b.frame(round);
            }
            if (round < 0) continue;
            big[t].push_back(ms[0]);
            small[t].push_back(ms[1]);
            cost[t].push_back(ms[0] - ms[1]);
            if (t == 0) baseCost = ms[0] - ms[1];
            ratio[t].push_back((ms[0] - ms[1]) / baseCost);
        }
    }
    for (std::size_t t = 0; t < n; ++t)
        std::printf("LADDER config=%s big_ms=%.1f small_ms=%.1f per_pixel_ms=%.1f ratio=%.2f rounds=%d\n",
                    kLadder[t].name, percentile(big[t], 0.5), percentile(small[t], 0.5),
                    percentile(cost[t], 0.5), percentile(ratio[t], 0.5), o.ladder);
}

} // namespace

int main(int argc, char** argv) {
    Options o;
    CLI::App app{"Per-pixel cost of a loaded model on an orbit (docs/performance.md)"};
    app.add_option("file", o.file, "model file (loadModel)")->required();
    app.add_option("--size", o.size, "WIDTHxHEIGHT (default 1280x720)");
    app.add_option("--frames", o.frames, "timed frames (default 40)")->check(CLI::Range(1, 100000));
    app.add_option("--target", o.target,
                   "scene colour target: srgb8 (default) or unorm8 (changes the image)");
    app.add_option("--submit-triangles", o.submitTriangles, "RendererOptions::submitTriangles (0: never)");
    app.add_option("--lighting", o.lighting, "pixel (default) or vertex");
    app.add_option("--shading", o.shading, "full (default) or constant (changes the image)");
    app.add_flag("--count-fragments", o.countFragments, "count fragments passing the depth test");
    app.add_option("--ladder", o.ladder, "rounds of every toggle at both sizes, interleaved")
        ->check(CLI::Range(1, 1000));
    app.add_flag("--cpu-time", o.cpuTime, "time frames by the process's CPU time, not wall time");
    app.add_flag("--turn", o.turn,
                 "osg_view --orbit's views: a full turn over the frames (not with --ladder)");
    CLI11_PARSE(app, argc, argv);
    try {
        int width = 0, height = 0;
        if (std::sscanf(o.size.c_str(), "%dx%d", &width, &height) != 2 || width < 1 || height < 1)
            throw CLI::ValidationError("--size", "WIDTHxHEIGHT, both positive");
        if (o.ladder && o.turn) throw CLI::ValidationError("--turn", "does not go with --ladder");
        if (o.ladder)
            runLadder(o);
        else
            runSingle(o, width, height);
    } catch (const CLI::Error& e) {
        return app.exit(e);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "pixel_cost: %s\n", e.what());
        return 1;
    }
    return 0;
}

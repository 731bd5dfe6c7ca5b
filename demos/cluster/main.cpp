// sgfx-cluster: the proving ground on a display of several channels, one MPI rank per channel.
// Rank 0 runs the application (camera path, clock, vehicle, fog, rain) and sends one frame packet
// per frame; every rank renders its channel headless; a frame lock with a timeout keeps them on
// the same frame; the channels are gathered to rank 0 as one composite PNG. --reference renders
// the display's overall frustum in one process and one view (no MPI). See docs/cluster.md.
#include "Application.h"
#include "CliParse.h"
#include "ClusterSync.h"

#include <sgfx/DisplayConfig.h>
#include <sgfx/Viewer.h>

#include <CLI/CLI.hpp>
#include <sgfx_glad/gl.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <exception>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>

namespace {

using Clock = std::chrono::steady_clock;

struct Options {
    std::string config, out;
    int frames = 20, channels = 0;
    bool reference = false, stats = false, syncOnly = false, egl = false;
    // The proving ground's depth range (CameraPath.h); 0: the description's own.
    float zNear = 0.5f, zFar = 2000.0f;
    double scale = 1.0, timeout = 5.0, firstFrameTimeout = 60.0, dt = 1.0 / 60.0;
    sgfxcluster::ApplicationOptions app;
    // Test hooks (hidden from --help): a rank stops answering, or kills itself, at a frame.
    int stallRank = -1, stallFrame = -1, killRank = -1, killFrame = -1;
};

void parse(CLI::App& cli, Options& o) {
    cli.add_option("--config", o.config, "display description (JSON, demos/cluster/configs/)")->required();
    cli.add_option("--frames", o.frames, "frames to run (the last is written)")
        ->check(CLI::Range(1, 1000000));
    cli.add_option("--out", o.out, "composite PNG written by rank 0");
    cli.add_flag("--reference", o.reference, "one process, one view: the display's overall frustum (walls)");
    cli.add_option("--scale", o.scale, "channel resolutions times this (exact pixels only)")
        ->check(CLI::Range(1e-3, 16.0));
    cli.add_option("--near", o.zNear,
                   "near plane (m) for every channel, same directions (0: the description's)")
        ->check(CLI::Range(0.0, 1e6));
    cli.add_option("--far", o.zFar, "far plane (m), likewise")->check(CLI::Range(0.0, 1e9));
    cli.add_option("--timeout", o.timeout, "seconds a rank may lag before the run stops")
        ->check(CLI::Range(0.1, 600.0));
    cli.add_option("--first-frame-timeout", o.firstFrameTimeout, "the same for frame 0 (shader compiles)")
        ->check(CLI::Range(0.1, 3600.0));
    cli.add_option("--scene-scale", o.app.sceneScale, "proving ground size (polygon --scale)")
        ->check(CLI::Range(0.01, 16.0));
    cli.add_option("--path-start", o.app.pathStart, "where on the camera path's lap frame 0 is")
        ->check(CLI::Range(0.0, 1.0));
    cli.add_option("--look", o.app.look,
                   "a fixed eye and target instead of the camera path: EX EY EZ TX TY TZ")
        ->expected(6);
    cli.add_option("--rain", o.app.rainDrops, "rain drops around the eye (0: none)");
    cli.add_option("--drive", o.app.drive, "the vehicle drives (1) or stands (0)");
    cli.add_option("--channels", o.channels, "only the first N channels (benchmarks; 0: all)")
        ->check(CLI::Range(0, 4096));
    cli.add_flag("--egl", o.egl, "render through EGL on the machine's GPU instead of OSMesa");
    cli.add_flag("--sync-only", o.syncOnly,
                 "packets and frame lock without drawing (the messaging's own cost)");
    cli.add_flag("--stats", o.stats, "print frame, barrier, packet and gather figures (rank 0)");
    const std::string test = ""; // an empty group hides the test hooks from --help
    cli.add_option("--test-stall-rank", o.stallRank)->group(test);
    cli.add_option("--test-stall-frame", o.stallFrame)->group(test);
    cli.add_option("--test-kill-rank", o.killRank)->group(test);
    cli.add_option("--test-kill-frame", o.killFrame)->group(test);
}

int scaled(int v, double scale, const std::string& what) {
    const double s = v * scale;
    if (std::abs(s - std::round(s)) > 1e-6)
        throw std::invalid_argument("--scale " + std::to_string(scale) + ": " + what + " " +
                                    std::to_string(v) + " becomes " + std::to_string(s) +
                                    ", not a whole number of pixels");
    return int(std::round(s));
}

sgfx::Viewport scaled(const sgfx::Viewport& v, double scale, const std::string& what) {
    return {scaled(v.x, scale, what + ".x"), scaled(v.y, scale, what + ".y"),
            scaled(v.width, scale, what + ".width"), scaled(v.height, scale, what + ".height")};
}

// The same directions on another near plane (the edges scale with it) and another far plane: the
// application's depth range, not the display's (the proving ground's roads lie centimetres over
// its terrain, which a 0.1 m near plane cannot tell apart at a few hundred metres).
sgfx::OffAxisFrustum depthRange(sgfx::OffAxisFrustum f, const Options& o) {
    if (o.zNear > 0.0f) {
        const float k = o.zNear / f.zNear;
        f = {f.left * k, f.right * k, f.bottom * k, f.top * k, o.zNear, f.zFar};
    }
    if (o.zFar > 0.0f) f.zFar = o.zFar;
    f.validate("--near/--far");
    return f;
}

std::unique_ptr<sgfx::Viewer> makeViewer(const sgfxcluster::Application& app, const sgfx::Viewport& size,
                                         const sgfx::OffAxisFrustum& frustum, bool egl) {
    auto viewer = sgfx::Viewer::createHeadless(
        size.width, size.height, egl ? sgfx::Viewer::Headless::Egl : sgfx::Viewer::Headless::Default);
    viewer->setSceneData(app.scene());
    auto& cam = *viewer->camera();
    cam.clearColor = sgfxcluster::Application::skyColor();
    cam.projectionMatrix = frustum.projection();
    cam.setViewport(0, 0, size.width, size.height);
    return viewer;
}

// One frame of this rank: the packet's changes and eye, the same update as every rank, drawn.
void drawFrame(sgfx::Viewer& viewer, sgfxcluster::Application& app, const sgfxcluster::FramePacket& p,
               const sgfx::DisplayChannel* channel) {
    app.apply(p);
    viewer.camera()->viewMatrix = channel ? channel->viewMatrix(p.eyeView) : p.eyeView;
    viewer.update(p.dt);
    viewer.renderFrame();
    glFinish(); // drawn, not just queued, before the frame lock
}

int runReference(const Options& o, const sgfx::DisplayConfig& config) {
    if (!config.overall)
        throw std::invalid_argument(o.config + ": layout '" + config.layout +
                                    "' has no overall frustum (walls only): --reference needs one");
    sgfxcluster::Application app(o.app);
    const sgfx::Viewport size = scaled(config.composite, o.scale, "composite");
    auto viewer = makeViewer(app, size, depthRange(*config.overall, o), o.egl);
    auto start = Clock::now();
    for (int f = 0; f < o.frames; ++f) {
        if (f == 1) start = Clock::now(); // frame 0 compiles the shaders
        drawFrame(*viewer, app, app.step(std::uint64_t(f), o.dt), nullptr);
    }
    if (o.stats)
        std::printf("reference: size=%dx%d frames=%d frame_ms=%.2f\n", size.width, size.height, o.frames,
                    1e3 * std::chrono::duration<double>(Clock::now() - start).count() /
                        std::max(o.frames - 1, 1));
    if (!o.out.empty()) viewer->writeScreenshot(o.out);
    return 0;
}

// The channels' images (rank order = channel order) placed by viewport; gaps (bezels) stay
// transparent black, so a comparison can leave them out.
sgfx::Image composite(const std::vector<sgfx::Image>& images, const std::vector<sgfx::Viewport>& viewports,
                      const sgfx::Viewport& size) {
    sgfx::Image out;
    out.width = size.width;
    out.height = size.height;
    out.pixels.assign(std::size_t(size.width) * std::size_t(size.height) * 4, 0);
    for (std::size_t i = 0; i < images.size(); ++i) {
        const sgfx::Image& im = images[i];
        const sgfx::Viewport& v = viewports[i];
        for (int y = 0; y < im.height; ++y) // rows top to bottom; viewports from the bottom
            std::copy_n(im.pixel(0, y), std::size_t(im.width) * 4,
                        out.pixel(v.x, size.height - (v.y + v.height) + y));
    }
    return out;
}

struct Figures {
    double frameSeconds = 0.0, barrierSeconds = 0.0, gatherSeconds = 0.0;
    // Every rank's total frame-lock wait: the least is the slowest rank's, about the messaging alone.
    std::vector<double> barrierByRank;
    std::size_t packetBytes = 0;
    int measured = 0;
};

// Says when it fires (wall-clock seconds), so a test can time the run's end from the failure.
void testHooks(const Options& o, int rank, int frame) {
    const bool kill = rank == o.killRank && frame == o.killFrame;
    const bool stall = rank == o.stallRank && frame == o.stallFrame;
    if (!kill && !stall) return;
    const double now =
        std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
    std::fprintf(stderr, "sgfx-cluster: test hook: rank %d %s at frame %d, t=%.3f\n", rank,
                 kill ? "kills itself" : "stalls", frame, now);
    std::fflush(stderr);
    if (kill) std::raise(SIGKILL);
    std::this_thread::sleep_for(std::chrono::hours(1));
}

void printFigures(const Options& o, const sgfxcluster::ClusterSync& sync, const Figures& f,
                  const sgfx::Viewport& channel) {
    const double n = std::max(f.measured, 1);
    const auto [least, most] = std::minmax_element(f.barrierByRank.begin(), f.barrierByRank.end());
    std::printf(
        "cluster: ranks=%d channel=%dx%d frames=%d frame_ms=%.2f barrier_ms=%.3f barrier_least_ms=%.3f "
        "barrier_most_ms=%.3f packet_bytes=%.1f gather_ms=%.2f\n",
        sync.size(), channel.width, channel.height, o.frames, 1e3 * f.frameSeconds / n,
        1e3 * f.barrierSeconds / n, 1e3 * *least / n, 1e3 * *most / n, double(f.packetBytes) / n,
        1e3 * f.gatherSeconds);
}

int runCluster(const Options& o, sgfx::DisplayConfig config, sgfxcluster::ClusterSync& sync) {
    if (o.channels > 0 && std::size_t(o.channels) < config.channels.size())
        config.channels.resize(std::size_t(o.channels));
    const int channels = int(config.channels.size());
    if (sync.size() != channels) {
        if (sync.rank() == 0)
            std::fprintf(
                stderr,
                "sgfx-cluster: %s has %d channels but the run has %d ranks: start one rank per channel "
                "(mpirun -np %d)\n",
                o.config.c_str(), channels, sync.size(), channels);
        return 2;
    }
    sync.setTimeout(o.timeout);
    std::vector<sgfx::Viewport> viewports;
    for (const sgfx::DisplayChannel& c : config.channels)
        viewports.push_back(scaled(c.viewport, o.scale, "channel '" + c.name + "' viewport"));
    const sgfx::DisplayChannel& mine = config.channels[std::size_t(sync.rank())];
    sgfxcluster::Application app(o.app);
    auto viewer = makeViewer(app, viewports[std::size_t(sync.rank())], depthRange(mine.frustum, o), o.egl);
    Figures fig;
    for (int f = 0; f < o.frames; ++f) {
        const auto start = Clock::now();
        std::vector<std::byte> bytes;
        if (sync.rank() == 0) bytes = app.step(std::uint64_t(f), o.dt).serialize();
        sync.broadcast(bytes, std::uint64_t(f), o.firstFrameTimeout);
        const sgfxcluster::FramePacket packet = sgfxcluster::FramePacket::deserialize(bytes);
        testHooks(o, sync.rank(), f);
        if (o.syncOnly)
            app.apply(packet);
        else
            drawFrame(*viewer, app, packet, &mine);
        const double wait = sync.frameBarrier(std::uint64_t(f), f == 0 ? o.firstFrameTimeout : o.timeout);
        if (f > 0 || o.frames == 1) { // frame 0 compiles the shaders
            fig.frameSeconds += std::chrono::duration<double>(Clock::now() - start).count();
            fig.barrierSeconds += wait;
            fig.packetBytes += bytes.size();
            ++fig.measured;
        }
    }
    const auto gatherStart = Clock::now();
    const std::vector<sgfx::Image> images = sync.gather(viewer->capture());
    fig.gatherSeconds = std::chrono::duration<double>(Clock::now() - gatherStart).count();
    fig.barrierByRank = sync.gather(fig.barrierSeconds);
    if (sync.rank() != 0) return 0;
    if (o.stats) printFigures(o, sync, fig, viewports[0]);
    if (!o.out.empty())
        sgfx::writePng(o.out, composite(images, viewports, scaled(config.composite, o.scale, "composite")));
    return 0;
}

} // namespace

int main(int argc, char** argv) {
    CLI::App cli{"sgfx-cluster: the proving ground on a multi-channel display, one MPI rank per channel",
                 "sgfx-cluster"};
    Options o;
    parse(cli, o);
    if (const int status = demo::parse(cli, argc, argv); status >= 0) return status; // 2: bad options
    try {
        const sgfx::DisplayConfig config = sgfx::DisplayConfig::load(o.config);
        if (o.reference) return runReference(o, config);
        sgfxcluster::ClusterSync sync(argc, argv);
        try {
            return runCluster(o, config, sync);
        } catch (const std::exception& e) {
            sync.fail(e.what(), 1); // one rank's error stops them all (never a hang in a wait)
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "sgfx-cluster: %s\n", e.what());
        return 1;
    }
}

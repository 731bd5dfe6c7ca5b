// Gaussian splats sorted and drawn per second (headless): a generated cloud of N splats filling
// the view, FRAMES frames with the GPU radix sort and with the CPU sort; the sort alone is timed
// too. One SPLATS line per sort mode (bench/splat_table.sh). `--write FILE.ply` writes the cloud
// as a 3D Gaussian splatting PLY and exits (the generator for demos: no sample file ships).
#include <sgfx/Viewer.h>
#include <sgfx/nodes/splat/GaussianSplatNode.h>

#include <sgfx_glad/gl.h>

#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

namespace {

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[v.size() / 2];
}

double millisecondsOf(const std::function<void()>& f) {
    const auto t0 = std::chrono::steady_clock::now();
    f();
    glFinish(); // the GPU's work counts: wait for it
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

} // namespace

int main(int argc, char** argv) {
    CLI::App app{"Gaussian splats sorted and drawn per second"};
    std::size_t count = 100000;
    int frames = 5, degree = 1;
    std::string size = "320x240", write, sorts = "gpu,cpu";
    app.add_option("--count", count, "splats")->check(CLI::Range(std::size_t(1), std::size_t(1) << 26));
    app.add_option("--frames", frames, "frames timed per sort mode")->check(CLI::Range(1, 10000));
    app.add_option("--degree", degree, "SH degree")->check(CLI::Range(0, 3));
    app.add_option("--size", size, "WIDTHxHEIGHT");
    app.add_option("--sorts", sorts, "sort modes, comma-separated: gpu, cpu");
    app.add_option("--write", write, "write the generated cloud as a splat PLY and exit");
    CLI11_PARSE(app, argc, argv);
    int w = 0, h = 0;
    if (std::sscanf(size.c_str(), "%dx%d", &w, &h) != 2 || w < 1 || h < 1 || w > 8192 || h > 8192) {
        std::fprintf(stderr, "--size: '%s' is not WIDTHxHEIGHT\n", size.c_str());
        return 2;
    }
    sgfx::SplatCloud cloud = sgfx::SplatCloud::random(count, 1, 1.0f, 0.6f / std::cbrt(float(count)), degree);
    if (!write.empty()) {
        sgfx::splat::savePly(cloud, write);
        std::printf("wrote %s: %zu splats, SH degree %d\n", write.c_str(), count, degree);
        return 0;
    }
    auto viewer = sgfx::Viewer::createHeadless(w, h);
    auto node = sgfx::GaussianSplatNode::create(std::move(cloud));
    viewer->setSceneData(node);
    auto& cam = *viewer->camera();
    cam.setLookAt({0, -3.2f, 0.4f}, {0, 0, 0}, {0, 0, 1});
    for (const std::string mode : {"gpu", "cpu"}) {
        if (sorts.find(mode) == std::string::npos) continue;
        node->setSort(mode == "gpu" ? sgfx::SplatSort::Gpu : sgfx::SplatSort::Cpu);
        viewer->frame(); // compiles programs and buffers
        std::vector<double> frame, sort;
        for (int f = 0; f < frames; ++f) {
            cam.setLookAt({3.2f * std::sin(0.1f * float(f)), -3.2f * std::cos(0.1f * float(f)), 0.4f},
                          {0, 0, 0}, {0, 0, 1});
            frame.push_back(millisecondsOf([&] { viewer->frame(); }));
            sort.push_back(millisecondsOf([&] { node->sortFor(viewer->renderer(), cam.viewMatrix); }));
        }
        const double ms = median(frame), sortMs = median(sort);
        std::printf("SPLATS count=%zu sort=%s size=%dx%d degree=%d ms_per_frame=%.2f sort_ms=%.2f "
                    "splats_per_s=%.0f sorted_per_s=%.0f\n",
                    count, mode.c_str(), w, h, degree, ms, sortMs, double(count) / ms * 1e3,
                    double(count) / sortMs * 1e3);
    }
    return 0;
}

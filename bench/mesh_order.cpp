// What GltfOptions::optimizeOrder (meshoptimizer's vertex-cache, overdraw and fetch order) does to
// the frame of a loaded model: `mesh_order FILE [--size WxH] [--rounds N] [--auto-lod] [--png PREFIX]`;
// with --auto-lod, what GltfOptions::autoLod adds to it; --png writes the last view of each
// (PREFIX_plain.png, PREFIX_ordered.png) to compare. The model is loaded twice, with and without, and drawn
// from three fixed views in interleaved rounds (A B, B A, ...), so the machine's drift falls on both; the
// median of the per-round ratios is printed with the medians of each. Source bench/common.sh first (malloc
// pin).
#include <sgfx/Camera.h>
#include <sgfx/MeshOptimize.h>
#include <sgfx/ModelLoader.h>
#include <sgfx/Viewer.h>

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace {

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[v.size() / 2];
}

// Milliseconds for one frame of each of three views around the model's bound, summed.
double frameMs(sgfx::Viewer& viewer, const sgfx::NodePtr& model) {
    viewer.setSceneData(model);
    const sgfx::BoundingSphere b = model->bound();
    const float r = std::max(b.radius, 1e-3f);
    double ms = 0.0;
    for (float yaw : {30.0f, 150.0f, 270.0f}) {
        const float a = glm::radians(yaw);
        const glm::vec3 eye = b.center + 1.5f * r * glm::vec3(std::cos(a), std::sin(a), 0.35f);
        viewer.camera()->setLookAt(eye, b.center, {0, 0, 1});
        const auto start = std::chrono::steady_clock::now();
        viewer.frame();
        ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    }
    return ms;
}

} // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr,
                     "usage: mesh_order FILE [--size WxH] [--rounds N] [--auto-lod] [--png PREFIX]\n");
        return 2;
    }
    int width = 1280, height = 720, rounds = 7;
    bool autoLod = false;
    std::string png;
    for (int i = 2; i < argc; ++i) {
        const std::string arg = argv[i];
        const char* value = i + 1 < argc ? argv[i + 1] : "";
        if (arg == "--auto-lod") {
            autoLod = true;
        } else if (arg == "--size" && std::sscanf(value, "%dx%d", &width, &height) == 2 && width > 0 &&
                   height > 0) {
            ++i;
        } else if (arg == "--rounds" && (rounds = std::atoi(value)) > 0) {
            ++i;
        } else if (arg == "--png" && *value) {
            png = argv[++i];
        } else {
            std::fprintf(stderr, "mesh_order: bad option '%s'\n", arg.c_str());
            return 2;
        }
    }
    sgfx::GltfOptions off, on;
    off.optimizeOrder = !autoLod; // --auto-lod: both ordered, one with LODs
    on.optimizeOrder = true;
    on.autoLod.enabled = autoLod;
    const auto start = std::chrono::steady_clock::now();
    const sgfx::NodePtr plain = sgfx::loadModel(argv[1], off);
    const auto mid = std::chrono::steady_clock::now();
    const sgfx::NodePtr ordered = sgfx::loadModel(argv[1], on);
    const auto end = std::chrono::steady_clock::now();
    auto viewer = sgfx::Viewer::createHeadless(width, height);
    const sgfx::BoundingSphere b = plain->bound();
    viewer->camera()->projectionMatrix = glm::perspective(glm::radians(45.0f), float(width) / float(height),
                                                          0.01f * b.radius, 10.0f * b.radius);
    frameMs(*viewer, plain); // warm: programs, buffers
    if (!png.empty()) viewer->writeScreenshot(png + "_plain.png");
    frameMs(*viewer, ordered);
    if (!png.empty()) viewer->writeScreenshot(png + "_ordered.png");
    std::vector<double> a, o, ratio;
    for (int k = 0; k < rounds; ++k) {
        const bool plainFirst = k % 2 == 0;
        const double first = frameMs(*viewer, plainFirst ? plain : ordered);
        const double second = frameMs(*viewer, plainFirst ? ordered : plain);
        a.push_back(plainFirst ? first : second);
        o.push_back(plainFirst ? second : first);
        ratio.push_back(o.back() / a.back());
    }
    std::printf(
        "MESH_ORDER file=%s size=%dx%d rounds=%d meshoptimizer=%d load_ms_plain=%.1f load_ms_ordered=%.1f "
        "frame_ms_plain=%.2f frame_ms_ordered=%.2f ratio_median=%.3f ratio_min=%.3f ratio_max=%.3f\n",
        argv[1], width, height, rounds, int(sgfx::meshOptimizerAvailable()),
        std::chrono::duration<double, std::milli>(mid - start).count(),
        std::chrono::duration<double, std::milli>(end - mid).count(), median(a) / 3.0, median(o) / 3.0,
        median(ratio), *std::min_element(ratio.begin(), ratio.end()),
        *std::max_element(ratio.begin(), ratio.end()));
    return 0;
}

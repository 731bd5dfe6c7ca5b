// A crowd of skinned glTF figures (issue 26's measurement): N copies of a model (RiggedFigure by
// default), each loaded on its own so each has its own pose, on a square grid, each player seeked
// to a different time, rendered headless (OSMesa/llvmpipe) at WxH with glFinish after each frame.
// Prints one CROWD line: median ms/frame and median Viewer::update ms with the players running,
// the same with the players paused (what the pose costs is the difference), update µs per joint
// per frame, and the players' sampling throughput (AnimationPlayer::update alone, channels/ms).
//   skinned_crowd MODEL [--count N] [--size WxH] [--frames N] [--warmup N]
#include <sgfx/Animation.h>
#include <sgfx/Camera.h>
#include <sgfx/FindNode.h>
#include <sgfx/Geometry.h>
#include <sgfx/GltfLoader.h>
#include <sgfx/Group.h>
#include <sgfx/Viewer.h>
#include <sgfx/Visitors.h>

#include <sgfx_glad/gl.h>

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

namespace {

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n == 0 ? 0.0 : n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

struct Options {
    std::string model;
    int count = 100, width = 1280, height = 720, frames = 60, warmup = 5;
};

[[noreturn]] void usage(const std::string& why) {
    std::fprintf(stderr,
                 "skinned_crowd: %s\nusage: skinned_crowd MODEL [--count N] [--size WxH] [--frames N] "
                 "[--warmup N]\n",
                 why.c_str());
    std::exit(2);
}

Options parse(int argc, char** argv) {
    Options o;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto next = [&]() -> std::string {
            if (i + 1 >= argc) usage(a + ": needs a value");
            return argv[++i];
        };
        if (a == "--count")
            o.count = std::atoi(next().c_str());
        else if (a == "--frames")
            o.frames = std::atoi(next().c_str());
        else if (a == "--warmup")
            o.warmup = std::atoi(next().c_str());
        else if (a == "--size") {
            const std::string s = next();
            if (std::sscanf(s.c_str(), "%dx%d", &o.width, &o.height) != 2) usage("--size: expected WxH");
        } else if (a.rfind("--", 0) == 0)
            usage("unknown option " + a);
        else
            o.model = a;
    }
    if (o.model.empty()) usage("no model");
    if (o.count < 1 || o.frames < 1 || o.warmup < 0 || o.width < 1 || o.height < 1) usage("bad value");
    return o;
}

struct Crowd {
    std::shared_ptr<sgfx::Group> scene = sgfx::Group::create();
    std::vector<sgfx::AnimationPlayer*> players;
    std::size_t joints = 0, channels = 0, triangles = 0;
};

Crowd build(const Options& o) {
    Crowd c;
    const int side = int(std::ceil(std::sqrt(double(o.count))));
    float spacing = 0.0f;
    for (int i = 0; i < o.count; ++i) {
        sgfx::GltfStats st;
        const auto model = sgfx::loadGltf(o.model, {}, &st); // its own load: its own pose
        c.triangles += st.triangles;
        if (spacing == 0.0f) spacing = 1.5f * 2.0f * model->bound().radius;
        auto* player = sgfx::animationPlayer(*model);
        if (!player) usage(o.model + " has no animation");
        player->seek(0.37 * i); // a different phase each (wrapped into the animation)
        c.players.push_back(player);
        for (const auto& a : player->animations)
            c.channels += a.channels.size();
        for (const auto& n : sgfx::findNodesIf(*model, [](sgfx::Node& x) {
                 auto* g = dynamic_cast<sgfx::Geometry*>(&x);
                 return g && g->skin;
             }))
            c.joints += std::static_pointer_cast<sgfx::Geometry>(n)->skin->joints.size();
        auto place = sgfx::Transform::create(glm::translate(
            glm::mat4(1.0f), glm::vec3(float(i % side) * spacing, 0.0f, float(i / side) * spacing)));
        place->addChild(model);
        c.scene->addChild(place);
    }
    return c;
}

// Median frame and update ms over `frames` frames after `warmup`.
std::pair<double, double> run(sgfx::Viewer& v, const Options& o) {
    std::vector<double> frame, update;
    for (int f = 0; f < o.warmup + o.frames; ++f) {
        const auto t0 = Clock::now();
        v.update(1.0 / 60.0);
        const double u = msSince(t0);
        v.renderFrame();
        glFinish();
        if (f >= o.warmup) {
            frame.push_back(msSince(t0));
            update.push_back(u);
        }
    }
    return {median(frame), median(update)};
}

} // namespace

int main(int argc, char** argv) {
    const Options o = parse(argc, argv);
    try {
        Crowd crowd = build(o);
        auto viewer = sgfx::Viewer::createHeadless(o.width, o.height);
        viewer->setSceneData(crowd.scene);
        sgfx::ComputeBoundsVisitor bounds;
        crowd.scene->accept(bounds);
        const glm::vec3 centre = 0.5f * (bounds.min + bounds.max);
        const float radius = 0.5f * glm::length(bounds.max - bounds.min);
        auto& cam = *viewer->camera();
        cam.setPerspective(45.0f, radius * 0.05f, radius * 10.0f);
        cam.setLookAt(centre + glm::vec3(0.0f, radius * 1.2f, radius * 2.0f), centre, {0, 1, 0});
        const auto [playMs, playUpdate] = run(*viewer, o);
        for (auto* p : crowd.players)
            p->pause();
        const auto [pausedMs, pausedUpdate] = run(*viewer, o);
        // Sampling alone: every player updated at 200 simulation times (resumed).
        for (auto* p : crowd.players)
            p->resume();
        const int steps = 200;
        const auto t0 = Clock::now();
        for (int s = 0; s < steps; ++s)
            for (auto* p : crowd.players)
                p->update(100.0 + s / 60.0);
        const double samplingMs = msSince(t0);
        const double perJointUs = 1000.0 * playUpdate / double(std::max<std::size_t>(crowd.joints, 1));
        const double poseUs =
            1000.0 * (playUpdate - pausedUpdate) / double(std::max<std::size_t>(crowd.joints, 1));
        std::printf("GL_RENDERER: %s\n", reinterpret_cast<const char*>(glGetString(GL_RENDERER)));
        std::printf("CROWD model=%s count=%d size=%dx%d frames=%d triangles=%zu joints=%zu channels=%zu "
                    "ms_per_frame=%.3f update_ms=%.4f paused_ms_per_frame=%.3f paused_update_ms=%.4f "
                    "update_us_per_joint=%.4f pose_us_per_joint=%.4f sampling_channels_per_ms=%.1f\n",
                    o.model.c_str(), o.count, o.width, o.height, o.frames, crowd.triangles, crowd.joints,
                    crowd.channels, playMs, playUpdate, pausedMs, pausedUpdate, perJointUs, poseUs,
                    double(crowd.channels) * steps / samplingMs);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "skinned_crowd: %s\n", e.what());
        return 1;
    }
    return 0;
}

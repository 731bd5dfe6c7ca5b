// Particle showcase and benchmark.
//
//   particles [--preset all|rain|snow|leaves|smoke|jet|sparks|cloud] [--count N]
//             [--path gs|instanced|pulled|points] [--layout interleaved|split]
//             [--update auto|tf|compute] [--size WxH] [--out FILE] [--bench N] [--egl]
//
// Without --bench: simulates two seconds at 30 Hz and writes a PNG of the preset(s) over a
// ground plane in fog. With --bench N: the "cloud" scene (sprites, the OSG peer's scene in
// bench/osg_particles.cpp) is stepped and drawn N frames after warm-up, and one line reports
// the median ms per frame and the GPU ms of the simulation and of the drawing:
//   PARTICLES count=... path=... layout=... frame_ms=... sim_ms=... update_ms=... draw_ms=...
//             update=tf|compute [auto_tf_ms=... auto_compute_ms=...]
// (update: the simulation path the steps ran on, --update's or Auto's pick, whose timings follow)
// (sim_ms: the simulation step alone, CPU-timed with glFinish; update_ms and draw_ms: GPU timer
// queries, which llvmpipe fills unreliably)
#include "CliParse.h"

#include <sgfx/GraphicsContext.h>
#include <sgfx/Group.h>
#include <sgfx/PassCommands.h>
#include <sgfx/Shapes.h>
#include <sgfx/Viewer.h>
#include <sgfx/nodes/fog/FogNode.h>
#include <sgfx/nodes/particles/ParticleSystemNode.h>

#include <glm/gtc/matrix_transform.hpp>
#include <sgfx_glad/gl.h>

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

struct Options {
    std::string preset = "all";
    std::uint32_t count = 0; // 0: the preset's own
    sgfx::ParticlePath path = sgfx::ParticlePath::Auto;
    sgfx::ParticleLayout layout = sgfx::ParticleLayout::Interleaved;
    sgfx::ParticleUpdate update = sgfx::ParticleUpdate::Auto;
    int width = 640, height = 360;
    std::string out = "particles.png";
    int bench = 0;
    bool egl = false;
};

using demo::choice;

void addSceneOptions(CLI::App& cli, Options& o) {
    cli.add_option("--preset", o.preset, "the preset(s) drawn (default all)")
        ->check(CLI::IsMember({"all", "rain", "snow", "leaves", "smoke", "jet", "sparks", "cloud"}))
        ->type_name("all|rain|snow|leaves|smoke|jet|sparks|cloud");
    cli.add_option_function<std::string>(
           "--count",
           [&o](const std::string& v) {
               o.count =
                   demo::integer<std::uint32_t>("--count", v, 0, std::numeric_limits<std::uint32_t>::max());
           },
           "particles (default 0: the preset's own)")
        ->type_name("N");
    demo::addSize(cli, o.width, o.height, 1, 8192, "image size (default 640x360)");
    cli.add_option("--out", o.out, "PNG to write (default particles.png)")->type_name("FILE");
    cli.add_option("--bench", o.bench,
                   "step and draw the cloud scene N frames after warm-up; print a PARTICLES line")
        ->check(CLI::Range(1, std::numeric_limits<int>::max()))
        ->type_name("N");
    cli.add_flag("--egl", o.egl, "render headless through EGL (GPU) instead of OSMesa");
}

void addPathOptions(CLI::App& cli, Options& o) {
    cli.add_option_function<std::string>(
           "--path",
           [&o](const std::string& v) {
               o.path = choice<sgfx::ParticlePath>("--path", v,
                                                   {{"gs", sgfx::ParticlePath::GeometryShader},
                                                    {"instanced", sgfx::ParticlePath::Instanced},
                                                    {"pulled", sgfx::ParticlePath::Pulled},
                                                    {"points", sgfx::ParticlePath::PointSprite}},
                                                   "gs, instanced, pulled or points");
           },
           "how the particles are drawn (default: the node's pick)")
        ->type_name("gs|instanced|pulled|points");
    cli.add_option_function<std::string>(
           "--layout",
           [&o](const std::string& v) {
               o.layout = choice<sgfx::ParticleLayout>("--layout", v,
                                                       {{"interleaved", sgfx::ParticleLayout::Interleaved},
                                                        {"split", sgfx::ParticleLayout::Split}},
                                                       "interleaved or split");
           },
           "the particle buffer's layout (default interleaved)")
        ->type_name("interleaved|split");
    cli.add_option_function<std::string>(
           "--update",
           [&o](const std::string& v) {
               o.update = choice<sgfx::ParticleUpdate>("--update", v,
                                                       {{"auto", sgfx::ParticleUpdate::Auto},
                                                        {"tf", sgfx::ParticleUpdate::TransformFeedback},
                                                        {"compute", sgfx::ParticleUpdate::Compute}},
                                                       "auto, tf or compute");
           },
           "the simulation's path: transform feedback, compute, or Auto's pick (default)")
        ->type_name("auto|tf|compute");
}

// The benchmark's cloud: 40 × 40 m of sprites shot upwards, one second of life (OSG peer: same).
std::shared_ptr<sgfx::ParticleSystemNode> cloud(std::uint32_t n) {
    sgfx::ParticleSettings s;
    s.capacity = n;
    s.emitter.size = {40.0f, 40.0f};
    s.emitter.velocity = {0.0f, 0.0f, 5.0f};
    s.emitter.velocitySpread = 1.0f;
    s.emitter.acceleration = {0.0f, 0.0f, -2.0f};
    s.emitter.lifetime = 1.0f;
    s.sizeStart = s.sizeEnd = 0.1f;
    s.colorStart = s.colorEnd = {1.0f, 0.9f, 0.7f, 0.8f};
    auto node = sgfx::ParticleSystemNode::create(s);
    node->name = "cloud";
    auto st = sgfx::ParticleSystemNode::defaultState();
    auto& m = **st->material.value;
    m.ambient = glm::vec3(0.0f);
    m.diffuse = glm::vec4(0.0f, 0.0f, 0.0f, 1.0f);
    m.emissive = glm::vec3(1.0f);
    st->blend.set(sgfx::BlendMode::Alpha);
    node->setStateSet(st);
    return node;
}

std::shared_ptr<sgfx::ParticleSystemNode> preset(const std::string& name, std::uint32_t n) {
    using P = sgfx::ParticleSystemNode;
    if (name == "rain") return n ? P::rain({40, 40}, n) : P::rain({40, 40});
    if (name == "snow") return n ? P::snow({40, 40}, n) : P::snow({40, 40});
    if (name == "leaves") return n ? P::leaves({20, 20}, n) : P::leaves();
    if (name == "smoke") return n ? P::smoke(1.0f, n) : P::smoke();
    if (name == "jet") return n ? P::waterJet({0.0f, 0.4f, 1.0f}, 12.0f, n) : P::waterJet();
    if (name == "sparks") return n ? P::sparks(n) : P::sparks();
    if (name == "cloud") return cloud(n ? n : 100000);
    throw std::invalid_argument("--preset: '" + name + "' is not a preset"); // --preset's check keeps it out
}

} // namespace

int main(int argc, char** argv) try {
    Options o;
    CLI::App cli{"particles: the particle presets over a ground plane in fog (a PNG), or with --bench the "
                 "particle benchmark's sgfx side (see the header of demos/particles/main.cpp)",
                 "particles"};
    demo::lastValueWins(cli);
    addSceneOptions(cli, o);
    addPathOptions(cli, o);
    if (const int status = demo::parse(cli, argc, argv); status >= 0) return status;
    auto viewer = sgfx::Viewer::createHeadless(
        o.width, o.height, o.egl ? sgfx::Viewer::Headless::Egl : sgfx::Viewer::Headless::Default);
    auto& cam = *viewer->camera();
    cam.clearColor = {0.42f, 0.60f, 0.85f, 1.0f};
    cam.setPerspective(50.0f, 0.5f, 500.0f);
    auto scene = sgfx::Group::create();
    auto sun = sgfx::Light::create();
    sun->direction = glm::normalize(glm::vec3(-0.4f, 0.5f, -1.0f));
    sun->color = glm::vec3(1.6f);
    auto sky = sgfx::Light::create(sgfx::LightType::Ambient);
    sky->color = glm::vec3(0.35f, 0.4f, 0.5f);
    scene->addChild(sun);
    scene->addChild(sky);
    std::vector<std::shared_ptr<sgfx::ParticleSystemNode>> systems;
    auto place = [&](std::shared_ptr<sgfx::ParticleSystemNode> p, glm::vec3 at) {
        p->getOrCreateStateSet();
        sgfx::ParticleSettings s = p->settings();
        s.path = o.path;
        s.layout = o.layout;
        s.update = o.update;
        p->setSettings(s);
        auto t = sgfx::Transform::create(glm::translate(glm::mat4(1.0f), at));
        t->addChild(p);
        scene->addChild(t);
        systems.push_back(p);
    };

    if (o.bench) {
        cam.setLookAt({0, -60, 20}, {0, 0, 8}, {0, 0, 1});
        place(cloud(o.count ? o.count : 100000), {0, 0, 0});
        viewer->setSceneData(scene);
        viewer->renderer().options().timePasses = true;
        for (int i = 0; i < 5; ++i)
            viewer->frame(1.0 / 30.0);
        std::vector<double> frame, update, draw;
        for (int i = 0; i < o.bench; ++i) {
            const auto t0 = std::chrono::steady_clock::now();
            viewer->frame(1.0 / 30.0);
            glFinish();
            frame.push_back(
                std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
            double u = 0, d = 0;
            for (const auto& pt : viewer->stats().passTimes)
                (pt.name.starts_with("particles") ? u : d) +=
                    pt.name.starts_with("main") || pt.name.starts_with("particles") ? pt.gpuMs : 0.0;
            update.push_back(u);
            draw.push_back(d);
        }
        auto med = [](std::vector<double> v) {
            std::sort(v.begin(), v.end());
            return v[v.size() / 2];
        };
        // The simulation alone, timed on the CPU with glFinish (llvmpipe's timer queries do not
        // see transform feedback work reliably): one step of 1/30 s at a time.
        std::vector<double> sim;
        for (int i = 0; i < std::max(3, o.bench); ++i) {
            systems[0]->queueStep(1.0f / 30.0f);
            glFinish();
            const auto t0 = std::chrono::steady_clock::now();
            viewer->renderer().runCommands("particles: simulate",
                                           [&](sgfx::PassCommands& c) { systems[0]->simulate(c); });
            glFinish();
            sim.push_back(
                std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
        }
        std::printf("GL_RENDERER: %s\n", viewer->context().renderer().c_str());
        std::printf(
            "PARTICLES count=%u path=%s layout=%s size=%dx%d frame_ms=%.2f sim_ms=%.2f update_ms=%.2f "
            "draw_ms=%.2f",
            systems[0]->settings().capacity,
            systems[0]->resolvedPath() == sgfx::ParticlePath::GeometryShader ? "gs"
            : systems[0]->resolvedPath() == sgfx::ParticlePath::Instanced    ? "instanced"
            : systems[0]->resolvedPath() == sgfx::ParticlePath::Pulled       ? "pulled"
                                                                             : "points",
            o.layout == sgfx::ParticleLayout::Split ? "split" : "interleaved", o.width, o.height, med(frame),
            med(sim), med(update), med(draw));
        const sgfx::ParticleFrameInfo& info = systems[0]->lastFrame();
        std::printf(" update=%s", info.update == sgfx::ParticleUpdate::Compute ? "compute" : "tf");
        if (info.measured)
            std::printf(" auto_tf_ms=%.2f auto_compute_ms=%.2f", info.transformFeedbackMs, info.computeMs);
        std::printf("\n");
        return 0;
    }

    // Showcase: a ground plane in light fog with the presets side by side.
    auto ground = sgfx::shapes::quad(200.0f, 200.0f);
    auto grass = sgfx::Material::create();
    grass->diffuse = glm::vec4(0.12f, 0.2f, 0.08f, 1.0f);
    ground->getOrCreateStateSet().material.set(grass);
    scene->addChild(ground);
    cam.setLookAt({0, -24, 6}, {0, 0, 4}, {0, 0, 1});
    if (o.preset == "all") {
        place(preset("snow", o.count), {-16, 8, 30});
        place(preset("rain", o.count), {16, 8, 36});
        place(preset("leaves", o.count), {0, -8, 10});
        place(preset("smoke", o.count), {-6, 4, 0});
        place(preset("jet", o.count), {3, -2, 0});
        place(preset("sparks", o.count), {8, -6, 0.5f});
    } else {
        place(preset(o.preset, o.count), o.preset == "rain"     ? glm::vec3(0, 8, 36)
                                         : o.preset == "snow"   ? glm::vec3(0, 8, 30)
                                         : o.preset == "leaves" ? glm::vec3(0, 0, 14)
                                                                : glm::vec3(0, 0, 0));
    }
    sgfx::FogParameters fp = sgfx::FogParameters::ground();
    auto fog = sgfx::FogNode::create(fp);
    fog->addChild(scene);
    viewer->setSceneData(fog);
    for (int i = 0; i < 60; ++i)
        viewer->frame(1.0 / 30.0);
    viewer->writeScreenshot(o.out);
    for (const std::string& e : viewer->renderer().takeGlErrors())
        std::cerr << "particles: GL: " << e << "\n";
    std::cout << "wrote " << o.out << " (" << o.width << "x" << o.height << ", " << viewer->stats().triangles
              << " triangles)\n";
    return 0;
} catch (const std::exception& e) {
    std::cerr << "particles: " << e.what() << "\n";
    return 1;
}

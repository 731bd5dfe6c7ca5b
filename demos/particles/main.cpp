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

[[noreturn]] void usage(const std::string& why) {
    std::cerr << "particles: " << why << "\n(see the header of demos/particles/main.cpp for the options)\n";
    std::exit(2);
}

template <class T> T number(const std::string& opt, std::string_view s) {
    T v{};
    auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (s.empty() || ec != std::errc() || p != s.data() + s.size())
        usage(opt + ": '" + std::string(s) + "' is not a number");
    return v;
}

Options parse(int argc, char** argv) {
    Options o;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto value = [&]() -> std::string {
            if (i + 1 >= argc) usage(a + " needs a value");
            return argv[++i];
        };
        if (a == "--preset") {
            o.preset = value();
        } else if (a == "--count") {
            o.count = number<std::uint32_t>(a, value());
        } else if (a == "--path") {
            const std::string v = value();
            if (v != "gs" && v != "instanced" && v != "pulled" && v != "points")
                usage("--path: '" + v + "' is not gs, instanced, pulled or points");
            o.path = v == "gs"          ? sgfx::ParticlePath::GeometryShader
                     : v == "instanced" ? sgfx::ParticlePath::Instanced
                     : v == "pulled"    ? sgfx::ParticlePath::Pulled
                                        : sgfx::ParticlePath::PointSprite;
        } else if (a == "--layout") {
            const std::string v = value();
            if (v != "interleaved" && v != "split")
                usage("--layout: '" + v + "' is not interleaved or split");
            o.layout = v == "split" ? sgfx::ParticleLayout::Split : sgfx::ParticleLayout::Interleaved;
        } else if (a == "--update") {
            const std::string v = value();
            if (v != "auto" && v != "tf" && v != "compute")
                usage("--update: '" + v + "' is not auto, tf or compute");
            o.update = v == "tf"        ? sgfx::ParticleUpdate::TransformFeedback
                       : v == "compute" ? sgfx::ParticleUpdate::Compute
                                        : sgfx::ParticleUpdate::Auto;
        } else if (a == "--size") {
            const std::string v = value();
            const auto x = v.find('x');
            if (x == std::string::npos) usage("--size: expected WxH");
            o.width = number<int>(a, std::string_view(v).substr(0, x));
            o.height = number<int>(a, std::string_view(v).substr(x + 1));
            if (o.width < 1 || o.height < 1 || o.width > 8192 || o.height > 8192)
                usage("--size: out of range");
        } else if (a == "--out") {
            o.out = value();
        } else if (a == "--bench") {
            o.bench = number<int>(a, value());
            if (o.bench < 1) usage("--bench: N must be at least 1");
        } else if (a == "--egl") {
            o.egl = true;
        } else {
            usage("unknown option '" + a + "'");
        }
    }
    return o;
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
    usage("--preset: '" + name + "' is not all, rain, snow, leaves, smoke, jet, sparks or cloud");
}

} // namespace

int main(int argc, char** argv) try {
    const Options o = parse(argc, argv);
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

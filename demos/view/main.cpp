// sgfx-view: look at a model (glTF, OBJ, OFF, PLY, STL) under the effects. Headless: renders one
// still to a PNG, optionally a row of panels comparing the effects (plain | fog | AO | both).
// The camera frames the model's bounds; a ground plane under it shows contact shadows from AO.
#include <ao/AmbientOcclusionNode.h>
#include <fog/FogNode.h>
#include <sgfx/ModelLoader.h>
#include <sgfx/Shapes.h>
#include <sgfx/Viewer.h>
#include <sgfx/Visitors.h>

#include <glm/gtc/matrix_transform.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

const char* const kUsage = R"(usage: sgfx-view [options] FILE...
Loads the files (.gltf .glb .obj .off .ply .stl) and renders them headless to a PNG.
  --out PNG          output image (default sgfx-view.png)
  --size WxH         image size per panel (default 512x384)
  --fog RHO|auto     height fog: density per metre at the model's base (auto: the model's
                     centre half hidden), falling off over the model's height
  --ao               screen-space ambient occlusion (radius a tenth of the model's size)
  --compare          four panels side by side: plain, fog, AO, fog + AO
  --yaw DEG          camera azimuth around the model (default 30)
  --pitch DEG        camera elevation (default 25)
  --crease DEG       glTF normals made for primitives without them: smooth below DEG (default flat)
  --no-ground        no ground plane under the model
  --keep-y-up        do not turn glTF's Y up into Z up
Exit status: 0 written, 1 a file failed to load or render, 2 bad options.
)";

struct UsageError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

struct Options {
    std::vector<std::string> files;
    std::string out = "sgfx-view.png";
    int width = 512, height = 384;
    std::optional<float> fog; // density; NaN = auto
    bool ao = false, compare = false, ground = true, keepYUp = false;
    float yaw = 30.0f, pitch = 25.0f, crease = 0.0f;
};

float number(const std::string& option, const std::string& text, float lo, float hi) {
    char* end = nullptr;
    const float v = std::strtof(text.c_str(), &end);
    if (text.empty() || *end || !std::isfinite(v) || v < lo || v > hi)
        throw UsageError(option + ": '" + text + "' is not a number in [" + std::to_string(lo) + ", " +
                         std::to_string(hi) + "]");
    return v;
}

Options parse(int argc, char** argv) {
    Options o;
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        auto value = [&] {
            if (i + 1 >= argc) throw UsageError(arg + " needs a value");
            return std::string(argv[++i]);
        };
        if (arg == "-h" || arg == "--help") {
            std::cout << kUsage;
            std::exit(0);
        } else if (arg == "--out") {
            o.out = value();
        } else if (arg == "--size") {
            const std::string v = value();
            const auto x = v.find('x');
            if (x == std::string::npos) throw UsageError("--size: '" + v + "' is not WxH");
            o.width = int(number("--size", v.substr(0, x), 16, 4096));
            o.height = int(number("--size", v.substr(x + 1), 16, 4096));
        } else if (arg == "--fog") {
            const std::string v = value();
            o.fog = v == "auto" ? std::nanf("") : number("--fog", v, 0.0f, 1e6f);
        } else if (arg == "--ao") {
            o.ao = true;
        } else if (arg == "--compare") {
            o.compare = true;
        } else if (arg == "--yaw") {
            o.yaw = number(arg, value(), -360.0f, 360.0f);
        } else if (arg == "--pitch") {
            o.pitch = number(arg, value(), -89.0f, 89.0f);
        } else if (arg == "--crease") {
            o.crease = number(arg, value(), 0.0f, 180.0f);
        } else if (arg == "--no-ground") {
            o.ground = false;
        } else if (arg == "--keep-y-up") {
            o.keepYUp = true;
        } else if (arg.starts_with("--")) {
            throw UsageError("unknown option " + arg);
        } else {
            o.files.push_back(arg);
        }
    }
    if (o.files.empty()) throw UsageError("no model file given");
    return o;
}

struct Framing {
    glm::vec3 centre, eye;
    float radius, distance, baseZ;
};

Framing frame(const sgfx::ComputeBoundsVisitor& b, const Options& o) {
    Framing f;
    f.centre = 0.5f * (b.min + b.max);
    f.radius = std::max(0.5f * glm::length(b.max - b.min), 1e-3f);
    f.baseZ = b.min.z;
    f.distance = f.radius / std::sin(glm::radians(20.0f)); // fits a 40° field of view
    const float yaw = glm::radians(o.yaw), pitch = glm::radians(o.pitch);
    f.eye = f.centre + f.distance * glm::vec3(std::sin(yaw) * std::cos(pitch),
                                              -std::cos(yaw) * std::cos(pitch), std::sin(pitch));
    return f;
}

// The scene for one panel: model (+ ground), lights, the chosen effects above it.
sgfx::NodePtr buildScene(const sgfx::NodePtr& model, const Framing& f, const Options& o, bool fog, bool ao) {
    auto world = sgfx::Group::create();
    world->addChild(model);
    if (o.ground) {
        auto ground = sgfx::shapes::quad(f.radius * 60.0f, f.radius * 60.0f);
        auto m = sgfx::Material::create();
        m->diffuse = {0.55f, 0.55f, 0.52f, 1.0f};
        m->ambient = glm::vec3(0.55f);
        ground->getOrCreateStateSet().material.set(m);
        auto t = sgfx::Transform::create(
            glm::translate(glm::mat4(1.0f), {f.centre.x, f.centre.y, f.baseZ - 1e-3f * f.radius}));
        t->addChild(ground);
        world->addChild(t);
    }
    sgfx::NodePtr top = world;
    if (ao) {
        sgfx::AmbientOcclusionParameters p;
        p.radius = 0.1f * f.radius;
        p.bias = 0.005f * f.radius;
        auto node = sgfx::AmbientOcclusionNode::create(p);
        node->addChild(top);
        top = node;
    }
    if (fog) {
        sgfx::FogParameters p;
        // Auto: half the light from the model's centre reaches the eye (e^(−ρ·d) = 0.5 at the base).
        p.density = std::isnan(*o.fog) ? std::log(2.0f) / f.distance : *o.fog;
        p.falloff = std::min(1.0f / f.radius, 1e3f);
        p.referenceHeight = f.baseZ;
        p.color = {0.72f, 0.76f, 0.82f};
        auto node = sgfx::FogNode::create(p);
        node->addChild(top);
        top = node;
    }
    auto root = sgfx::Group::create();
    auto sun = sgfx::Light::create(sgfx::LightType::Directional);
    sun->direction = glm::normalize(glm::vec3(-0.4f, 0.3f, -0.85f));
    sun->color = glm::vec3(0.9f);
    auto sky = sgfx::Light::create(sgfx::LightType::Ambient);
    sky->color = glm::vec3(0.35f);
    root->addChild(sun);
    root->addChild(sky);
    root->addChild(top);
    return root;
}

} // namespace

int main(int argc, char** argv) {
    Options o;
    try {
        o = parse(argc, argv);
    } catch (const UsageError& e) {
        std::fprintf(stderr, "sgfx-view: %s\n%s", e.what(), kUsage);
        return 2;
    }
    try {
        auto model = sgfx::Group::create();
        sgfx::GltfOptions gltf;
        gltf.zUp = !o.keepYUp;
        gltf.creaseAngle = glm::radians(o.crease);
        const auto start = std::chrono::steady_clock::now();
        for (const std::string& file : o.files)
            model->addChild(sgfx::loadModel(file, gltf));
        const double loadMs =
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
        sgfx::ComputeBoundsVisitor bounds;
        model->accept(bounds);
        if (!bounds.valid()) throw std::runtime_error("the files hold no geometry");
        sgfx::StatsVisitor stats;
        model->accept(stats);
        const Framing f = frame(bounds, o);

        struct Panel {
            bool fog, ao;
        };
        std::vector<Panel> panels;
        if (o.compare)
            panels = {{false, false}, {true, false}, {false, true}, {true, true}};
        else
            panels = {{o.fog.has_value(), o.ao}};
        if (o.compare && !o.fog) o.fog = std::nanf("");
        sgfx::Image out;
        out.width = o.width * int(panels.size());
        out.height = o.height;
        out.channels = 4;
        out.pixels.assign(std::size_t(out.width) * std::size_t(out.height) * 4, 0);
        auto viewer = sgfx::Viewer::createHeadless(o.width, o.height);
        auto& cam = *viewer->camera();
        cam.setPerspective(40.0f, f.distance * 0.02f, f.distance * 20.0f);
        cam.setLookAt(f.eye, f.centre, {0, 0, 1});
        cam.clearColor = {0.72f, 0.76f, 0.82f, 1.0f};
        double frameMs = 0.0;
        for (std::size_t p = 0; p < panels.size(); ++p) {
            viewer->setSceneData(buildScene(model, f, o, panels[p].fog, panels[p].ao));
            const auto t0 = std::chrono::steady_clock::now();
            viewer->frame();
            const sgfx::Image img = viewer->capture();
            frameMs =
                std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
            for (int y = 0; y < o.height; ++y)
                std::copy_n(img.pixel(0, y), std::size_t(o.width) * 4,
                            out.pixels.begin() + std::ptrdiff_t((std::size_t(y) * std::size_t(out.width) +
                                                                 p * std::size_t(o.width)) *
                                                                4));
        }
        sgfx::writePng(o.out, out);
        std::printf("wrote %s (%dx%d): %zu triangles, %zu nodes, loaded in %.0f ms, last frame %.0f ms, %u "
                    "draw calls\n",
                    o.out.c_str(), out.width, out.height, stats.triangles, stats.nodes, loadMs, frameMs,
                    unsigned(viewer->stats().drawCalls));
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "sgfx-view: %s\n", e.what());
        return 1;
    }
}

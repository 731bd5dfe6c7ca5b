// sgfx-bench: frame times of a scene (the proving ground, or a model file) along a deterministic
// camera path, at several sizes, without effects, with each effect alone and with all of them.
// Markdown on stdout, JSON with --json, a PNG bar chart with --plot, progress on stderr.
#include "CameraPath.h"
#include "CliParse.h"
#include "PolygonScene.h"

#include <sgfx/GraphicsContext.h>
#include <sgfx/ModelLoader.h>
#include <sgfx/Shapes.h>
#include <sgfx/Viewer.h>
#include <sgfx/Visitors.h>
#include <sgfx/nodes/ao/AmbientOcclusionNode.h>
#include <sgfx/nodes/environment/EnvironmentLightNode.h>
#include <sgfx/nodes/fog/FogNode.h>
#include <sgfx/nodes/particles/ParticleSystemNode.h>
#include <sgfx/nodes/sky/SkyNode.h>
#include <sgfx/nodes/transparency/TransparencyBin.h>
#include <sgfx/nodes/volume/VolumeNode.h>

#include <sgfx_glad/gl.h>

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <thread>
#include <utility>
#include <vector>

namespace {

constexpr float kExtent = 800.0f;                     // the proving ground, as in polygon
const glm::vec4 kSkyColor{0.42f, 0.60f, 0.85f, 1.0f}; // linear
constexpr float kSkyHours = 18.5f;                    // the README's sky (`polygon --sky 18.5 --smoke`)
constexpr std::uint32_t kRainCount = 200000;          // polygon's --rain-count default
constexpr float kSmokePoseTime = 0.1f;                // polygon places the smoke ahead of this pose

const char* const kDescription =
    R"(sgfx-bench renders a scene headless along a deterministic camera path (t = i/N) at each size with
each effect configuration, glFinish after every frame, and prints ms/frame (median, p10, p90), FPS
(1000/median) and the GPU time of every pass as Markdown tables, one per size.)";

struct Size {
    int width = 0, height = 0;
    std::string name() const { return std::to_string(width) + "x" + std::to_string(height); }
};

struct Effects {
    bool fog = false, ao = false, aa = false, oit = false, rain = false, sky = false, smoke = false;
    bool env = false;
    bool windscreen = false;
};

struct Config {
    std::string name;
    Effects effects;
};

struct Options {
    std::string model;
    float scale = 1.0f;
    std::vector<Size> sizes{{1280, 720}, {1920, 1080}, {3840, 2160}};
    int frames = 100;
    int warmup = 5;
    std::vector<Config> configs;
    std::string json, plot;
    bool egl = false;
};

std::vector<std::string_view> split(std::string_view s, char sep) {
    std::vector<std::string_view> parts;
    std::size_t pos = 0;
    while (true) {
        const std::size_t next = s.find(sep, pos);
        parts.push_back(s.substr(pos, next == std::string_view::npos ? std::string_view::npos : next - pos));
        if (next == std::string_view::npos) return parts;
        pos = next + 1;
    }
}

Config parseConfig(std::string_view item) {
    Config c{std::string(item), {}};
    for (std::string_view e : split(item, '+')) {
        Effects& f = c.effects;
        if (e == "none") {
        } else if (e == "fog") {
            f.fog = true;
        } else if (e == "ao") {
            f.ao = true;
        } else if (e == "aa") {
            f.aa = true;
        } else if (e == "oit") {
            f.oit = true;
        } else if (e == "rain") {
            f.rain = true;
        } else if (e == "sky") {
            f.sky = true;
        } else if (e == "smoke") {
            f.smoke = true;
        } else if (e == "env") {
            f.env = true;
        } else if (e == "windscreen") {
            f.windscreen = true;
        } else if (e == "all") {
            f = {true, true, true, true, true, true, true, f.env, f.windscreen};
        } else {
            throw CLI::ValidationError("--effects",
                                       "'" + std::string(e) +
                                           "' is not none, fog, ao, aa, oit, rain, sky, smoke, env, "
                                           "windscreen or all");
        }
    }
    return c;
}

void addSceneOptions(CLI::App& cli, Options& o) {
    cli.add_option_function<std::string>(
           "--model",
           [&o](const std::string& v) {
               if (v.empty()) throw CLI::ValidationError("--model", "empty file name");
               o.model = v;
           },
           "benchmark this model (glTF/OBJ/OFF/PLY/STL; the camera orbits its bounds at 20° elevation; two "
           "glass panes through it, for oit) instead of the proving ground")
        ->type_name("FILE");
    cli.add_option_function<std::string>(
           "--scale",
           [&o](const std::string& v) {
               o.scale = float(demo::number("--scale", v, 0, 16));
               if (o.scale <= 0.0f)
                   throw CLI::ValidationError("--scale", "'" + v + "': S must be in (0, 16]");
           },
           "proving-ground triangle scale, 0 < S <= 16 (default 1)")
        ->type_name("S");
    cli.add_option_function<std::string>(
           "--sizes",
           [&o](const std::string& v) {
               o.sizes.clear();
               for (std::string_view sv : split(v, ',')) {
                   const std::string s(sv);
                   const auto x = s.find('x');
                   if (x == std::string::npos)
                       throw CLI::ValidationError("--sizes", "expected WxH, got '" + s + "'");
                   o.sizes.push_back(Size{demo::integer("--sizes", s.substr(0, x), 1, 16384),
                                          demo::integer("--sizes", s.substr(x + 1), 1, 16384)});
               }
           },
           "sizes (default 1280x720,1920x1080,3840x2160)")
        ->type_name("WxH[,WxH...]");
    cli.add_option("--frames", o.frames, "measured frames per configuration (default 100)")
        ->check(CLI::Range(1, 1000000))
        ->type_name("N");
    cli.add_option("--warmup", o.warmup, "warm-up frames before them, not measured (default 5)")
        ->check(CLI::Range(0, 1000000))
        ->type_name("N");
    cli.add_option_function<std::string>(
           "--effects",
           [&o](const std::string& v) {
               o.configs.clear();
               for (std::string_view item : split(v, ','))
                   o.configs.push_back(parseConfig(item));
           },
           "comma-separated configurations (default none,fog,ao,aa,oit,rain,sky,smoke,all); join effects "
           "with "
           "'+' for combinations (fog+ao). fog: forward height fog; ao: SSAO (32 samples); aa: MSAA 4x (the "
           "docs' first example, and polygon's `--aa msaa`); oit: weighted blended transparency; rain: "
           "200,000 "
           "GPU particles; sky: the physical sky at 18:30; smoke: a raymarched cloud; all: every one of "
           "those; "
           "env (not in all): the sky's image-based light in place of the flat ambient light; windscreen "
           "(not "
           "in all): a transmissive glass pane (KHR_materials_transmission) 1.5 m in front of the eye, "
           "filling "
           "the view")
        ->type_name("LIST");
}

void addOutputOptions(CLI::App& cli, Options& o) {
    auto file = [&cli](const char* name, std::string& out, const char* what) {
        return cli.add_option_function<std::string>(
            name,
            [&out, name](const std::string& v) {
                if (v.empty()) throw CLI::ValidationError(name, "empty file name");
                out = v;
            },
            what);
    };
    file("--json", o.json, "also write the results as JSON (machine and driver strings included)")
        ->type_name("FILE");
    file("--plot", o.plot,
         "also write a bar chart (FPS per configuration, grouped by size) through scripts/plot_bench.py "
         "(python3 and python3-matplotlib); without --json the JSON goes to FILE.png.json")
        ->type_name("FILE.png");
    cli.add_flag("--egl", o.egl, "render through EGL (GPU) instead of OSMesa");
}

// Returns -1 when the run goes on, else the exit status (0 after --help, 2 for bad options).
int parseArgs(int argc, char** argv, Options& o) {
    CLI::App cli{kDescription, "sgfx-bench"};
    cli.footer("exit status: 0 on success, 1 on a runtime error, 2 on a bad option or value");
    demo::lastValueWins(cli);
    addSceneOptions(cli, o);
    addOutputOptions(cli, o);
    const int status = demo::parse(cli, argc, argv);
    if (status < 0 && o.configs.empty())
        for (std::string_view item : {"none", "fog", "ao", "aa", "oit", "rain", "sky", "smoke", "all"})
            o.configs.push_back(parseConfig(item));
    return status;
}

// The scene without effects, and what the effects need to know about it.
struct BenchScene {
    sgfx::NodePtr root;
    std::shared_ptr<sgfx::Light> sun;
    glm::vec3 sunDirection{0.0f, 0.0f, -1.0f}; // as built (the sky effect turns the sun)
    std::shared_ptr<sgfx::TransparencyBin> bin;
    bool provingGround = true;
    glm::vec3 centre{0.0f};
    float radius = 1.0f, distance = 1.0f, baseZ = 0.0f; // a model's framing
    std::string description;
    std::size_t triangles = 0;
};

BenchScene provingGround(float scale) {
    const polygon::PolygonScene scene = polygon::buildPolygonScene({kExtent, scale, 1, true, false});
    BenchScene s;
    s.root = scene.root;
    s.bin = scene.glassBin;
    for (const auto& child : scene.root->children())
        if (auto sun = std::dynamic_pointer_cast<sgfx::Light>(child); sun && sun->name == "sun") s.sun = sun;
    std::ostringstream d;
    d << "proving ground (scale " << scale << ")";
    s.description = d.str();
    return s;
}

BenchScene modelScene(const std::string& file) {
    if (!std::filesystem::is_regular_file(file)) throw std::runtime_error(file + ": no such file");
    sgfx::NodePtr model;
    try {
        model = sgfx::loadModel(file);
    } catch (const std::exception& e) {
        throw std::runtime_error(file + ": " + e.what());
    }
    sgfx::ComputeBoundsVisitor bounds;
    model->accept(bounds);
    if (!bounds.valid()) throw std::runtime_error(file + ": the file holds no geometry");
    BenchScene s;
    s.provingGround = false;
    s.centre = 0.5f * (bounds.min + bounds.max);
    s.radius = std::max(0.5f * glm::length(bounds.max - bounds.min), 1e-3f);
    s.distance = s.radius / std::sin(glm::radians(20.0f)); // fits a 40° field of view
    s.baseZ = bounds.min.z;
    // Two horizontal glass panes through the model in a transparency bin, as the proving ground's
    // glass: drawn sorted, or order-independent with `oit` (everything under a bin is blended, so
    // the model itself stays outside it).
    s.bin = sgfx::TransparencyBin::create();
    auto glass = sgfx::StateSet::create();
    auto glassMaterial = sgfx::Material::create();
    glassMaterial->ambient = {0.55f, 0.75f, 0.85f};
    glassMaterial->diffuse = {0.55f, 0.75f, 0.85f, 0.3f};
    glassMaterial->specular = glm::vec3(0.8f);
    glassMaterial->shininess = 80.0f;
    glass->material.set(glassMaterial);
    glass->cullFace.set(sgfx::CullFace::None);
    const float height = bounds.max.z - bounds.min.z;
    for (const float f : {0.35f, 0.65f}) {
        auto pane = sgfx::shapes::quad(2.5f * s.radius, 2.5f * s.radius);
        pane->setStateSet(glass);
        auto place = sgfx::Transform::create(
            glm::translate(glm::mat4(1.0f), {s.centre.x, s.centre.y, s.baseZ + f * height}));
        place->addChild(pane);
        s.bin->addChild(place);
    }
    auto root = sgfx::Group::create();
    s.sun = sgfx::Light::create(sgfx::LightType::Directional);
    s.sun->name = "sun";
    s.sun->direction = glm::normalize(glm::vec3(-0.4f, 0.3f, -0.85f));
    s.sun->color = glm::vec3(0.9f);
    auto ambient = sgfx::Light::create(sgfx::LightType::Ambient);
    ambient->color = glm::vec3(0.35f);
    root->addChild(s.sun);
    root->addChild(ambient);
    root->addChild(model);
    root->addChild(s.bin);
    s.root = root;
    s.description = file;
    return s;
}

polygon::CameraPose poseAt(const BenchScene& s, float t) {
    if (s.provingGround) return polygon::cameraPose(t, kExtent);
    const float a = 6.28318530718f * t, pitch = glm::radians(20.0f);
    polygon::CameraPose p;
    p.eye = s.centre + s.distance * glm::vec3(std::sin(a) * std::cos(pitch), -std::cos(a) * std::cos(pitch),
                                              std::sin(pitch));
    p.target = s.centre;
    return p;
}

// Rain over an area that follows the camera, as polygon's withRain (scaled to a model's size).
sgfx::NodePtr withRain(const BenchScene& s, sgfx::NodePtr world, std::shared_ptr<const sgfx::Camera> camera) {
    const float area = s.provingGround ? 80.0f : 4.0f * s.radius;
    const float above = s.provingGround ? 20.0f : 2.0f * s.radius;
    const float lowest = s.provingGround ? -10.0f : s.baseZ;
    return polygon::withRainFollowing(std::move(world), std::move(camera), area, kRainCount, above, lowest);
}

// The scene with the configuration's effects around it, placed as polygon's sceneWithEffects.
sgfx::NodePtr withEffects(const BenchScene& s, const Effects& e, std::shared_ptr<const sgfx::Camera> camera) {
    if (s.bin)
        s.bin->setMode(e.oit ? sgfx::TransparencyMode::WeightedBlended : sgfx::TransparencyMode::Sorted);
    if (s.sun) s.sun->direction = e.sky ? -sgfx::sky::sunDirection(kSkyHours) : s.sunDirection;
    sgfx::NodePtr world = s.root;
    if (e.rain) world = withRain(s, world, std::move(camera));
    std::shared_ptr<sgfx::SkyNode> sky;
    if (e.sky || e.smoke) {
        auto group = sgfx::Group::create();
        group->addChild(world);
        if (e.sky) {
            sky = sgfx::SkyNode::create(sgfx::SkyParameters::atTime(kSkyHours));
            group->addChild(sky);
        }
        if (e.smoke) {
            sgfx::VolumeParameters vp;
            glm::vec3 at;
            if (s.provingGround) { // polygon's cloud: 40 x 40 x 24 m over the road ahead
                vp.size = {40.0f, 40.0f, 24.0f};
                vp.absorption = 0.02f;
                vp.scattering = 0.12f;
                const polygon::CameraPose pose = poseAt(s, kSmokePoseTime);
                at = pose.eye + 0.6f * (pose.target - pose.eye);
                at.z = std::max(at.z, 0.0f) + 0.5f * vp.size.z;
            } else { // the same optical depth across a box around the model
                vp.size = glm::vec3(2.0f, 2.0f, 1.2f) * s.radius;
                vp.absorption = 0.4f / s.radius;
                vp.scattering = 2.4f / s.radius;
                at = s.centre;
            }
            vp.g = 0.5f;
            vp.lightColor = glm::vec3(4.0f, 3.8f, 3.4f);
            if (s.sun) vp.lightDirection = glm::normalize(s.sun->direction);
            vp.validate();
            auto place = sgfx::Transform::create(glm::translate(glm::mat4(1.0f), at));
            place->addChild(sgfx::VolumeNode::create(vp, sgfx::VolumeGrid::noise(64, 7, 4, 0.35f)));
            group->addChild(place);
        }
        world = group;
    }
    if (e.env) { // the sky's light (drawn or not) for the scene's sun
        if (!sky) {
            sgfx::SkyParameters sp;
            sp.sunDirection = s.sun ? -glm::normalize(s.sun->direction) : glm::vec3(0, 0, 1);
            sky = sgfx::SkyNode::create(sp);
        }
        auto env = sgfx::EnvironmentLightNode::create(std::shared_ptr<const sgfx::SkyNode>(sky));
        env->addChild(world);
        world = env;
    }
    if (e.ao) {
        sgfx::AmbientOcclusionParameters p;
        if (!s.provingGround) {
            p.radius = 0.1f * s.radius;
            p.bias = 0.005f * s.radius;
        }
        auto ao = sgfx::AmbientOcclusionNode::create(p);
        ao->addChild(world);
        world = ao;
    }
    if (!e.fog) return world;
    sgfx::FogParameters p = s.provingGround ? sgfx::FogParameters::ground() : sgfx::FogParameters{};
    if (!s.provingGround) { // as sgfx-view: half the light from the model's centre reaches the eye
        p.density = std::log(2.0f) / s.distance;
        p.falloff = std::min(1.0f / s.radius, 1e3f);
        p.referenceHeight = s.baseZ;
        p.color = {0.72f, 0.76f, 0.82f};
    }
    auto fog = sgfx::FogNode::create(p, sgfx::FogMode::Forward);
    fog->addChild(world);
    if (sky && e.sky) sky->attachFog(fog);
    return fog;
}

// A cockpit's windscreen: thin, slightly tinted, almost smooth glass (KHR_materials_transmission),
// facing the eye in its own frame (Transform set per frame).
std::shared_ptr<sgfx::Transform> makeWindscreen() {
    auto glass = sgfx::Material::create();
    glass->model = sgfx::ShadingModel::MetallicRoughness;
    glass->diffuse = {0.92f, 0.96f, 0.94f, 1.0f};
    glass->metallic = 0.0f;
    glass->roughness = 0.05f;
    glass->transmission = 1.0f;
    glass->thickness = 0.01f;
    auto pane = sgfx::shapes::quad(4.0f, 2.4f);
    pane->getOrCreateStateSet().material.set(glass);
    pane->getOrCreateStateSet().cullFace.set(sgfx::CullFace::None);
    auto t = sgfx::Transform::create();
    t->addChild(pane);
    return t;
}

struct Result {
    Size size;
    std::string effects;
    double medianMs = 0, p10Ms = 0, p90Ms = 0, fps = 0, drawCalls = 0, triangles = 0;
    std::vector<std::pair<std::string, double>> passes; // mean GPU ms per frame, frame order
};

double percentile(std::vector<double> v, double q) {
    std::sort(v.begin(), v.end());
    const double x = q * double(v.size() - 1);
    const std::size_t lo = std::size_t(x), hi = std::min(lo + 1, v.size() - 1);
    return v[lo] + (x - double(lo)) * (v[hi] - v[lo]);
}

void reportGl(sgfx::Viewer& viewer) {
    for (const std::string& e : viewer.renderer().takeGlErrors())
        std::cerr << "sgfx-bench: GL: " << e << "\n";
    for (const std::string& w : viewer.renderer().takeWarnings())
        std::cerr << "sgfx-bench: warning: " << w << "\n";
}

struct Machine {
    std::string renderer, version, context;
};

Result runOne(const Options& o, const BenchScene& s, const Size& size, const Config& c, Machine& machine) {
    using clock = std::chrono::steady_clock;
    auto viewer = sgfx::Viewer::createHeadless(
        size.width, size.height, o.egl ? sgfx::Viewer::Headless::Egl : sgfx::Viewer::Headless::Default);
    viewer->renderer().options().timePasses = true; // GPU time per pass from timer queries
    auto& cam = *viewer->camera();
    if (s.provingGround) {
        cam.clearColor = kSkyColor;
        cam.setPerspective(polygon::kPathFovyDegrees, polygon::kPathNear, polygon::kPathFar);
    } else {
        cam.clearColor = {0.72f, 0.76f, 0.82f, 1.0f};
        cam.setPerspective(40.0f, s.distance * 0.02f, s.distance * 20.0f);
    }
    cam.setAntiAliasing(c.effects.aa ? sgfx::AntiAliasing::msaa(4) : sgfx::AntiAliasing::none());
    // The windscreen rides with the eye: 1.5 m ahead, 4 × 2.4 m (wider than the view).
    const std::shared_ptr<sgfx::Transform> windscreen = c.effects.windscreen ? makeWindscreen() : nullptr;
    auto look = [&](float t) {
        const polygon::CameraPose p = poseAt(s, t);
        cam.setLookAt(p.eye, p.target, p.up);
        if (windscreen)
            windscreen->setMatrix(glm::inverse(cam.viewMatrix) *
                                  glm::translate(glm::mat4(1.0f), {0.0f, 0.0f, -1.5f}));
    };
    look(0.0f);
    sgfx::NodePtr scene = withEffects(s, c.effects, viewer->camera());
    if (windscreen) {
        auto group = sgfx::Group::create();
        group->addChild(scene);
        group->addChild(windscreen);
        scene = group;
    }
    viewer->setSceneData(scene);
    for (int i = 0; i < o.warmup; ++i) {
        viewer->frame();
        glFinish();
    }
    if (machine.renderer.empty()) {
        machine.renderer = viewer->context().renderer();
        machine.version = viewer->context().version();
        machine.context = std::string(viewer->context().kind());
    }
    Result r;
    r.size = size;
    r.effects = c.name;
    std::vector<double> ms;
    ms.reserve(std::size_t(o.frames));
    for (int i = 0; i < o.frames; ++i) {
        look(float(i) / float(o.frames));
        const auto t0 = clock::now();
        viewer->frame();
        glFinish();
        ms.push_back(std::chrono::duration<double, std::milli>(clock::now() - t0).count());
        const sgfx::FrameStats& st = viewer->stats();
        r.drawCalls += double(st.drawCalls);
        r.triangles += double(st.triangles);
        for (const auto& pt : st.passTimes) {
            auto it = std::find_if(r.passes.begin(), r.passes.end(),
                                   [&](const auto& p) { return p.first == pt.name; });
            if (it == r.passes.end())
                r.passes.emplace_back(pt.name, pt.gpuMs);
            else
                it->second += pt.gpuMs;
        }
    }
    reportGl(*viewer);
    const double n = double(o.frames);
    r.drawCalls /= n;
    r.triangles /= n;
    for (auto& p : r.passes)
        p.second /= n;
    r.medianMs = percentile(ms, 0.5);
    r.p10Ms = percentile(ms, 0.1);
    r.p90Ms = percentile(ms, 0.9);
    r.fps = r.medianMs > 0.0 ? 1000.0 / r.medianMs : 0.0;
    return r; // the viewer goes here, releasing the scene's GL objects with its context
}

std::string jsonString(std::string_view s) {
    std::string out = "\"";
    for (const char ch : s) {
        const auto c = static_cast<unsigned char>(ch);
        switch (c) {
        case '"':
            out += "\\\"";
            break;
        case '\\':
            out += "\\\\";
            break;
        case '\n':
            out += "\\n";
            break;
        case '\r':
            out += "\\r";
            break;
        case '\t':
            out += "\\t";
            break;
        default:
            if (c < 0x20) {
                char buf[8];
                std::snprintf(buf, sizeof buf, "\\u%04x", unsigned(c));
                out += buf;
            } else {
                out += ch;
            }
        }
    }
    return out + "\"";
}

std::string jsonNumber(double v) {
    if (!std::isfinite(v)) return "null";
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.4f", v);
    return buf;
}

void writeJson(const std::string& path, const Options& o, const BenchScene& s, const Machine& m,
               const std::vector<Result>& results) {
    std::ofstream f(path);
    if (!f) throw std::runtime_error(path + ": cannot write");
    f << "{\n  \"renderer\": " << jsonString(m.renderer) << ",\n  \"version\": " << jsonString(m.version)
      << ",\n  \"context\": " << jsonString(m.context)
      << ",\n  \"cpus\": " << std::thread::hardware_concurrency()
      << ",\n  \"scene\": " << jsonString(s.description) << ",\n  \"scene_triangles\": " << s.triangles
      << ",\n  \"frames\": " << o.frames << ",\n  \"warmup\": " << o.warmup << ",\n  \"results\": [";
    for (std::size_t i = 0; i < results.size(); ++i) {
        const Result& r = results[i];
        f << (i ? ",\n" : "\n") << "    {\"size\": " << jsonString(r.size.name())
          << ", \"effects\": " << jsonString(r.effects) << ", \"median_ms\": " << jsonNumber(r.medianMs)
          << ", \"p10_ms\": " << jsonNumber(r.p10Ms) << ", \"p90_ms\": " << jsonNumber(r.p90Ms)
          << ", \"fps\": " << jsonNumber(r.fps) << ", \"passes\": {";
        for (std::size_t k = 0; k < r.passes.size(); ++k)
            f << (k ? ", " : "") << jsonString(r.passes[k].first) << ": " << jsonNumber(r.passes[k].second);
        f << "}, \"draw_calls\": " << jsonNumber(r.drawCalls)
          << ", \"triangles\": " << jsonNumber(r.triangles) << "}";
    }
    f << "\n  ]\n}\n";
    if (!f) throw std::runtime_error(path + ": write failed");
}

std::string markdownCell(std::string s) {
    for (std::size_t p = 0; (p = s.find('|', p)) != std::string::npos; p += 2)
        s.insert(p, "\\");
    return s;
}

void printMarkdown(const Options& o, const BenchScene& s, const Machine& m,
                   const std::vector<Result>& results) {
    std::printf("# sgfx-bench: %s\n\n", markdownCell(s.description).c_str());
    std::printf("GL_RENDERER: %s; GL_VERSION: %s (%s, %u CPUs). %zu triangles in the scene; %d frames "
                "per configuration after %d warm-up frames; ms/frame median, p10, p90; FPS = 1000/median.\n",
                markdownCell(m.renderer).c_str(), markdownCell(m.version).c_str(), m.context.c_str(),
                std::thread::hardware_concurrency(), s.triangles, o.frames, o.warmup);
    for (const Size& size : o.sizes) {
        double none = 0.0;
        for (const Result& r : results)
            if (r.size.name() == size.name() && r.effects == "none") none = r.medianMs;
        std::printf("\n## %s\n\n| effects | median ms | p10 | p90 | FPS | × none | passes (GPU ms) |\n"
                    "|---|---:|---:|---:|---:|---:|---|\n",
                    size.name().c_str());
        for (const Result& r : results) {
            if (r.size.name() != size.name()) continue;
            std::string passes;
            char buf[64];
            for (const auto& [name, gpuMs] : r.passes) {
                std::snprintf(buf, sizeof buf, "%.2f", gpuMs);
                passes += (passes.empty() ? "" : ", ") + name + " " + buf;
            }
            char ratio[32] = "–";
            if (none > 0.0) std::snprintf(ratio, sizeof ratio, "%.2f", r.medianMs / none);
            std::printf("| %s | %.2f | %.2f | %.2f | %.1f | %s | %s |\n", r.effects.c_str(), r.medianMs,
                        r.p10Ms, r.p90Ms, r.fps, ratio, markdownCell(passes).c_str());
        }
    }
    std::fflush(stdout);
}

std::string shellQuote(const std::string& s) {
    std::string out = "'";
    for (const char c : s)
        out += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return out + "'";
}

std::filesystem::path plotScript() {
#ifdef SGFX_SOURCE_DIR
    const std::filesystem::path source = SGFX_SOURCE_DIR;
#else
    const std::filesystem::path source =
        std::filesystem::path(__FILE__).parent_path().parent_path().parent_path();
#endif
    return source / "scripts" / "plot_bench.py";
}

int plot(const std::string& json, const std::string& png) {
    const std::filesystem::path script = plotScript();
    if (!std::filesystem::is_regular_file(script)) {
        std::cerr << "sgfx-bench: --plot: " << script.string() << " not found\n";
        return 1;
    }
    if (std::system("command -v python3 >/dev/null 2>&1") != 0) {
        std::cerr << "sgfx-bench: --plot needs python3 and matplotlib (Debian: apt-get install python3 "
                     "python3-matplotlib); the results are in "
                  << json << "\n";
        return 1;
    }
    const std::string cmd = "python3 " + shellQuote(script.string()) + " " + shellQuote(json) + " " +
                            shellQuote(png) + " 1>&2"; // stdout is the Markdown table
    if (std::system(cmd.c_str()) != 0) {
        std::cerr << "sgfx-bench: --plot: " << cmd << " failed; the results are in " << json << "\n";
        return 1;
    }
    std::cerr << "sgfx-bench: wrote " << png << "\n";
    return 0;
}

int run(const Options& o) {
    BenchScene scene = o.model.empty() ? provingGround(o.scale) : modelScene(o.model);
    if (scene.sun) scene.sunDirection = scene.sun->direction;
    sgfx::StatsVisitor stats;
    scene.root->accept(stats);
    scene.triangles = stats.triangles;

    Machine machine;
    std::vector<Result> results;
    const std::size_t total = o.sizes.size() * o.configs.size();
    for (const Size& size : o.sizes)
        for (const Config& c : o.configs) {
            // One scene for every viewer: each viewer releases its GL objects when it goes.
            results.push_back(runOne(o, scene, size, c, machine));
            std::fprintf(stderr, "[%zu/%zu] %s %s: %.1f ms\n", results.size(), total, size.name().c_str(),
                         c.name.c_str(), results.back().medianMs);
        }

    printMarkdown(o, scene, machine, results);
    std::string json = o.json;
    if (json.empty() && !o.plot.empty()) json = o.plot + ".json";
    if (!json.empty()) writeJson(json, o, scene, machine, results);
    if (!o.plot.empty()) return plot(json, o.plot);
    return 0;
}

} // namespace

int main(int argc, char** argv) {
    Options options;
    if (const int status = parseArgs(argc, argv, options); status >= 0) return status;
    try {
        return run(options);
    } catch (const std::exception& e) {
        std::cerr << "sgfx-bench: error: " << e.what() << "\n";
        return 1;
    }
}

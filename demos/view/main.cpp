// sgfx-view: look at a model (glTF, OBJ, OFF, PLY, STL) under the effects. With a display it opens
// a window (orbit/fly camera, a panel to tune the effects, a stats overlay); without one, or with
// --headless or --out, it renders one still to a PNG, optionally a row of panels comparing the
// effects (plain | fog | AO | both). A click in the window, or --pick X,Y headless, tells what a
// pixel shows: the node path, the world point and the normal (sgfx::pick).
#include "AnimationControls.h"
#include "CliParse.h"
#include "Options.h"
#include "ViewScene.h"

#include <sgfx/GraphicsContext.h>
#include <sgfx/Manipulator.h>
#include <sgfx/ModelLoader.h>
#include <sgfx/Queries.h>
#include <sgfx/Viewer.h>
#include <sgfx/Visitors.h>
#include <sgfx/nodes/splat/GaussianSplatNode.h>
#include <sgfx_glad/gl.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <numeric>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace {

const char* const kDescription =
    R"(sgfx-view: look at a model under the effects. Loads the files (.gltf .glb .obj .off .ply .stl; a .ply of 3D Gaussian splats (vertex properties
f_dc_0, opacity, scale_0, rot_0) is drawn as splats; with the OpenSceneGraph bridge also .osgt .osgb
.osg .ive .flt and the other formats osgDB reads, images found through OSG_FILE_PATH). With a
display (DISPLAY or WAYLAND_DISPLAY) it opens a window; otherwise, or with --headless or --out, it
renders a PNG.)";

const char* const kFooter = R"(Window keys: left click pick (the panel shows the node path, point and normal),
  left drag orbit/look, right drag zoom, middle drag pan, wheel zoom (fly: speed),
  WASD move, Q/E down/up, Shift fast, V orbit/fly, H home, F fog, O AO, M anti-aliasing, R weather,
  K sky, G ground, L shadows, Space play/pause, N next animation, F1 panel, F12 or P screenshot,
  Esc quit; drop files on the window to load them. The panel's Animation section has the
  timeline: the animation, play/pause, a time slider to scrub, the speed and loop or clamp.
Exit status: 0 written, 1 a file failed to load or render, 2 bad options (an unknown animation
too).)";

using demo::number;

// What the command line gave beyond the options' values, for the checks after the parse.
struct Given {
    bool size = false;
    std::vector<std::string> files; // taken as an optional value (--auto-lod FILE, --shadows FILE)
    std::vector<std::string> args;  // the command line, for the files' order
};

// The files in command-line order, those taken as an optional value (--auto-lod FILE or
// --auto-lod=FILE) among the others: they load, and name their errors, in that order.
std::vector<std::string> inArgumentOrder(std::vector<std::string> pool,
                                         const std::vector<std::string>& args) {
    std::vector<std::string> out;
    for (std::string a : args) {
        for (const std::string_view option : {"--auto-lod=", "--shadows="})
            if (a.starts_with(option)) a.erase(0, option.size());
        if (const auto it = std::find(pool.begin(), pool.end(), a); it != pool.end()) {
            out.push_back(std::move(*it));
            pool.erase(it);
        }
    }
    out.insert(out.end(), pool.begin(), pool.end());
    return out;
}

using demo::choice;

void addOutputOptions(CLI::App& cli, view::Options& o, Given& given) {
    cli.add_option("files", o.files, "the model files")->type_name("FILE");
    cli.add_option_function<std::string>(
           "--out", [&](const std::string& v) { o.out = v, o.outGiven = true; },
           "output image (default sgfx-view.png); implies --headless")
        ->type_name("PNG");
    cli.add_flag("--headless", o.headless, "render to the PNG even when a display exists");
    cli.add_flag("--window", o.window, "open a window or fail (exit 1) when none can be opened");
    demo::addSize(cli, o.width, o.height, 16, 4096,
                  "window size (default 1280x720), or image size per panel (512x384)", &given.size);
    cli.add_flag("--compare", o.compare, "four panels side by side: plain, fog, AO, fog + AO (headless)");
    cli.add_option_function<std::string>(
           "--pick",
           [&](const std::string& v) {
               const auto comma = v.find(',');
               if (comma == std::string::npos) throw CLI::ValidationError("--pick", "'" + v + "' is not X,Y");
               o.pick = glm::dvec2(number("--pick", v.substr(0, comma), 0, 65536),
                                   number("--pick", v.substr(comma + 1), 0, 65536));
           },
           "headless: print what pixel (X, Y) of the image shows (pixels from its top-left corner, "
           "fractions allowed): the node path, the world point and the normal, then exit without rendering")
        ->type_name("X,Y");
    cli.add_option_function<int>(
           "--self-test", [&](int n) { o.selfTestFrames = n, o.window = true; },
           "window: N frames of scripted input (both cameras, every toggle, a resize, a screenshot to "
           "--out's name), then exit")
        ->check(CLI::Range(4, 100000))
        ->type_name("N");
}

void addFogAndLightOptions(CLI::App& cli, view::Settings& s) {
    cli.add_option_function<std::string>(
           "--fog",
           [&](const std::string& v) {
               s.fog = v != "off";
               const bool autoFog = v == "auto" || v == "on"; // density 0: the model-scaled preset's own
               s.fogDensity = autoFog || !s.fog ? 0.0f : float(number("--fog", v, 0.0, 1e6));
           },
           "height fog: density per metre at the model's base (auto or on: the model's centre half "
           "hidden), falling off over the model's height; off: none")
        ->type_name("RHO|auto|on|off");
    cli.add_option_function<std::string>(
           "--fog-mode",
           [&](const std::string& v) {
               s.fogMode = choice<sgfx::FogMode>("--fog-mode", v,
                                                 {{"forward", sgfx::FogMode::Forward},
                                                  {"split", sgfx::FogMode::ForwardSplit},
                                                  {"post", sgfx::FogMode::PostProcess}},
                                                 "forward, split or post");
           },
           "forward (default), split (seed 2's pre-pass) or post (seed 1's post-process)")
        ->type_name("MODE");
    cli.add_option_function<std::string>(
           "--sky",
           [&](const std::string& v) { s.sky = true, s.skyHours = float(number("--sky", v, 0, 24)); },
           "physical sky and sun at this solar time (0..24)")
        ->type_name("HOURS");
    cli.add_option_function<std::string>(
           "--env",
           [&](const std::string& v) {
               s.env = v == "none"  ? view::EnvSource::None
                       : v == "sky" ? view::EnvSource::Sky
                                    : view::EnvSource::File;
               s.envFile = s.env == view::EnvSource::File ? v : std::string();
           },
           "image-based light: sky (default: the sky of --sky's time, drawn or not), none, or a panorama "
           "file (.hdr, .png, .jpg; twice as wide as high, Z up)")
        ->type_name("SOURCE");
    cli.add_option_function<std::string>(
           "--env-intensity",
           [&](const std::string& v) { s.envIntensity = float(number("--env-intensity", v, 0, 1e6)); },
           "scales the environment's light (default 1)")
        ->type_name("X");
    cli.add_flag_callback(
        "--no-ground", [&] { s.ground = false; }, "no ground plane under the model");
}

void addEffectOptions(CLI::App& cli, view::Settings& s, Given& given) {
    cli.add_flag("--ao", s.ao, "screen-space ambient occlusion (radius a tenth of the model's size)");
    cli.add_option_function<std::string>(
           "--aa",
           [&](const std::string& v) {
               try {
                   s.antiAliasing = sgfx::AntiAliasing::parse(v);
               } catch (const std::invalid_argument& e) {
                   throw CLI::ValidationError("--aa", e.what());
               }
           },
           "anti-aliasing: none, msaa, msaa1..msaa8, ssaa2..ssaa4, fxaa, fxaa-low, fxaa-high, taa, smaa, "
           "smaa-t2x, smaa[-t2x][-low|-medium|-high|-ultra][-luma|-colour|-depth]")
        ->type_name("MODE");
    cli.add_option_function<std::string>(
           "--weather",
           [&](const std::string& v) {
               s.weather = choice<view::Weather>("--weather", v,
                                                 {{"none", view::Weather::None},
                                                  {"rain", view::Weather::Rain},
                                                  {"snow", view::Weather::Snow}},
                                                 "none, rain or snow");
           },
           "none, rain or snow particles over the model")
        ->type_name("KIND");
    // An optional on|off: a bare --shadows is on; anything else after it is a model file.
    cli.add_option_function<std::string>(
           "--shadows",
           [&](const std::string& v) {
               s.shadows = v != "off";
               if (!v.empty() && v != "on" && v != "off") given.files.push_back(v);
           },
           "the sun's shadows (cascaded shadow maps over 20 model radii of view depth; default off, a "
           "bare --shadows is on)")
        ->expected(0, 1)
        ->type_name("[on|off]");
    cli.add_option_function<std::string>(
           "--shadow-filter",
           [&](const std::string& v) {
               s.shadowFilter = choice<sgfx::ShadowFilter>("--shadow-filter", v,
                                                           {{"hard", sgfx::ShadowFilter::Hard2x2},
                                                            {"pcf", sgfx::ShadowFilter::Pcf},
                                                            {"pcss", sgfx::ShadowFilter::Pcss}},
                                                           "hard, pcf or pcss");
           },
           "hard (one hardware comparison, 2x2 bilinear), pcf (a rotated 16-tap Poisson disc, default) or "
           "pcss (penumbrae widen with the blocker's distance)")
        ->type_name("F");
    cli.add_option_function<std::string>(
           "--shadow-debug",
           [&](const std::string& v) {
               if (v != "cascades")
                   throw CLI::ValidationError("--shadow-debug", "'" + v + "' is not cascades");
               s.shadowCascades = true;
           },
           "cascades: tint each pixel by the shadow cascade that shades it")
        ->type_name("cascades");
}

void addModelOptions(CLI::App& cli, view::Options& o, Given& given) {
    auto angle = [&](const char* name, float& out, double lo, double hi, const char* what) {
        cli.add_option_function<std::string>(
               name, [&out, name, lo, hi](const std::string& v) { out = float(number(name, v, lo, hi)); },
               what)
            ->type_name("DEG");
    };
    angle("--yaw", o.yaw, -360, 360, "camera azimuth around the model (default 30)");
    angle("--pitch", o.pitch, -89, 89, "camera elevation (default 25)");
    angle("--crease", o.crease, 0, 180,
          "glTF normals made for primitives without them: smooth below DEG (default flat)");
    cli.add_flag("--keep-y-up", o.keepYUp, "do not turn glTF's Y up into Z up");
    cli.add_option_function<std::string>(
           "--time",
           [&](const std::string& v) {
               char* end = nullptr;
               const double t = std::strtod(v.c_str(), &end);
               if (v.empty() || *end || !std::isfinite(t) || t < 0.0)
                   throw CLI::ValidationError("--time",
                                              "'" + v + "' is not a time in seconds (finite, >= 0)");
               o.time = t;
           },
           "the pose at this time (>= 0) of the animation (--animation's, or the first), paused there; "
           "headless, the summary line names both. Times past the end loop")
        ->type_name("SECONDS");
    cli.add_option_function<std::string>(
           "--animation",
           [&](const std::string& v) {
               if (v.empty()) throw CLI::ValidationError("--animation needs a name or an index");
               o.animation = v;
           },
           "the animation to play: an integer is an index, else a name (an unknown one is an error "
           "listing the files' animations)")
        ->type_name("NAME|INDEX");
    cli.add_flag("--list-animations", o.listAnimations,
                 "print each animation's index, name, duration and channels, then exit");
    // An optional number: a bare --auto-lod is 1 pixel; a value that is not wholly a number (such as
    // 2CylinderEngine.glb) is a model file.
    cli.add_option_function<std::string>(
           "--auto-lod",
           [&](const std::string& v) {
               char* end = nullptr;
               std::strtod(v.c_str(), &end);
               const bool isNumber = !v.empty() && *end == '\0';
               o.autoLodPixels = isNumber ? float(number("--auto-lod", v, 0.01, 100)) : 1.0f;
               if (!isNumber && !v.empty()) given.files.push_back(v);
           },
           "levels of detail made at load for every mesh (GltfOptions::autoLod), each level within PX pixels "
           "(default 1) of full detail where it is drawn")
        ->expected(0, 1)
        ->type_name("[PX]");
}

void addBenchOptions(CLI::App& cli, view::Options& o) {
    cli.add_option(
           "--bench", o.benchFrames,
           "headless: time N frames (after 3 warm-up frames, each ended by glFinish) and print a BENCH "
           "line (median_ms=...) like polygon --bench's; with --out the last frame is also written (as "
           "osg_view --frames writes its own)")
        ->check(CLI::Range(1, 100000))
        ->type_name("N");
    cli.add_flag(
        "--orbit", o.orbit,
        "with --bench: the orbit camera of bench/foreign_table.sh (eye at 1.5 times the bounding "
        "radius, 30 degrees elevation, 60 degree vertical field of view, the azimuth advancing 360/N "
        "degrees a frame from --yaw)");
    cli.add_flag("--occlusion", o.occlusion,
                 "with --bench: conservative occlusion culling of opaque items "
                 "(RendererOptions::occlusionCulling); the BENCH line adds the culled share");
}

// The checks across options, after the parse; then what the options imply.
void checkOptions(view::Options& o, Given& given) {
    o.files.insert(o.files.end(), given.files.begin(), given.files.end());
    o.files = inArgumentOrder(std::move(o.files), given.args);
    if (o.files.empty()) demo::usageError("no model file given");
    if (o.window && (o.headless || o.compare || o.pick))
        demo::usageError("--window and --self-test cannot go with --headless, --compare or --pick");
    if (o.pick && o.compare) demo::usageError("--pick cannot go with --compare");
    if (o.pick && (o.pick->x > o.width || o.pick->y > o.height))
        demo::usageError("--pick: the pixel is outside the " + std::to_string(o.width) + "x" +
                         std::to_string(o.height) + " image");
    if (o.orbit && !o.benchFrames) demo::usageError("--orbit needs --bench N");
    if (o.occlusion && !o.benchFrames) demo::usageError("--occlusion needs --bench N");
    if (o.benchFrames && (o.window || o.compare || o.pick))
        demo::usageError("--bench cannot go with --window, --self-test, --compare or --pick");
    if (o.pick || o.benchFrames) o.headless = true;
    if (o.outGiven && !o.window) o.headless = true;
    if (o.compare) o.headless = true;
    if (!o.headless && !given.size) o.width = 1280, o.height = 720; // a window's default
}

// Returns -1 when the program goes on, else its exit status (0 after --help, 2 for bad options).
int parse(int argc, char** argv, view::Options& o) {
    CLI::App cli{kDescription, "sgfx-view"};
    cli.footer(kFooter);
    demo::lastValueWins(cli);
    Given given;
    given.args.assign(argv + 1, argv + argc);
    addOutputOptions(cli, o, given);
    addFogAndLightOptions(cli, o.settings);
    addEffectOptions(cli, o.settings, given);
    addModelOptions(cli, o, given);
    addBenchOptions(cli, o);
    return demo::parse(cli, argc, argv, [&] { checkOptions(o, given); });
}

// The headless camera: homed on the model from the options' yaw and pitch, clip planes around it.
void homeCamera(const view::Options& o, const view::ViewScene& scene, sgfx::Camera& cam) {
    sgfx::OrbitManipulator orbit;
    orbit.home(scene.boundsMin(), scene.boundsMax(), 40.0f, float(o.width) / float(o.height), o.yaw, o.pitch);
    orbit.apply(cam);
    cam.setPerspective(40.0f, orbit.distance * 0.02f, orbit.distance * 20.0f);
}

// The benchmark's orbit camera (bench/osg_view.cpp --orbit has the same formula): around the
// centre C of the model's bounding box at 1.5 R (R: half the box's diagonal), 30 degrees above the
// horizontal, azimuth `yawDegrees` in sgfx-view's convention (0 looks along +Y, anticlockwise seen
// from above), 60 degree vertical field of view, near 0.01 R, far 4 R (the far side of the bounding
// sphere is 2.5 R away).
void orbitCamera(const view::ViewScene& scene, float yawDegrees, sgfx::Camera& cam) {
    const glm::vec3 centre = 0.5f * (scene.boundsMin() + scene.boundsMax());
    const float r = std::max(0.5f * glm::length(scene.boundsMax() - scene.boundsMin()), 1e-4f);
    const float yaw = glm::radians(yawDegrees), pitch = glm::radians(30.0f);
    const glm::vec3 look{-std::sin(yaw) * std::cos(pitch), std::cos(yaw) * std::cos(pitch), -std::sin(pitch)};
    cam.setLookAt(centre - look * (1.5f * r), centre, {0, 0, 1});
    cam.setPerspective(60.0f, 0.01f * r, 4.0f * r);
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// --bench N: N timed frames, each ended by glFinish, from the home camera or (--orbit) along the
// orbit; the BENCH line's fields are polygon --bench's where they mean the same.
int runBench(const view::Options& o, view::ViewScene& scene, double loadMs) {
    using clock = std::chrono::steady_clock;
    auto viewer = sgfx::Viewer::createHeadless(o.width, o.height);
    auto& cam = *viewer->camera();
    homeCamera(o, scene, cam);
    scene.apply(o.settings, cam);
    viewer->setSceneData(scene.root());
    if (o.occlusion)
        viewer->renderer().options().occlusionCulling = sgfx::RendererOptions::OcclusionCulling::On;
    auto pose = [&](int i) {
        if (o.orbit) orbitCamera(scene, o.yaw + 360.0f * float(i) / float(o.benchFrames), cam);
    };
    pose(0);
    for (int i = 0; i < 3; ++i) { // programs compile and buffers upload on the first frames
        viewer->frame();
        glFinish();
    }
    std::vector<double> ms;
    double triangles = 0, drawCalls = 0, culled = 0, items = 0, submissions = 0;
    for (int i = 0; i < o.benchFrames; ++i) {
        pose(i);
        const auto t0 = clock::now();
        viewer->frame();
        glFinish();
        ms.push_back(std::chrono::duration<double, std::milli>(clock::now() - t0).count());
        triangles += double(viewer->stats().triangles);
        drawCalls += double(viewer->stats().drawCalls);
        culled += double(viewer->stats().occlusionCulled);
        items += double(viewer->stats().items);
        submissions += double(viewer->stats().submissions);
    }
    for (const std::string& e : viewer->renderer().takeGlErrors())
        std::fprintf(stderr, "sgfx-view: GL: %s\n", e.c_str());
    if (o.outGiven) sgfx::writePng(o.out, viewer->capture()); // the last frame, to set beside OSG's
    const double n = double(o.benchFrames), mean = std::accumulate(ms.begin(), ms.end(), 0.0) / n;
    std::printf(
        "BENCH sgfx ms_per_frame=%.3f fps=%.2f frames=%d median_ms=%.3f triangles=%.0f draw_calls=%.1f "
        "size=%dx%d camera=%s fog=%d occlusion_culled=%.3f load_ms=%.0f submissions=%.1f context=%s "
        "renderer=%s\n",
        mean, 1000.0 / mean, o.benchFrames, median(ms), triangles / n, drawCalls / n, o.width, o.height,
        o.orbit ? "orbit" : "home", int(o.settings.fog), items > 0 ? culled / items : 0.0, loadMs,
        submissions / n, std::string(viewer->context().kind()).c_str(), viewer->context().renderer().c_str());
    return 0;
}

// --pick: what the image's pixel shows, with the camera the still would have.
int runPick(const view::Options& o, view::ViewScene& scene) {
    auto viewer = sgfx::Viewer::createHeadless(o.width, o.height);
    homeCamera(o, scene, *viewer->camera());
    scene.apply(o.settings, *viewer->camera());
    viewer->setSceneData(scene.root());
    if (o.time) viewer->update(); // the paused pose reaches the transforms
    std::printf("%s\n",
                scene.describePick(sgfx::pick(*viewer, o.pick->x, o.pick->y), o.pick->x, o.pick->y).c_str());
    return 0;
}

// `animated`: what --time and --animation chose, for the summary line.
int runHeadless(const view::Options& o, view::ViewScene& scene, double loadMs, const std::string& animated) {
    sgfx::StatsVisitor stats;
    scene.model()->accept(stats);
    std::vector<view::Settings> panels;
    if (o.compare) {
        for (int p = 0; p < 4; ++p) {
            view::Settings s = o.settings;
            s.fog = p == 1 || p == 3;
            s.ao = p >= 2;
            panels.push_back(s);
        }
    } else {
        panels.push_back(o.settings);
    }
    sgfx::Image out;
    out.width = o.width * int(panels.size());
    out.height = o.height;
    out.channels = 4;
    out.pixels.assign(std::size_t(out.width) * std::size_t(out.height) * 4, 0);
    auto viewer = sgfx::Viewer::createHeadless(o.width, o.height);
    auto& cam = *viewer->camera();
    homeCamera(o, scene, cam);
    viewer->setSceneData(scene.root());
    double frameMs = 0.0;
    for (std::size_t p = 0; p < panels.size(); ++p) {
        scene.apply(panels[p], cam);
        const auto t0 = std::chrono::steady_clock::now();
        // Particles and TAA need a few frames to settle; one is enough for the rest.
        const bool settle = panels[p].weather != view::Weather::None ||
                            panels[p].antiAliasing.mode == sgfx::AntiAliasing::Mode::Taa ||
                            panels[p].antiAliasing.mode == sgfx::AntiAliasing::Mode::SmaaT2x;
        for (int f = 0; f < (settle ? 30 : 1); ++f)
            viewer->frame();
        const sgfx::Image img = viewer->capture();
        frameMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        for (int y = 0; y < o.height; ++y)
            std::copy_n(
                img.pixel(0, y), std::size_t(o.width) * 4,
                out.pixels.begin() +
                    std::ptrdiff_t((std::size_t(y) * std::size_t(out.width) + p * std::size_t(o.width)) * 4));
    }
    for (const std::string& e : viewer->renderer().takeGlErrors())
        std::fprintf(stderr, "sgfx-view: GL: %s\n", e.c_str());
    sgfx::writePng(o.out, out);
    std::printf("wrote %s (%dx%d): %zu triangles, %zu nodes, loaded in %.0f ms, last frame %.0f ms, %u "
                "draw calls%s%s\n",
                o.out.c_str(), out.width, out.height, stats.triangles, stats.nodes, loadMs, frameMs,
                unsigned(viewer->stats().drawCalls), animated.empty() ? "" : ", ", animated.c_str());
    return 0;
}

} // namespace

sgfx::NodePtr view::loadFiles(const std::vector<std::string>& files, const Options& o) {
    auto model = sgfx::Group::create();
    model->name = "model";
    sgfx::GltfOptions gltf;
    gltf.zUp = !o.keepYUp;
    gltf.creaseAngle = glm::radians(o.crease);
    if (o.autoLodPixels > 0.0f) {
        gltf.autoLod.enabled = true;
        gltf.autoLod.errorPixels = o.autoLodPixels;
    }
    for (const std::string& file : files) {
        // A .ply whose vertices carry f_dc_0, opacity, scale_0 and rot_0 is 3D Gaussian splats.
        if (sgfx::splat::isSplatPly(file))
            model->addChild(sgfx::GaussianSplatNode::load(file));
        else
            model->addChild(sgfx::loadModel(file, gltf));
    }
    return model;
}

int main(int argc, char** argv) {
    view::Options o;
    if (const int status = parse(argc, argv, o); status >= 0) return status;
    try {
        const auto start = std::chrono::steady_clock::now();
        view::ViewScene scene;
        scene.setModel(view::loadFiles(o.files, o));
        const double loadMs =
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
        const auto players = view::findPlayers(*scene.model());
        if (o.listAnimations) {
            std::printf("%s", view::listAnimations(players).c_str());
            return 0;
        }
        std::string animated;
        try {
            animated = view::chooseAnimation(players, o.animation, o.time);
        } catch (const view::AnimationChoiceError& e) {
            std::fprintf(stderr, "sgfx-view: %s", e.what());
            if (!std::string_view(e.what()).ends_with('\n')) std::fprintf(stderr, "\n");
            return 2; // a bad option, only known once the files are loaded
        }
        if (!o.headless) {
            try {
                return view::runWindow(o, scene);
            } catch (const sgfx::ContextError& e) {
                std::fprintf(stderr, "sgfx-view: %s\n", e.what());
                if (o.window) return 1;
                std::fprintf(stderr, "sgfx-view: no window: rendering headless to %s\n", o.out.c_str());
            }
        }
        if (o.benchFrames) return runBench(o, scene, loadMs);
        return o.pick ? runPick(o, scene) : runHeadless(o, scene, loadMs, animated);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "sgfx-view: %s\n", e.what());
        return 1;
    }
}

// polygon: the sgfx proving ground. Renders the procedural test site headless to a PNG, flies
// through it in a window, benchmarks the shared camera path, or exports it as OBJ.
#include "AoFloor.h"
#include "CameraPath.h"
#include "CliParse.h"
#include "PolygonScene.h"
#include "StreetLamps.h"
#include "VehicleDrive.h"

#include <sgfx/GltfWriter.h>
#include <sgfx/GraphicsContext.h>
#include <sgfx/Manipulator.h>
#include <sgfx/OsgViewConfig.h>
#include <sgfx/nodes/ao/AmbientOcclusionNode.h>
#include <sgfx/nodes/fog/FogNode.h>
#include <sgfx/nodes/particles/ParticleSystemNode.h>
#include <sgfx/nodes/shadow/ShadowNode.h>
#include <sgfx/nodes/spherical/SphericalDisplayRig.h>

#include <filesystem>
#include <sgfx/ObjWriter.h>
#include <sgfx/Viewer.h>
#include <sgfx/Visitors.h>
#include <sgfx/nodes/environment/EnvironmentLightNode.h>
#include <sgfx/nodes/sky/SkyNode.h>
#include <sgfx/nodes/splat/GaussianSplatNode.h>
#include <sgfx/nodes/transparency/TransparencyBin.h>
#include <sgfx/nodes/volume/VolumeNode.h>

#include <sgfx_glad/gl.h>
// After glad: GLFW must not pull in the system GL header.
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <glm/gtc/constants.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <array>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <limits>
#include <memory>
#include <numeric>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace {

constexpr float kExtent = 800.0f;
constexpr float kStillTime = 0.1f;
const glm::vec4 kSkyColor{0.42f, 0.60f, 0.85f, 1.0f};  // linear
const glm::vec4 kDuskColor{0.05f, 0.05f, 0.09f, 1.0f}; // linear, with --lamps

const char* const kDescription =
    R"(polygon renders the sgfx proving ground: hilly terrain in tiles, roads, a few hundred buildings,
alpha-masked trees, a tracked robot vehicle, two glass panes and a glass cabin, lit by a sun and
the sky. The vehicle drives a loop over the hills, following the ground.
Without a mode option it renders one frame headless (OSMesa) and writes a PNG.)";

struct UsageError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

enum class Mode { Still, Window, Bench, ExportObj, ExportGltf };

struct Options {
    Mode mode = Mode::Still;
    std::string out = "polygon.png";
    std::string graph; ///< --graph: DOT file of the frame graph
    std::string objPath;
    std::string gltfPath;
    int width = 1280, height = 720;
    float time = kStillTime;
    std::optional<polygon::CameraPose> look;
    int channelsX = 1, channelsY = 1; ///< --channels CxR
    float scale = 1.0f;
    std::uint64_t seed = 1;
    std::optional<bool> drive; // --drive; unset: on except in --bench
    bool lod = true;
    bool manyDrawables = false;
    bool autoInstancing = true;
    std::uint64_t submitTriangles = sgfx::RendererOptions{}.submitTriangles;
    std::uint32_t submitsPerFrame = sgfx::RendererOptions{}.submitsPerFrame;
    int benchFrames = 0;
    bool egl = false;
    sgfx::RendererOptions::Lighting lighting = sgfx::RendererOptions::Lighting::PerPixel;
    std::optional<int> lamps; // --lamps: dusk and this many street lamps
    bool countFragments = false;
    sgfx::RendererOptions::ColorTarget colorTarget = sgfx::RendererOptions::ColorTarget::Srgb8;
    long windowFrames = 0; // --window: quit after this many frames (0 = until closed)
    std::string osgView;   // --osg-view: a .view file for the still image
    std::optional<sgfx::FogMode> fog = sgfx::FogMode::Forward;
    bool fogDeferOpaque = false; // --fog deferred: Forward with the opaque items' fog in one pass
    sgfx::FogParameters fogParameters = sgfx::FogParameters::ground();
    sgfx::TransparencyMode transparency = sgfx::TransparencyMode::Sorted;
    sgfx::AntiAliasing aa;
    std::optional<std::array<int, 5>> crop;
    bool ao = false;
    bool aoFloor = false; // --ao floor: AoFloorNode instead of AmbientOcclusionNode
    sgfx::AmbientOcclusionParameters aoParameters;
    bool rain = false;
    std::uint32_t rainCount = 200000;
    std::optional<float> skyHours;
    bool skyDirect = false;
    std::optional<std::string> env; // "sky" or a panorama file
    float envIntensity = 1.0f;
    bool smoke = false;
    std::optional<std::string> splats; // a Gaussian splatting .ply
    sgfx::SplatSort splatSort = sgfx::SplatSort::Gpu;
    sgfx::VolumeParameters volume = [] {
        sgfx::VolumeParameters p;
        p.size = {40.0f, 40.0f, 24.0f};
        p.absorption = 0.02f;
        p.scattering = 0.12f;
        p.g = 0.5f;
        p.lightColor = glm::vec3(4.0f, 3.8f, 3.4f);
        return p;
    }();
    bool shadows = false;       // --shadows on
    sgfx::ShadowOptions shadow; // --shadow-*: 3 cascades of 2048², 200 m, PCF
};

using demo::choice;
using demo::integer;
using demo::onOff;

// A finite number; the effects' validate() checks its range after the parse.
float real(const std::string& option, const std::string& v) {
    return float(
        demo::number(option, v, -std::numeric_limits<float>::max(), std::numeric_limits<float>::max()));
}

// Comma-separated values, exactly `n` of them; else a usage error naming the option and `what`.
std::vector<std::string> fields(const std::string& option, const std::string& v, std::size_t n,
                                const char* what) {
    std::vector<std::string> out;
    std::size_t pos = 0;
    for (std::size_t k = 0; k < n; ++k) {
        const std::size_t comma = k + 1 < n ? v.find(',', pos) : v.size();
        if (comma == std::string::npos) throw CLI::ValidationError(option, "'" + v + "' is not " + what);
        out.push_back(v.substr(pos, comma - pos));
        pos = comma + 1;
    }
    return out;
}

// --window, --bench, --export-obj and --export-gltf: at most one.
void addModeOptions(CLI::App& cli, Options& o, int& modes) {
    const char* group = "modes (at most one)";
    auto setMode = [&o, &modes](Mode m) { o.mode = m, ++modes; };
    cli.add_flag_callback(
           "--window", [=] { setMode(Mode::Window); },
           "fly through the scene in a window (WASD move, Q/E down/up, Shift fast, left mouse drag to look, "
           "F "
           "cycles the fog mode, T switches the glass between sorted and OIT, M cycles anti-aliasing, Esc "
           "quits); without a display it says \"no display: rendering headless\" and writes the PNG instead")
        ->group(group);
    cli.add_option_function<std::string>(
           "--bench",
           [&o, setMode](const std::string& v) {
               setMode(Mode::Bench);
               o.benchFrames = integer("--bench", v, 1, std::numeric_limits<int>::max());
           },
           "render N frames along the camera path (t = i/N) after 3 warm-up frames, glFinish after each, and "
           "print timings and render statistics")
        ->type_name("N")
        ->group(group);
    cli.add_option_function<std::string>(
           "--export-obj",
           [&o, setMode](const std::string& v) {
               setMode(Mode::ExportObj);
               if (v.empty()) throw CLI::ValidationError("--export-obj", "empty file name");
               o.objPath = v;
           },
           "write the scene as Wavefront OBJ (+ .mtl) and exit")
        ->type_name("FILE")
        ->group(group);
    cli.add_option_function<std::string>(
           "--export-gltf",
           [&o, setMode](const std::string& v) {
               setMode(Mode::ExportGltf);
               const std::filesystem::path ext = std::filesystem::path(v).extension();
               if (ext != ".glb" && ext != ".gltf")
                   throw CLI::ValidationError("--export-gltf", "'" + v + "' must end in .glb or .gltf");
               o.gltfPath = v;
           },
           "write the scene as glTF 2.0 (.glb binary, or .gltf with the data embedded)")
        ->type_name("FILE")
        ->group(group);
}

// The image: file names, size, camera, crop and channels.
void addImageOptions(CLI::App& cli, Options& o) {
    auto file = [&cli](const char* name, std::string& out, const char* what) {
        cli.add_option_function<std::string>(
               name,
               [&out, name](const std::string& v) {
                   if (v.empty()) throw CLI::ValidationError(name, "empty file name");
                   out = v;
               },
               what)
            ->type_name("FILE");
    };
    file("--out", o.out, "PNG to write (default polygon.png)");
    file("--graph", o.graph, "also write the frame's graph (passes, resources, GPU ms) as Graphviz DOT");
    demo::addSize(cli, o.width, o.height, 1, 16384,
                  "image / bench / window size in pixels (default 1280x720)");
    cli.add_option_function<std::string>(
           "--time",
           [&o](const std::string& v) {
               o.time = real("--time", v);
               if (!(o.time >= 0.0f && o.time < 1.0f))
                   throw CLI::ValidationError("--time", "'" + v + "': T must be in [0, 1)");
           },
           "camera path time of the still image, 0 <= T < 1 (default 0.1)")
        ->type_name("T");
    cli.add_option_function<std::string>(
           "--look",
           [&o](const std::string& v) {
               const auto f = fields("--look", v, 6, "six comma-separated numbers");
               polygon::CameraPose p;
               p.eye = {real("--look", f[0]), real("--look", f[1]), real("--look", f[2])};
               p.target = {real("--look", f[3]), real("--look", f[4]), real("--look", f[5])};
               const glm::vec3 d = p.target - p.eye;
               if (glm::length(glm::cross(d, p.up)) < 1e-6f * std::max(1.0f, glm::length(d)))
                   throw CLI::ValidationError("--look", "'" + v +
                                                            "': the eye must differ from the target and not "
                                                            "look straight up or down");
               o.look = p;
           },
           "still image (or every --bench frame) from eye E looking at target T instead of the camera path "
           "(metres, Z up)")
        ->type_name("EX,EY,EZ,TX,TY,TZ");
    cli.add_option_function<std::string>(
           "--crop",
           [&o](const std::string& v) {
               const auto f = fields("--crop", v, 5, "X,Y,W,H,Z");
               std::array<int, 5> c{};
               for (std::size_t k = 0; k < 5; ++k)
                   c[k] = integer("--crop", f[k], k < 2 ? 0 : 1, k < 4 ? 1 << 20 : 16);
               o.crop = c;
           },
           "write only the WxH region at (X, Y) of the image, each pixel shown as ZxZ (comparison crops; X, "
           "Y "
           ">= 0, W, H >= 1, Z in 1..16)")
        ->type_name("X,Y,W,H,Z");
    cli.add_option_function<std::string>(
           "--channels",
           [&o](const std::string& v) {
               char x = 0, rest = 0;
               if (std::sscanf(v.c_str(), "%d%c%d%c", &o.channelsX, &x, &o.channelsY, &rest) != 3 ||
                   x != 'x' || o.channelsX < 1 || o.channelsX > 8 || o.channelsY < 1 || o.channelsY > 8)
                   throw CLI::ValidationError("--channels", "'" + v + "' is not CxR with C and R in 1..8");
           },
           "split the view's frustum into CxR display channels of (W/C)x(H/R) pixels (Viewer::setChannels, "
           "docs/multi-view.md), 1..8 each")
        ->type_name("CxR");
    cli.add_option(
           "--osg-view", o.osgView,
           "the still image through an OpenSceneGraph .view display: a panoramic or 3D spherical-mirror "
           "projector (six cube faces warped, intensity map) of --size; setUpViewOnSingleScreen gives "
           "the plain image")
        ->type_name("FILE");
}

// The scene and how it is drawn.
void addSceneOptions(CLI::App& cli, Options& o) {
    cli.add_option_function<std::string>(
           "--scale",
           [&o](const std::string& v) {
               o.scale = real("--scale", v);
               if (!(o.scale > 0.0f && o.scale <= 16.0f))
                   throw CLI::ValidationError("--scale", "'" + v + "': S must be in (0, 16]");
           },
           "scale the triangle count, 0 < S <= 16 (default 1, about 600k triangles): terrain resolution and "
           "numbers of buildings and trees")
        ->type_name("S");
    cli.add_option_function<std::string>(
           "--seed",
           [&o](const std::string& v) {
               o.seed = integer<std::uint64_t>("--seed", v, 0, std::numeric_limits<std::uint64_t>::max());
           },
           "scene seed, an unsigned integer (default 1)")
        ->type_name("N");
    cli.add_option_function<std::string>(
           "--drive", [&o](const std::string& v) { o.drive = onOff("--drive", v); },
           "the vehicle drives its loop from the flat centre over the hills, set on the ground by four "
           "height "
           "queries a frame (default on; parked in exports, and in --bench unless on, so its frames match "
           "the "
           "OpenSceneGraph peer's)")
        ->type_name("on|off");
    cli.add_flag_callback(
        "--no-lod", [&o] { o.lod = false; },
        "every object at full detail (by default distant terrain tiles drop to half and quarter resolution "
        "and distant buildings to flat window panes; exports always hold the full detail)");
    cli.add_flag("--many-drawables", o.manyDrawables,
                 "the many-drawables benchmark scene: every window of every building its own drawable (about "
                 "26,000 more drawables)");
    cli.add_flag_callback(
        "--no-instancing", [&o] { o.autoInstancing = false; },
        "draw repeated meshes one by one (RendererOptions::autoInstancing off)");
    cli.add_option_function<std::string>(
           "--submit-triangles",
           [&o](const std::string& v) {
               o.submitTriangles = integer<std::uint64_t>("--submit-triangles", v, 0,
                                                          std::numeric_limits<std::uint64_t>::max());
           },
           "submit queued draws every N triangles so llvmpipe rasterises while the frame is still being "
           "drawn "
           "(RendererOptions::submitTriangles, default 20000; 0 submits once per frame)")
        ->type_name("N");
    cli.add_option_function<std::string>(
           "--submits-per-frame",
           [&o](const std::string& v) {
               o.submitsPerFrame = integer<std::uint32_t>("--submits-per-frame", v, 0,
                                                          std::numeric_limits<std::uint32_t>::max());
           },
           "at most about N of those submissions a frame (RendererOptions::submitsPerFrame, default 4; "
           "0: no limit)")
        ->type_name("N");
    cli.add_flag("--egl", o.egl, "render headless through EGL (GPU) instead of OSMesa");
    cli.add_option_function<std::string>(
           "--lighting",
           [&o](const std::string& v) {
               o.lighting = choice<sgfx::RendererOptions::Lighting>(
                   "--lighting", v,
                   {{"pixel", sgfx::RendererOptions::Lighting::PerPixel},
                    {"vertex", sgfx::RendererOptions::Lighting::PerVertex}},
                   "'pixel' or 'vertex'");
           },
           "per-pixel Blinn-Phong (default) or per-vertex (Gouraud) lighting")
        ->type_name("pixel|vertex");
    cli.add_option_function<std::string>(
           "--lamps", [&o](const std::string& v) { o.lamps = integer("--lamps", v, 0, 100000); },
           "dusk (a low, dim sun and a faint sky) with N street lamps along the roads, 0..100000: spot "
           "lights "
           "with a range (the light list's benchmark)")
        ->type_name("N");
    cli.add_option_function<std::string>(
           "--frames",
           [&o](const std::string& v) {
               o.windowFrames = integer("--frames", v, 1L, std::numeric_limits<long>::max());
           },
           "with --window: close after N frames (scripted runs)")
        ->type_name("N");
    cli.add_flag("--count-fragments", o.countFragments,
                 "with --bench: also count fragments that pass the depth test (an occlusion query per frame, "
                 "which itself costs a little time)");
    cli.add_option_function<std::string>(
           "--color-target",
           [&o](const std::string& v) {
               using Target = sgfx::RendererOptions::ColorTarget;
               o.colorTarget = choice<Target>(
                   "--color-target", v,
                   {{"srgb8", Target::Srgb8}, {"rgba16f", Target::Rgba16F}, {"rgba32f", Target::Rgba32F}},
                   "srgb8, rgba16f or rgba32f");
           },
           "the view's colour target (default srgb8); a float target keeps the small opacities of many "
           "blended "
           "slices unrounded (splats accumulate in a float target of their own)")
        ->type_name("srgb8|rgba16f|rgba32f");
}

// Fog and anti-aliasing. The preset comes before --fog-density and --fog-falloff, which override
// it whatever their order on the command line (CLI11 runs the options in the order set up here).
void addFogOptions(CLI::App& cli, Options& o) {
    const char* group = "effects";
    cli.add_option_function<std::string>(
           "--fog",
           [&o](const std::string& v) {
               o.fog = choice<std::optional<sgfx::FogMode>>("--fog", v,
                                                            {{"off", std::nullopt},
                                                             {"forward", sgfx::FogMode::Forward},
                                                             {"deferred", sgfx::FogMode::Forward},
                                                             {"split", sgfx::FogMode::ForwardSplit},
                                                             {"post", sgfx::FogMode::PostProcess}},
                                                            "off, forward, deferred, split or post");
               o.fogDeferOpaque = v == "deferred";
           },
           "height fog over the whole scene (default forward): in every material (forward), forward with the "
           "opaque items' fog in one pass after them where exact (deferred), the paper's depth pre-pass "
           "split "
           "(split) or its full-screen post-process (post)")
        ->type_name("off|forward|deferred|split|post")
        ->group(group);
    cli.add_option_function<std::string>(
           "--fog-preset",
           [&o](const std::string& v) {
               const sgfx::FogParameters keep = o.fogParameters; // response and sky stay as chosen
               o.fogParameters = choice<sgfx::FogParameters>(
                   "--fog-preset", v,
                   {{"solid", sgfx::FogParameters::solid()}, {"ground", sgfx::FogParameters::ground()}},
                   "solid or ground");
               o.fogParameters.response = keep.response;
               o.fogParameters.sky = keep.sky;
           },
           "the paper's figure 1 parameters: solid (rho0 = 1e-4, b = 1e-4) or ground fog (rho0 = 1e-3, b = "
           "4.5e-3, default)")
        ->type_name("solid|ground")
        ->group(group);
    cli.add_option_function<std::string>(
           "--fog-density",
           [&o](const std::string& v) { o.fogParameters.density = real("--fog-density", v); },
           "density rho0 per metre at height 0 (overrides the preset)")
        ->type_name("R")
        ->group(group);
    cli.add_option_function<std::string>(
           "--fog-falloff",
           [&o](const std::string& v) { o.fogParameters.falloff = real("--fog-falloff", v); },
           "falloff b per metre (overrides the preset)")
        ->type_name("B")
        ->group(group);
    cli.add_option_function<std::string>(
           "--fog-response",
           [&o](const std::string& v) {
               o.fogParameters.response = choice<sgfx::FogResponse>(
                   "--fog-response", v,
                   {{"linear", sgfx::FogResponse::Linear}, {"exp", sgfx::FogResponse::Exponential}},
                   "linear or exp");
           },
           "k = clamp(F, 0, 1) as in the paper, or 1 - e^-F (default)")
        ->type_name("linear|exp")
        ->group(group);
    cli.add_option_function<std::string>(
           "--fog-sky",
           [&o](const std::string& v) {
               o.fogParameters.sky = choice<sgfx::FogSky>("--fog-sky", v,
                                                          {{"off", sgfx::FogSky::Off},
                                                           {"far", sgfx::FogSky::FarPlane},
                                                           {"distance", sgfx::FogSky::Distance}},
                                                          "off, far or distance");
           },
           "fog on pixels without geometry: none, to the far plane, or along the ray to 100 km (default)")
        ->type_name("off|far|distance")
        ->group(group);
    cli.add_option_function<std::string>(
           "--aa",
           [&o](const std::string& v) {
               try {
                   o.aa = sgfx::AntiAliasing::parse(v);
               } catch (const std::invalid_argument& e) {
                   throw CLI::ValidationError("--aa", e.what());
               }
           },
           "anti-aliasing of the camera (default none; msaa = msaa4; smaa = high preset on luma, "
           "smaa[-t2x][-PRESET][-luma|-colour|-depth]): none, msaa, msaa2, msaa4, msaa8, ssaa2, ssaa3, "
           "ssaa4, "
           "fxaa, fxaa-low, fxaa-high, taa, smaa, smaa-low, smaa-medium, smaa-ultra, smaa-colour, "
           "smaa-depth, "
           "smaa-t2x; TAA converges over 16 frames, SMAA T2x over 2: --bench and --frames show it, a still "
           "renders 16 frames first")
        ->type_name("MODE")
        ->group(group);
    cli.add_option_function<std::string>(
           "--transparency",
           [&o](const std::string& v) {
               o.transparency =
                   choice<sgfx::TransparencyMode>("--transparency", v,
                                                  {{"sorted", sgfx::TransparencyMode::Sorted},
                                                   {"oit", sgfx::TransparencyMode::WeightedBlended}},
                                                  "sorted or oit");
           },
           "how the glass (two panes and a closed cabin) is blended: sorted back to front (default) or "
           "weighted blended order-independent transparency")
        ->type_name("sorted|oit")
        ->group(group);
}

// Ambient occlusion; the AO parameters' validate() checks the numbers after the parse.
void addAoOptions(CLI::App& cli, Options& o) {
    const char* group = "effects";
    cli.add_option_function<std::string>(
           "--ao",
           [&o](const std::string& v) {
               o.aoFloor = v == "floor";
               o.ao = o.aoFloor || onOff("--ao", v);
           },
           "screen-space ambient occlusion on the ambient light (default off); floor: only what any AO "
           "reading a depth pre-pass pays before computing anything (the pre-pass, a half-size pass, one "
           "read per fragment), for bench/ao_table.sh")
        ->type_name("off|on|floor")
        ->group(group);
    cli.add_option_function<std::string>(
           "--ao-samples",
           [&o](const std::string& v) {
               o.aoParameters.samples = integer("--ao-samples", v, 8, 64); // AmbientOcclusionNode's range
           },
           "samples per pixel, 8..64 (default 32)")
        ->type_name("M")
        ->group(group);
    cli.add_option_function<std::string>(
           "--ao-radius", [&o](const std::string& v) { o.aoParameters.radius = real("--ao-radius", v); },
           "kernel radius in metres (default 0.5)")
        ->type_name("R")
        ->group(group);
    cli.add_flag_callback(
           "--ao-half", [&o] { o.aoParameters.halfResolution = true; },
           "compute the occlusion at half resolution")
        ->group(group);
    cli.add_flag_callback(
           "--ao-temporal", [&o] { o.aoParameters.temporal = true; },
           "half resolution, 8 taps a frame accumulated over frames")
        ->group(group);
    cli.add_option_function<std::string>(
           "--ao-normals",
           [&o](const std::string& v) {
               o.aoParameters.normals = choice<sgfx::AoNormals>(
                   "--ao-normals", v,
                   {{"gbuffer", sgfx::AoNormals::GBuffer}, {"depth", sgfx::AoNormals::FromDepth}},
                   "gbuffer or depth");
           },
           "normals from a G-buffer pre-pass (default) or rebuilt from the depth pre-pass")
        ->type_name("gbuffer|depth")
        ->group(group);
    cli.add_option_function<std::string>(
           "--ao-debug",
           [&o](const std::string& v) {
               o.aoParameters.debugView = choice<sgfx::AoDebugView>(
                   "--ao-debug", v,
                   {{"raw", sgfx::AoDebugView::Raw}, {"blurred", sgfx::AoDebugView::Blurred}},
                   "raw or blurred");
           },
           "show the occlusion map instead of the scene")
        ->type_name("raw|blurred")
        ->group(group);
}

// Rain, the sky and the environment light.
void addSkyOptions(CLI::App& cli, Options& o) {
    const char* group = "effects";
    cli.add_flag(
           "--rain", o.rain,
           "rain: GPU particles (streaked tetrahedra) falling from 20 m above the camera over an 80 x 80 m "
           "area that follows it, lit and fogged with the scene")
        ->group(group);
    cli.add_option_function<std::string>(
           "--rain-count",
           [&o](const std::string& v) {
               o.rainCount =
                   integer<std::uint32_t>("--rain-count", v, 1, sgfx::ParticleSystemNode::kMaxCapacity);
           },
           "raindrops, 1..16777216 (default 200000)")
        ->type_name("N")
        ->group(group);
    cli.add_option_function<std::string>(
           "--sky", [&o](const std::string& v) { o.skyHours = float(demo::number("--sky", v, 0, 24)); },
           "a physically based sky (Rayleigh and Mie scattering) at local solar time HOURS (0..24, latitude "
           "45°, midsummer); the scene's sun follows it and the fog takes the sky's horizon colour")
        ->type_name("HOURS")
        ->group(group);
    cli.add_flag("--sky-direct", o.skyDirect, "integrate the sky per pixel instead of through its view table")
        ->group(group);
    cli.add_option_function<std::string>(
           "--env",
           [&o](const std::string& v) { o.env = v == "none" ? std::nullopt : std::optional<std::string>(v); },
           "image-based light instead of the flat sky ambient: the sky's (--sky's, or one for the scene's "
           "sun "
           "when the sky is not drawn) or a panorama file (.hdr, .png, .jpg, twice as wide as high, Z up); "
           "default none")
        ->type_name("sky|none|FILE")
        ->group(group);
    cli.add_option_function<std::string>(
           "--env-intensity",
           [&o](const std::string& v) { o.envIntensity = float(demo::number("--env-intensity", v, 0, 1e6)); },
           "scales the environment's light (default 1)")
        ->type_name("X")
        ->group(group);
}

// The smoke cloud and the Gaussian splats; the volume's validate() checks the numbers.
void addVolumeOptions(CLI::App& cli, Options& o) {
    const char* group = "effects";
    cli.add_flag(
           "--smoke", o.smoke,
           "a raymarched smoke cloud (noise density, single scattering of the sun) over the road ahead of "
           "the camera")
        ->group(group);
    cli.add_option_function<std::string>(
           "--volume-steps",
           [&o](const std::string& v) {
               o.volume.steps = integer("--volume-steps", v, 1, 4096); // VolumeNode's range
           },
           "raymarch steps per ray, 1..4096 (default 64)")
        ->type_name("N")
        ->group(group);
    cli.add_flag_callback(
           "--volume-half", [&o] { o.volume.halfResolution = true; },
           "march the smoke at half resolution (depth-aware upsample)")
        ->group(group);
    cli.add_option_function<std::string>(
           "--volume-skip",
           [&o](const std::string& v) { o.volume.emptySpaceSkipping = onOff("--volume-skip", v); },
           "empty-space skipping (default off)")
        ->type_name("on|off")
        ->group(group);
    cli.add_flag_callback(
           "--volume-jitter", [&o] { o.volume.jitter = true; },
           "random start per pixel (noise instead of banding)")
        ->group(group);
    cli.add_option_function<std::string>(
           "--volume-slices",
           [&o](const std::string& v) {
               o.volume.slices = integer("--volume-slices", v, 2, 4096);
               o.volume.method = sgfx::VolumeMethod::Slicing;
           },
           "draw the smoke by slicing with N view-aligned slices instead, 2..4096")
        ->type_name("N")
        ->group(group);
    cli.add_option_function<std::string>(
           "--volume-splats",
           [&o](const std::string& v) {
               o.volume.splatSpacing = real("--volume-splats", v);
               o.volume.method = sgfx::VolumeMethod::Splatting;
           },
           "draw the smoke by splatting: Gaussian kernels M metres apart, sorted back to front each frame, "
           "instead")
        ->type_name("M")
        ->group(group);
    cli.add_option(
           "--splats", o.splats,
           "a 3D Gaussian splatting .ply (bench/splat_bench --write makes one) over the road ahead of the "
           "camera, scaled to 6 m across")
        ->type_name("FILE")
        ->group(group);
    cli.add_option_function<std::string>(
           "--splat-sort",
           [&o](const std::string& v) {
               o.splatSort = choice<sgfx::SplatSort>(
                   "--splat-sort", v, {{"gpu", sgfx::SplatSort::Gpu}, {"cpu", sgfx::SplatSort::Cpu}},
                   "gpu or cpu");
           },
           "the splats' depth sort every frame (default gpu: compute radix sort)")
        ->type_name("gpu|cpu")
        ->group(group);
}

// The sun's shadows; ShadowOptions::validate() checks them together after the parse.
void addShadowOptions(CLI::App& cli, Options& o) {
    const char* group = "effects";
    cli.add_option_function<std::string>(
           "--shadows", [&o](const std::string& v) { o.shadows = onOff("--shadows", v); },
           "cascaded sun shadow maps: the scene's sun (--sky's) shadows the scene (rain and smoke cast "
           "none); "
           "the terrain only receives while the sun is above 30 degrees, where its low hills throw no shadow "
           "worth drawing (default off)")
        ->type_name("on|off")
        ->group(group);
    cli.add_option_function<std::string>(
           "--shadow-cascades",
           [&o](const std::string& v) { o.shadow.cascades = integer("--shadow-cascades", v, 1, 4); },
           "maps along the view, 1..4 (default 3)")
        ->type_name("N")
        ->group(group);
    cli.add_option_function<std::string>(
           "--shadow-filter",
           [&o](const std::string& v) {
               o.shadow.filter = choice<sgfx::ShadowFilter>("--shadow-filter", v,
                                                            {{"hard", sgfx::ShadowFilter::Hard2x2},
                                                             {"pcf", sgfx::ShadowFilter::Pcf},
                                                             {"pcss", sgfx::ShadowFilter::Pcss}},
                                                            "hard, pcf or pcss");
           },
           "one hardware comparison, bilinear over 2x2 texels (hard), a rotated 16-tap Poisson disc (pcf, "
           "default), or soft penumbrae that widen with the blocker's distance (pcss: the sun's angular "
           "size)")
        ->type_name("hard|pcf|pcss")
        ->group(group);
    cli.add_option_function<std::string>(
           "--shadow-map",
           [&o](const std::string& v) {
               o.shadow.mapSize = integer("--shadow-map", v, 256, 4096);
               if (o.shadow.mapSize % 64 != 0)
                   throw CLI::ValidationError("--shadow-map", "'" + v + "' is not a multiple of 64");
           },
           "texels per side of each cascade's map, 256..4096, a multiple of 64 (default 2048)")
        ->type_name("N")
        ->group(group);
    cli.add_option_function<std::string>(
           "--shadow-distance",
           [&o](const std::string& v) {
               o.shadow.maxDistance = real("--shadow-distance", v);
               if (!(o.shadow.maxDistance > 0.0f && o.shadow.maxDistance <= 1e6f))
                   throw CLI::ValidationError("--shadow-distance", "'" + v + "': M must be in (0, 1e6]");
           },
           "metres of view depth shadowed, 0 < M <= 1e6 (default 200)")
        ->type_name("M")
        ->group(group);
    cli.add_option_function<std::string>(
           "--shadow-debug",
           [&o](const std::string& v) {
               if (v != "cascades")
                   throw CLI::ValidationError("--shadow-debug", "'" + v + "' is not cascades");
               o.shadow.debugView = sgfx::ShadowDebugView::Cascades;
           },
           "tint each pixel by the cascade that shades it (red, green, blue, yellow)")
        ->type_name("cascades")
        ->group(group);
}

// The checks across options and of each effect's parameters together, after the parse.
void checkOptions(const Options& o, int modes) {
    if (modes > 1)
        demo::usageError("--window, --bench, --export-obj and --export-gltf are mutually exclusive");
    if (!o.osgView.empty() && o.mode != Mode::Still) demo::usageError("--osg-view: only for the still image");
    auto check = [](const char* options, auto&& validate) {
        try {
            validate();
        } catch (const std::invalid_argument& e) {
            demo::usageError(std::string(options) + ": " + e.what());
        }
    };
    check("--fog-*", [&] { o.fogParameters.validate(); });
    check("--ao-*", [&] { o.aoParameters.validate(); });
    check("--volume-*", [&] { o.volume.validate(); });
    check("--shadow-*", [&] { o.shadow.validate(); });
}

// Returns -1 when the program goes on, else its exit status (0 after --help, 2 for bad options).
int parseArgs(int argc, char** argv, Options& o) {
    CLI::App cli{kDescription, "polygon"};
    cli.footer("exit status: 0 on success, 1 on a runtime error, 2 on a bad option or value");
    demo::lastValueWins(cli);
    int modes = 0;
    addModeOptions(cli, o, modes);
    addImageOptions(cli, o);
    addSceneOptions(cli, o);
    addFogOptions(cli, o);
    addAoOptions(cli, o);
    addSkyOptions(cli, o);
    addVolumeOptions(cli, o);
    addShadowOptions(cli, o);
    return demo::parse(cli, argc, argv, [&] { checkOptions(o, modes); });
}

polygon::CameraPose startPose(const Options& o, float t);

// Rain over an area that follows `camera` (the drops already falling stay where they are).
// 200,000 drops (--rain-count) over 80 x 80 m, 20 m above the eye, reaching the lowest ground (z = -10).
sgfx::NodePtr withRain(const Options& o, sgfx::NodePtr world, std::shared_ptr<const sgfx::Camera> camera) {
    if (!o.rain) return world;
    return polygon::withRainFollowing(std::move(world), std::move(camera), 80.0f, o.rainCount, 20.0f, -10.0f);
}

// --shadows on: a ShadowNode (nothing below it yet) shadowing the scene's light "sun", the object
// --sky turns, so the shadows follow it; nullptr when off. The lever (docs/plans/shadows.md §10):
// while the sun is above 30° the terrain's low hills (8 m at most) throw no shadow worth drawing
// the whole ground into every cascade for, so the terrain only receives; lower, it casts too.
std::shared_ptr<sgfx::ShadowNode> shadowNode(const Options& o, const polygon::PolygonScene& scene) {
    if (!o.shadows) return nullptr;
    std::shared_ptr<sgfx::Light> sun;
    for (const auto& child : scene.root->children())
        if (auto light = std::dynamic_pointer_cast<sgfx::Light>(child); light && light->name == "sun")
            sun = light;
    if (!sun) throw std::runtime_error("--shadows: the scene has no light named 'sun'");
    const float sunElevation = std::asin(std::clamp(-glm::normalize(sun->direction).z, -1.0f, 1.0f));
    if (sunElevation > glm::radians(30.0f))
        scene.terrain->nodeMask &= ~sgfx::shadow::kCasts;
    else
        scene.terrain->nodeMask |= sgfx::shadow::kCasts;
    auto node = sgfx::ShadowNode::create(std::move(sun), o.shadow);
    node->name = "shadows";
    return node;
}

// `world` below --shadows' node (or itself without).
sgfx::NodePtr withShadows(const Options& o, sgfx::NodePtr world, const polygon::PolygonScene& scene) {
    auto shadows = shadowNode(o, scene);
    if (!shadows) return world;
    shadows->addChild(std::move(world));
    return shadows;
}

// --splats: the cloud over the road ahead of the start pose, 6 m across, resting on the ground;
// a transparent item like glass (ordered by its bound's centre), fogged by the fog above it.
sgfx::NodePtr placedSplats(const Options& o) {
    auto splats = sgfx::GaussianSplatNode::load(*o.splats);
    splats->setSort(o.splatSort);
    const sgfx::BoundingSphere b = splats->bound();
    const float scale = b.radius > 0.0f ? 3.0f / b.radius : 1.0f;
    const polygon::CameraPose pose = startPose(o, o.time);
    glm::vec3 at = pose.eye + 12.0f * glm::normalize(pose.target - pose.eye);
    at.z = std::max(at.z, 3.0f);
    auto place = sgfx::Transform::create(glm::scale(glm::translate(glm::mat4(1.0f), at), glm::vec3(scale)) *
                                         glm::translate(glm::mat4(1.0f), -b.center));
    place->addChild(splats);
    return place;
}

// The sky (its sun becomes the scene's), a smoke cloud over the road ahead of the start pose and
// --shadows' node over the world and the smoke (the sky beside it: it neither casts nor receives).
sgfx::NodePtr withSkySmokeAndShadows(const Options& o, sgfx::NodePtr world,
                                     const polygon::PolygonScene& scene,
                                     std::shared_ptr<sgfx::SkyNode>& sky) {
    glm::vec3 toSun(0.0f);
    for (const auto& child : scene.root->children())
        if (auto* sun = dynamic_cast<sgfx::Light*>(child.get()); sun && sun->name == "sun") {
            if (o.skyHours) sun->direction = -sgfx::sky::sunDirection(*o.skyHours);
            toSun = -glm::normalize(sun->direction);
        }
    if (!o.skyHours && !o.smoke && !o.splats) return withShadows(o, std::move(world), scene);
    auto group = sgfx::Group::create();
    const std::shared_ptr<sgfx::ShadowNode> shadows = shadowNode(o, scene);
    sgfx::Group& shadowed = shadows ? *shadows : *group; // where the world and the smoke go
    shadowed.addChild(world);
    if (shadows) group->addChild(shadows);
    if (o.skyHours) {
        sgfx::SkyParameters sp = sgfx::SkyParameters::atTime(*o.skyHours);
        sp.lookupTable = !o.skyDirect;
        sky = sgfx::SkyNode::create(sp);
        group->addChild(sky);
    }
    if (o.smoke) {
        sgfx::VolumeParameters vp = o.volume;
        vp.lightDirection = -toSun;
        const polygon::CameraPose pose = startPose(o, o.time);
        glm::vec3 at = pose.eye + 0.6f * (pose.target - pose.eye);
        at.z = std::max(at.z, 0.0f) + 0.5f * vp.size.z;
        auto place = sgfx::Transform::create(glm::translate(glm::mat4(1.0f), at));
        place->addChild(sgfx::VolumeNode::create(vp, sgfx::VolumeGrid::noise(64, 7, 4, 0.35f)));
        shadowed.addChild(place);
    }
    if (o.splats) group->addChild(placedSplats(o));
    return group;
}

// --env: image-based light in place of the flat sky ambient light (which would light twice).
sgfx::NodePtr withEnvironment(const Options& o, sgfx::NodePtr world, const polygon::PolygonScene& scene,
                              std::shared_ptr<sgfx::SkyNode> sky) {
    if (!o.env) return world;
    glm::vec3 toSun(0.0f, 0.0f, 1.0f);
    for (const auto& child : scene.root->children())
        if (auto* light = dynamic_cast<sgfx::Light*>(child.get())) {
            if (light->name == "sun") toSun = -glm::normalize(light->direction);
            if (light->name == "sky_ambient") light->color = glm::vec3(0.0f);
        }
    std::shared_ptr<sgfx::EnvironmentLightNode> env;
    if (*o.env == "sky") {
        if (!sky) { // the sky's light, not drawn: the one of the scene's sun
            sgfx::SkyParameters sp;
            sp.sunDirection = toSun;
            sky = sgfx::SkyNode::create(sp);
        }
        env = sgfx::EnvironmentLightNode::create(std::shared_ptr<const sgfx::SkyNode>(sky), o.envIntensity);
    } else {
        env = sgfx::EnvironmentLightNode::create(sgfx::Environment::load(*o.env), o.envIntensity);
    }
    env->addChild(std::move(world));
    return env;
}

// The scene with the chosen effects around it.
sgfx::NodePtr sceneWithEffects(const Options& o, const polygon::PolygonScene& scene,
                               std::shared_ptr<const sgfx::Camera> camera) {
    scene.glassBin->setMode(o.transparency);
    std::shared_ptr<sgfx::SkyNode> sky;
    sgfx::NodePtr world = withSkySmokeAndShadows(o, withRain(o, scene.root, std::move(camera)), scene, sky);
    world = withEnvironment(o, std::move(world), scene, sky);
    if (o.aoFloor) {
        auto ao = polygon::AoFloorNode::create();
        ao->addChild(world);
        world = ao;
    } else if (o.ao) {
        auto ao = sgfx::AmbientOcclusionNode::create(o.aoParameters);
        ao->addChild(world);
        world = ao;
    }
    if (!o.fog) return world;
    auto fog = sgfx::FogNode::create(o.fogParameters, *o.fog);
    fog->setDeferOpaque(o.fogDeferOpaque); // --fog deferred
    fog->addChild(world);
    if (sky) sky->attachFog(fog); // aerial perspective: distant geometry fades into the sky
    return fog;
}

std::unique_ptr<sgfx::Viewer> makeHeadlessViewer(const Options& o) {
    auto viewer = sgfx::Viewer::createHeadless(
        o.width, o.height, o.egl ? sgfx::Viewer::Headless::Egl : sgfx::Viewer::Headless::Default);
    viewer->renderer().options().lighting = o.lighting;
    viewer->renderer().options().autoInstancing = o.autoInstancing;
    viewer->renderer().options().submitTriangles = o.submitTriangles;
    viewer->renderer().options().submitsPerFrame = o.submitsPerFrame;
    viewer->renderer().options().countFragments = o.countFragments;
    viewer->renderer().options().colorTarget = o.colorTarget;
    viewer->camera()->setAntiAliasing(o.aa);
    return viewer;
}

polygon::CameraPose startPose(const Options& o, float t) {
    return o.look ? *o.look : polygon::cameraPose(t, kExtent);
}

void setupCamera(const Options& o, sgfx::Viewer& viewer, const polygon::CameraPose& pose) {
    auto& cam = *viewer.camera();
    cam.clearColor = o.lamps ? kDuskColor : kSkyColor;
    cam.setPerspective(polygon::kPathFovyDegrees, polygon::kPathNear, polygon::kPathFar);
    cam.setLookAt(pose.eye, pose.target, pose.up);
    if (o.channelsX * o.channelsY == 1) return;
    // The camera's frustum cut into a wall of channels (docs/multi-view.md).
    const int w = o.width / o.channelsX, h = o.height / o.channelsY;
    sgfx::OffAxisFrustum whole;
    whole.zNear = polygon::kPathNear;
    whole.zFar = polygon::kPathFar;
    whole.top = whole.zNear * std::tan(glm::radians(polygon::kPathFovyDegrees) / 2.0f);
    whole.bottom = -whole.top;
    whole.right = whole.top * float(w * o.channelsX) / float(h * o.channelsY);
    whole.left = -whole.right;
    std::vector<sgfx::DisplayChannel> channels;
    for (int r = 0; r < o.channelsY; ++r)
        for (int c = 0; c < o.channelsX; ++c)
            channels.push_back({"c" + std::to_string(c) + "r" + std::to_string(r), glm::mat4(1.0f),
                                whole.sub(double(c) / o.channelsX, double(c + 1) / o.channelsX,
                                          double(r) / o.channelsY, double(r + 1) / o.channelsY),
                                sgfx::Viewport{c * w, r * h, w, h}});
    viewer.setChannels(std::move(channels));
}

// GL errors are library problems worth seeing, not something to hide.
void reportGlErrors(sgfx::Viewer& viewer) {
    for (const std::string& e : viewer.renderer().takeGlErrors())
        std::cerr << "polygon: GL: " << e << "\n";
}

// --osg-view: the still image through an OSG spherical display, from the same eye.
int runOsgView(const Options& o, const polygon::PolygonScene& scene) {
    const sgfx::OsgViewConfig config = sgfx::loadOsgView(o.osgView);
    auto viewer = makeHeadlessViewer(o);
    sgfx::SphericalDisplaySetup setup;
    setup.width = o.width;
    setup.height = o.height;
    setup.zNear = polygon::kPathNear;
    setup.zFar = polygon::kPathFar;
    auto rig = sgfx::SphericalDisplayRig::create(config.spherical, setup,
                                                 sceneWithEffects(o, scene, viewer->camera()));
    const polygon::CameraPose pose = startPose(o, o.time);
    rig->setEyeView(glm::lookAt(pose.eye, pose.target, pose.up));
    for (const auto& face : rig->faces())
        face->clearColor = o.lamps ? kDuskColor : kSkyColor;
    rig->configureOutputCamera(*viewer->camera());
    viewer->setSceneData(rig->root());
    viewer->frame(); // the first frame compiles the programs: the second one is timed
    const auto t0 = std::chrono::steady_clock::now();
    viewer->frame();
    viewer->capture();
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    viewer->writeScreenshot(o.out);
    reportGlErrors(*viewer);
    std::cout << "wrote " << o.out << " (" << o.osgView << ": "
              << (config.spherical.kind == sgfx::SphericalDisplayKind::Panoramic ? "panoramic" : "3D")
              << " spherical display, " << o.width << "x" << o.height << ", six " << setup.faceSize
              << "² faces; second frame " << ms << " ms)\n";
    return 0;
}

int runStill(const Options& o, const polygon::PolygonScene& scene) {
    if (!o.osgView.empty() && sgfx::loadOsgView(o.osgView).kind == sgfx::OsgViewConfig::Kind::Spherical)
        return runOsgView(o, scene);
    auto viewer = makeHeadlessViewer(o);
    setupCamera(o, *viewer, startPose(o, o.time));
    viewer->setSceneData(sceneWithEffects(o, scene, viewer->camera()));
    const bool temporal =
        o.aa.mode == sgfx::AntiAliasing::Mode::Taa || o.aa.mode == sgfx::AntiAliasing::Mode::SmaaT2x;
    const int frames = temporal ? 16 : 1; // TAA's (and SMAA T2x's) history fills
    for (int i = 0; i < frames; ++i)
        viewer->frame();
    if (o.crop) {
        const auto [cx, cy, cw, ch, zoom] = *o.crop;
        const sgfx::Image full = viewer->capture();
        if (cx + cw > full.width || cy + ch > full.height)
            throw UsageError("--crop: the region leaves the " + std::to_string(full.width) + "x" +
                             std::to_string(full.height) + " image");
        sgfx::Image out;
        out.width = cw * zoom;
        out.height = ch * zoom;
        out.channels = 4;
        out.pixels.resize(std::size_t(out.width) * out.height * 4);
        for (int y = 0; y < out.height; ++y)
            for (int x = 0; x < out.width; ++x)
                std::copy_n(full.pixel(cx + x / zoom, cy + y / zoom), 4, out.pixel(x, y));
        sgfx::writePng(o.out, out);
        std::cout << "wrote " << o.out << " (" << out.width << "x" << out.height << ", a crop of " << o.width
                  << "x" << o.height << ")\n";
        reportGlErrors(*viewer);
        return 0;
    }
    viewer->writeScreenshot(o.out);
    reportGlErrors(*viewer);
    if (!o.graph.empty()) {
        std::ofstream dot(o.graph);
        dot << viewer->renderer().lastFrameGraphDot();
        if (!dot) throw std::runtime_error("cannot write " + o.graph);
        std::cout << "wrote " << o.graph << " (frame-graph textures held: "
                  << double(viewer->renderer().renderTargetBytes()) / (1024.0 * 1024.0) << " MiB)\n";
    }
    const sgfx::FrameStats& st = viewer->stats();
    std::cout << "frame: " << st.triangles << " triangles drawn, " << st.drawCalls << " draw calls, "
              << st.culledNodes << " nodes culled (" << viewer->context().kind() << ", "
              << viewer->context().renderer() << ")\n";
    std::cout << "wrote " << o.out << " (" << o.width << "x" << o.height << ")\n";
    return 0;
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

int runBench(const Options& o, const polygon::PolygonScene& scene, std::size_t sceneTriangles) {
    using clock = std::chrono::steady_clock;
    auto viewer = makeHeadlessViewer(o);
    setupCamera(o, *viewer, polygon::cameraPose(0.0f, kExtent));
    viewer->setSceneData(sceneWithEffects(o, scene, viewer->camera()));
    for (int i = 0; i < 3; ++i) {
        viewer->frame();
        glFinish();
    }
    reportGlErrors(*viewer);

    const int n = o.benchFrames;
    std::vector<double> ms;
    ms.reserve(std::size_t(n));
    double triangles = 0, drawCalls = 0, stateChanges = 0, programChanges = 0, culled = 0, cullMs = 0,
           drawMs = 0, fragments = 0;
    viewer->renderer().options().timePasses = true;     // GPU time per pass from timer queries
    std::vector<std::pair<std::string, double>> passMs; // summed over the frames, in frame order
    for (int i = 0; i < n; ++i) {
        // With --look every frame is from that pose (the cost of what it sees), else the path.
        const polygon::CameraPose pose = o.look ? *o.look : polygon::cameraPose(float(i) / float(n), kExtent);
        viewer->camera()->setLookAt(pose.eye, pose.target, pose.up);
        const auto t0 = clock::now();
        viewer->frame();
        glFinish();
        const auto t1 = clock::now();
        ms.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
        const sgfx::FrameStats& st = viewer->stats();
        triangles += double(st.triangles);
        drawCalls += double(st.drawCalls);
        stateChanges += double(st.stateChanges);
        programChanges += double(st.programChanges);
        culled += double(st.culledNodes);
        cullMs += st.cullMs;
        drawMs += st.drawMs;
        fragments += double(st.fragments);
        for (const auto& pt : st.passTimes) {
            auto it =
                std::find_if(passMs.begin(), passMs.end(), [&](const auto& e) { return e.first == pt.name; });
            if (it == passMs.end())
                passMs.emplace_back(pt.name, pt.gpuMs);
            else
                it->second += pt.gpuMs;
        }
    }
    reportGlErrors(*viewer);
    const double dn = double(n);
    const double mean = std::accumulate(ms.begin(), ms.end(), 0.0) / dn;
    const double med = median(ms);
    const double fps = 1000.0 / mean;
    const auto [mn, mx] = std::minmax_element(ms.begin(), ms.end());
    std::printf("bench: %d frames at %dx%d on %.*s (%s)\n", n, o.width, o.height,
                int(viewer->context().kind().size()), viewer->context().kind().data(),
                viewer->context().renderer().c_str());
    std::printf("  ms/frame         mean %.2f  median %.2f  min %.2f  max %.2f\n", mean, med, *mn, *mx);
    std::printf("  fps              %.2f\n", fps);
    std::printf(
        "  per frame (mean) triangles %.0f  draw calls %.1f  state changes %.1f  program changes %.1f\n",
        triangles / dn, drawCalls / dn, stateChanges / dn, programChanges / dn);
    std::printf("                   culled nodes %.1f  cull %.2f ms  draw submit %.2f ms (CPU)\n",
                culled / dn, cullMs / dn, drawMs / dn);
    std::printf("  scene            %zu triangles\n", sceneTriangles);
    std::printf("  GPU ms per pass  ");
    for (const auto& [name, total] : passMs)
        std::printf("%s %.2f  ", name.c_str(), total / dn);
    std::printf("\n");
    if (o.countFragments)
        std::printf("  fragments        %.0f passed depth per frame = %.2f per pixel\n", fragments / dn,
                    fragments / dn / (double(o.width) * o.height));
    std::printf(
        "BENCH sgfx ms_per_frame=%.3f fps=%.2f triangles=%.0f draw_calls=%.1f state_changes=%.1f "
        "program_changes=%.1f median_ms=%.3f cull_ms=%.3f scene_triangles=%zu size=%dx%d context=%.*s\n",
        mean, fps, triangles / dn, drawCalls / dn, stateChanges / dn, programChanges / dn, med, cullMs / dn,
        sceneTriangles, o.width, o.height, int(viewer->context().kind().size()),
        viewer->context().kind().data());
    std::printf("PASSES");
    for (const auto& [name, total] : passMs) {
        std::string key = name;
        std::replace_if(
            key.begin(), key.end(), [](char c) { return c == ' ' || c == ':'; }, '_');
        std::printf(" %s=%.3f", key.c_str(), total / dn);
    }
    std::printf("\n");
    return 0;
}

// Interactive fly camera: WASD in the view direction, Q/E vertical, left-drag to look.
int runWindow(const Options& o, const polygon::PolygonScene& scene) {
    std::unique_ptr<sgfx::GlfwWindow> window;
    try {
        window = std::make_unique<sgfx::GlfwWindow>(o.width, o.height, "sgfx polygon");
    } catch (const sgfx::ContextError& e) {
        std::cerr << "polygon: " << e.what() << "\n";
        std::cout << "no display: rendering headless" << std::endl;
        return runStill(o, scene);
    }
    GLFWwindow* win = window->handle();
    sgfx::Viewer viewer(std::move(window));
    viewer.renderer().options().lighting = o.lighting;
    viewer.renderer().options().autoInstancing = o.autoInstancing;
    viewer.renderer().options().submitTriangles = o.submitTriangles;
    viewer.renderer().options().submitsPerFrame = o.submitsPerFrame;
    viewer.renderer().options().colorTarget = o.colorTarget;
    viewer.camera()->setAntiAliasing(o.aa);
    setupCamera(o, viewer, startPose(o, o.time));
    // Fog is always in the graph here so F can cycle it: off, forward, split, post.
    auto fog = sgfx::FogNode::create(o.fogParameters, o.fog.value_or(sgfx::FogMode::Forward));
    fog->setDeferOpaque(o.fogDeferOpaque);
    fog->enabled = o.fog.has_value();
    fog->addChild(withShadows(o, withRain(o, scene.root, viewer.camera()), scene));
    viewer.setSceneData(fog);
    scene.glassBin->setMode(o.transparency);
    bool fogKeyDown = false, transparencyKeyDown = false, aaKeyDown = false;
    const polygon::Terrain terrain(o.seed);

    const polygon::CameraPose start = startPose(o, o.time);
    sgfx::FlyManipulator fly; // the library's: left drag looks, WASD along the view, Q/E down/up
    fly.setLookAt(start.eye, start.target);
    fly.speed = 20.0f; // m/s; Shift: 80
    double lastX = 0, lastY = 0;
    bool dragging = false;
    double last = glfwGetTime(), titleTime = last;
    int frames = 0;
    std::cout << "window: WASD move, Q/E down/up, Shift fast, left mouse drag to look, F cycles the fog "
                 "mode, T switches sorted/OIT glass, M cycles anti-aliasing, Esc quits"
              << std::endl;

    long total = 0;
    while (!viewer.context().shouldClose() && (o.windowFrames == 0 || total < o.windowFrames)) {
        glfwPollEvents();
        const double now = glfwGetTime();
        const float dt = float(std::min(now - last, 0.1));
        last = now;
        if (glfwGetKey(win, GLFW_KEY_ESCAPE) == GLFW_PRESS) glfwSetWindowShouldClose(win, GLFW_TRUE);
        const bool fogKey = glfwGetKey(win, GLFW_KEY_F) == GLFW_PRESS;
        if (fogKey && !fogKeyDown) { // off → forward → split → post → off
            if (!fog->enabled) {
                fog->enabled = true;
                fog->setMode(sgfx::FogMode::Forward);
            } else if (fog->mode() == sgfx::FogMode::PostProcess) {
                fog->enabled = false;
            } else {
                fog->setMode(sgfx::FogMode(int(fog->mode()) + 1));
            }
        }
        fogKeyDown = fogKey;
        const bool transparencyKey = glfwGetKey(win, GLFW_KEY_T) == GLFW_PRESS;
        if (transparencyKey && !transparencyKeyDown)
            scene.glassBin->setMode(scene.glassBin->mode() == sgfx::TransparencyMode::Sorted
                                        ? sgfx::TransparencyMode::WeightedBlended
                                        : sgfx::TransparencyMode::Sorted);
        transparencyKeyDown = transparencyKey;
        const bool aaKey = glfwGetKey(win, GLFW_KEY_M) == GLFW_PRESS;
        if (aaKey && !aaKeyDown) { // none → MSAA 4× → SSAA 2× → FXAA → TAA → SMAA → SMAA T2x → none
            using M = sgfx::AntiAliasing::Mode;
            static const sgfx::AntiAliasing cycle[] = {
                sgfx::AntiAliasing::none(),   sgfx::AntiAliasing::msaa(4), sgfx::AntiAliasing::ssaa(2),
                sgfx::AntiAliasing::fxaa(),   sgfx::AntiAliasing::taa(),   sgfx::AntiAliasing::smaa(),
                sgfx::AntiAliasing::smaaT2x()};
            const M current = viewer.camera()->antiAliasing().mode;
            viewer.camera()->setAntiAliasing(cycle[(std::size_t(current) + 1) % std::size(cycle)]);
        }
        aaKeyDown = aaKey;

        double x = 0, y = 0;
        glfwGetCursorPos(win, &x, &y);
        const bool held = glfwGetMouseButton(win, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS;
        if (held && dragging)
            fly.drag(sgfx::MouseButton::Left, {float(x - lastX), float(y - lastY)},
                     float(viewer.camera()->viewport.height));
        dragging = held;
        lastX = x;
        lastY = y;
        auto key = [&](int k) { return glfwGetKey(win, k) == GLFW_PRESS ? 1.0f : 0.0f; };
        fly.move({key(GLFW_KEY_D) - key(GLFW_KEY_A), key(GLFW_KEY_W) - key(GLFW_KEY_S),
                  key(GLFW_KEY_E) - key(GLFW_KEY_Q)},
                 dt, key(GLFW_KEY_LEFT_SHIFT) + key(GLFW_KEY_RIGHT_SHIFT) > 0.0f);
        fly.position.z = std::max(fly.position.z, terrain.height(fly.position.x, fly.position.y) + 1.5f);
        fly.apply(*viewer.camera());

        viewer.frame(dt);
        reportGlErrors(viewer);
        ++frames;
        ++total;
        if (now - titleTime >= 1.0) {
            const std::string title =
                "sgfx polygon - " + std::to_string(int(std::lround(frames / (now - titleTime)))) + " fps, " +
                std::to_string(viewer.stats().triangles) + " triangles, fog " +
                (!fog->enabled                                ? "off"
                 : fog->mode() == sgfx::FogMode::Forward      ? "forward"
                 : fog->mode() == sgfx::FogMode::ForwardSplit ? "split"
                                                              : "post") +
                ", glass " + (scene.glassBin->mode() == sgfx::TransparencyMode::Sorted ? "sorted" : "OIT") +
                ", AA " +
                std::array{"none", "MSAA 4x", "SSAA 2x", "FXAA", "TAA", "SMAA", "SMAA T2x"}[std::size_t(
                    viewer.camera()->antiAliasing().mode)];
            glfwSetWindowTitle(win, title.c_str());
            titleTime = now;
            frames = 0;
        }
    }
    std::cout << "window: " << total << " frames" << std::endl;
    return 0;
}

int runMode(const Options& o, const polygon::PolygonScene& scene, std::size_t sceneTriangles) {
    switch (o.mode) {
    case Mode::ExportObj: {
        const sgfx::ObjWriteResult r = sgfx::writeObj(*scene.root, o.objPath);
        std::printf("wrote %s: %zu objects, %zu vertices, %zu triangles\n", o.objPath.c_str(), r.objects,
                    r.vertices, r.triangles);
        return 0;
    }
    case Mode::ExportGltf: {
        const sgfx::GltfWriteResult r = sgfx::writeGltf(*scene.root, o.gltfPath);
        std::printf("wrote %s: %zu meshes, %zu materials, %zu vertices, %zu triangles\n", o.gltfPath.c_str(),
                    r.meshes, r.materials, r.vertices, r.triangles);
        return 0;
    }
    case Mode::Bench:
        return runBench(o, scene, sceneTriangles);
    case Mode::Window:
        return runWindow(o, scene);
    case Mode::Still:
        return runStill(o, scene);
    }
    return 0;
}

int run(const Options& o) {
    const auto t0 = std::chrono::steady_clock::now();
    polygon::PolygonScene scene = polygon::buildPolygonScene(
        // Exports hold the full detail without the levels' skirts: what --no-lod renders.
        {kExtent, o.scale, o.seed, o.lod && o.mode != Mode::ExportObj && o.mode != Mode::ExportGltf,
         o.manyDrawables});
    if (o.lamps) polygon::addDuskAndStreetLamps(scene, *o.lamps, o.seed);
    const double buildMs =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    sgfx::StatsVisitor stats;
    scene.root->accept(stats);
    const polygon::SceneInfo& info = scene.info;
    std::printf("scene: %zu triangles, %zu vertices, %zu drawables, %zu nodes (scale %g, seed %llu, built in "
                "%.0f ms)\n",
                stats.triangles, stats.vertices, stats.drawables, stats.nodes, double(o.scale),
                static_cast<unsigned long long>(o.seed), buildMs);
    std::printf(
        "       %d terrain tiles of %dx%d cells, %d road pieces, %d buildings from %d prototypes, %d trees\n",
        info.terrainTiles, info.terrainCellsPerTile, info.terrainCellsPerTile, info.roadPieces,
        info.buildings, info.buildingPrototypes, info.trees);
    {
        auto triangles = [](const std::shared_ptr<sgfx::Group>& g) {
            sgfx::StatsVisitor v;
            g->accept(v);
            return v.triangles;
        };
        std::printf(
            "       triangles: terrain %zu, roads %zu, buildings %zu, trees %zu, vehicle and glass %zu\n",
            triangles(scene.terrain), triangles(scene.roads), triangles(scene.buildings),
            triangles(scene.trees), triangles(scene.vehicle) + triangles(scene.glass));
    }
    if (info.buildings < info.buildingsRequested || info.trees < info.treesRequested)
        std::printf("       (the ground is full: placed %d of %d buildings, %d of %d trees)\n",
                    info.buildings, info.buildingsRequested, info.trees, info.treesRequested);
    std::fflush(stdout);

    const bool exporting = o.mode == Mode::ExportObj || o.mode == Mode::ExportGltf;
    if (!exporting && o.drive.value_or(o.mode != Mode::Bench)) {
        const polygon::DriveRoute route = polygon::provingGroundRoute();
        const auto drive = polygon::driveVehicle(scene, route);
        std::printf("vehicle: drives a %.0f m loop at %.0f m/s, %zu ground queries a frame\n", route.length(),
                    polygon::DriveOptions{}.speed, polygon::kTrackContacts.size());
        std::fflush(stdout);
        const int status = runMode(o, scene, stats.triangles);
        glm::dvec3 at(0.0);
        for (const glm::dvec3& c : drive->contacts)
            at += 0.25 * c;
        std::printf(
            "vehicle: %llu ground queries over %llu frames, %.1f m along the loop, at (%.1f, %.1f, %.2f)\n",
            static_cast<unsigned long long>(drive->queries), static_cast<unsigned long long>(drive->frames),
            drive->distance, at.x, at.y, at.z);
        return status;
    }
    return runMode(o, scene, stats.triangles);
}

} // namespace

int main(int argc, char** argv) {
    Options options;
    if (const int status = parseArgs(argc, argv, options); status >= 0) return status;
    try {
        return run(options);
    } catch (const std::exception& e) {
        std::cerr << "polygon: error: " << e.what() << "\n";
        return 1;
    }
}

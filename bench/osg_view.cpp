// OpenSceneGraph reference renderer: any file osgDB reads (.osgt, .osgb, .ive, .flt, ...) drawn by
// OpenSceneGraph 3.6 itself, headless on OSMesa (llvmpipe), to a PNG, with sgfx-view's camera, so
// the same file rendered by OSG and by sgfx (`sgfx-view FILE --out x.png`) can be set side by side
// (docs/coming-from-osg.md, scripts/osg-figures.sh).
//
//   osg_view FILE [--size WxH] [--out PNG] [--yaw DEG] [--pitch DEG] [--fog DENSITY|auto|on|off]
//            [--no-ground] [--frames N [--orbit] [--cpu-time]] [--osg-options STRING]
//
// --frames N times N frames (after 3 warm-up frames, each ended by glFinish, as `polygon --bench`
// and `sgfx-view --bench`) and prints a BENCH line with their median; the PNG is then written only
// when --out is given. --orbit moves the camera along bench/foreign_table.sh's orbit, the formula
// of sgfx-view --orbit (demos/view/main.cpp orbitCamera): around the centre C of the bounding box
// at 1.5 R (R half its diagonal), 30 degrees above the horizontal, the azimuth advancing 360/N
// degrees a frame from --yaw, a 60 degree vertical field of view, near 0.01 R and far 4 R.
// --cpu-time times each frame by the CPU time of all the process's threads (llvmpipe's included)
// instead of wall time, as `pixel_cost --cpu-time` (bench/pixel_vs_osg.sh).
// --fog auto (or on) picks the EXP2 density that hides half of the model's centre seen from the
// orbit (exp(-(1.5 R rho)^2) = 1/2), as sgfx-view's --fog auto hides half of it.
//
// The camera is sgfx-view's headless one (demos/view/main.cpp homeCamera, sgfx::CameraManipulator
// ::home): a 40 degree vertical field of view, the model's world bounding box (active children)
// framed with 5 % to spare in the narrower field of view, looking at the box's centre from yaw and
// pitch (yaw 0 looks along +Y, growing anticlockwise seen from above; pitch > 0 looks down), Z up,
// near and far planes at 0.02 and 20 times the distance. The scene around the model follows
// sgfx-view's too: a grey ground plane 60 radii wide just under the model (--no-ground: none), a
// directional sun from sgfx-view's direction, the clear colour 0.72, 0.76, 0.82.
//
// Colours: OSG content is authored in display (sRGB) values and OSG renders without conversions,
// while sgfx turns the file's colours and textures into linear values, lights in linear and
// encodes the image to sRGB. The PNG here is the framebuffer as OSG draws it (no encoding), and
// sgfx-view's linear clear and ground colours are given to OSG as display values (IEC 61966-2-1);
// the light intensities (sun 0.9, ambient 0.35) are given as they are, factors on display colours,
// which keeps the lit ground within a few levels of sgfx-view's. sgfx-view's ambient comes from its
// sky's image-based light; OSG gets a flat ambient (LightModel) instead.
//
// Headless OSMesa setup and link order: as bench/osg_polygon.cpp (read its header comment): OSMesa
// is linked before the OSG libraries so that libosg's gl* calls reach OSMesa, checked at start-up.
#include "osg_osmesa.h"

#include <osg/ComputeBoundsVisitor>
#include <osg/Fog>
#include <osg/GLExtensions>
#include <osg/Geode>
#include <osg/Geometry>
#include <osg/LightModel>
#include <osg/Material>
#include <osg/NodeVisitor>
#include <osg/TriangleFunctor>
#include <osgDB/Options>
#include <osgDB/ReadFile>
#include <osgViewer/Viewer>

#include <stb/stb_image_write.h>

#include <CLI/CLI.hpp>

#include <dlfcn.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <numeric>
#include <string>
#include <vector>

namespace {

struct Options {
    std::string file;
    int width = 512, height = 384; // sgfx-view's headless default
    std::string out = "osg_view.png";
    float yaw = 30.0f, pitch = 25.0f; // sgfx-view's defaults
    float fogDensity = 0.0f;          // > 0: osg::Fog EXP2 on the root StateSet
    bool autoFog = false;             // --fog auto|on: the density from the model's radius
    bool ground = true;
    int frames = 0;            // --frames N: time N frames and print a BENCH line
    bool orbit = false;        // --orbit: the orbit camera of the header
    bool cpuTime = false;      // --cpu-time: frames timed by the process's CPU time (pixel_cost's)
    std::string readerOptions; // --osg-options: osgDB::Options' string (the plugins' switches)
};

// The median of the frame times.
double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// CPU time of every thread of the process (llvmpipe's rasterizer threads included).
double processCpuMs() {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return double(t.tv_sec) * 1e3 + double(t.tv_nsec) * 1e-6;
}

// --fog: a density (> 0), auto/on (from the radius) or off.
bool parseFog(const std::string& v, Options& opt) {
    opt.autoFog = v == "auto" || v == "on";
    if (opt.autoFog || v == "off") return true;
    char* end = nullptr;
    const float d = std::strtof(v.c_str(), &end);
    if (v.empty() || *end || !std::isfinite(d) || d <= 0.0f) return false;
    opt.fogDensity = d;
    return true;
}

// sgfx-view's scene values (demos/view/ViewScene.cpp), linear.
constexpr float kFovyDegrees = 40.0f;
const osg::Vec3 kClearLinear{0.72f, 0.76f, 0.82f};
const osg::Vec3 kSunTravel{-0.4f, 0.3f, -0.85f}; // the sun light's travel direction (normalised below)
constexpr float kSunLinear = 0.9f;
constexpr float kAmbientLinear = 0.35f;
const osg::Vec3 kGroundLinear{0.55f, 0.55f, 0.52f};

float toDisplay(float c) {
    const double v = std::clamp(double(c), 0.0, 1.0);
    return float(v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1.0 / 2.4) - 0.055);
}
osg::Vec4 toDisplay(const osg::Vec3& c) {
    return {toDisplay(c.x()), toDisplay(c.y()), toDisplay(c.z()), 1.0f};
}

struct TriangleCounter {
    std::size_t n = 0;
    void operator()(const osg::Vec3&, const osg::Vec3&, const osg::Vec3&) { ++n; }
};

// Drawables and triangles, each Geometry once per parent path (OSG's own statistics' way).
class CountVisitor : public osg::NodeVisitor {
public:
    CountVisitor()
        : osg::NodeVisitor(TRAVERSE_ALL_CHILDREN) {}
    void apply(osg::Drawable& d) override {
        ++drawables;
        if (osg::Geometry* g = d.asGeometry()) {
            osg::TriangleFunctor<TriangleCounter> tc;
            g->accept(tc);
            triangles += tc.n;
        }
    }
    std::size_t drawables = 0, triangles = 0;
};

// sgfx-view's ground: a quad 60 radii wide, 1e-3 radii under the model's base, grey material.
osg::ref_ptr<osg::Geode> makeGround(const osg::BoundingBox& box, float radius) {
    const float half = 30.0f * radius, z = box.zMin() - 1e-3f * radius;
    const osg::Vec3 c = box.center();
    osg::ref_ptr<osg::Geometry> quad = new osg::Geometry;
    osg::ref_ptr<osg::Vec3Array> v = new osg::Vec3Array;
    v->push_back({c.x() - half, c.y() - half, z});
    v->push_back({c.x() + half, c.y() - half, z});
    v->push_back({c.x() + half, c.y() + half, z});
    v->push_back({c.x() - half, c.y() + half, z});
    quad->setVertexArray(v.get());
    osg::ref_ptr<osg::Vec3Array> n = new osg::Vec3Array(osg::Array::BIND_OVERALL);
    n->push_back({0.0f, 0.0f, 1.0f});
    quad->setNormalArray(n.get());
    quad->addPrimitiveSet(new osg::DrawArrays(GL_QUADS, 0, 4));
    osg::ref_ptr<osg::Material> m = new osg::Material;
    m->setColorMode(osg::Material::OFF);
    m->setDiffuse(osg::Material::FRONT_AND_BACK, toDisplay(kGroundLinear));
    m->setAmbient(osg::Material::FRONT_AND_BACK, toDisplay(kGroundLinear));
    m->setSpecular(osg::Material::FRONT_AND_BACK, osg::Vec4(0, 0, 0, 1));
    quad->getOrCreateStateSet()->setAttributeAndModes(m.get(), osg::StateAttribute::ON);
    osg::ref_ptr<osg::Geode> geode = new osg::Geode;
    geode->setName("ground");
    geode->addDrawable(quad.get());
    return geode;
}

} // namespace

int main(int argc, char** argv) {
    Options opt;
    CLI::App app{"osg_view: renders a file osgDB reads with OpenSceneGraph, headless (OSMesa), to a PNG, "
                 "with sgfx-view's camera"};
    app.add_option("file", opt.file, "model file (.osgt, .osgb, .ive, .osg, .flt, ...)")->required();
    std::string size = "512x384";
    app.add_option("--size", size, "image size WxH (default 512x384, sgfx-view's)");
    app.add_option("--out", opt.out, "output PNG (default osg_view.png)");
    app.add_option("--yaw", opt.yaw, "camera azimuth around the model, degrees (default 30)")
        ->check(CLI::Range(-360.0f, 360.0f));
    app.add_option("--pitch", opt.pitch, "camera elevation, degrees (default 25)")
        ->check(CLI::Range(-89.0f, 89.0f));
    std::string fog = "off";
    app.add_option("--fog", fog,
                   "osg::Fog EXP2 of this density (1/m) on the root, clear colour; auto or on: the model's "
                   "centre half hidden from the orbit; off (default): none");
    bool noGround = false;
    app.add_flag("--no-ground", noGround, "no ground plane under the model");
    app.add_option("--frames", opt.frames, "time N frames, print a BENCH line (no PNG unless --out)")
        ->check(CLI::Range(1, 100000));
    app.add_option(
        "--osg-options", opt.readerOptions,
        "osgDB reader options, e.g. noRotation for an OBJ that is Z up already (polygon's exports)");
    app.add_flag("--orbit", opt.orbit, "with --frames: the orbit camera of bench/foreign_table.sh");
    app.add_flag("--cpu-time", opt.cpuTime, "time frames by the CPU time of all threads, not wall time");
    CLI11_PARSE(app, argc, argv);
    opt.ground = !noGround;
    const bool writePng = opt.frames == 0 || app.count("--out") > 0;
    if (!parseFog(fog, opt)) {
        std::fprintf(stderr, "osg_view: --fog: '%s' is not a density > 0, auto, on or off\n", fog.c_str());
        return 2;
    }
    if (opt.orbit && opt.frames == 0) {
        std::fprintf(stderr, "osg_view: --orbit needs --frames N\n");
        return 2;
    }
    if (std::sscanf(size.c_str(), "%dx%d", &opt.width, &opt.height) != 2 || opt.width < 16 ||
        opt.height < 16 || opt.width > 8192 || opt.height > 8192) {
        std::fprintf(stderr, "osg_view: --size: '%s' is not WxH (16..8192)\n", size.c_str());
        return 2;
    }

    // ---- OSMesa context, checked to reach OSMesa (osg_osmesa.h)
    const auto gl = OsgOsmesaContext::open("osg_view", opt.width, opt.height);
    if (!gl) return 1;
    const char* renderer = gl->renderer();

    // ---- load (images resolve through OSG_FILE_PATH and the file's folder, osgDB's own rules)
    osg::ref_ptr<osgDB::Options> readOptions = new osgDB::Options(opt.readerOptions);
    osg::ref_ptr<osg::Node> model = osgDB::readRefNodeFile(opt.file, readOptions.get());
    if (!model) {
        std::fprintf(stderr, "osg_view: osgDB cannot read %s\n", opt.file.c_str());
        return 1;
    }
    CountVisitor count;
    model->accept(count);
    // World bounds of the active children, as sgfx::ComputeBoundsVisitor (Mode::ActiveChildren).
    osg::ComputeBoundsVisitor boundsVisitor(osg::NodeVisitor::TRAVERSE_ACTIVE_CHILDREN);
    model->accept(boundsVisitor);
    osg::BoundingBox box = boundsVisitor.getBoundingBox();
    if (!box.valid()) box.set(-0.5f, -0.5f, -0.5f, 0.5f, 0.5f, 0.5f);
    const float radius = std::max(0.5f * (box._max - box._min).length(), 1e-4f);
    if (opt.autoFog) opt.fogDensity = std::sqrt(std::log(2.0f)) / (1.5f * radius);

    // ---- the scene around it: ground, sun, ambient, fog
    osg::ref_ptr<osg::Group> root = new osg::Group;
    root->addChild(model.get());
    if (opt.ground) root->addChild(makeGround(box, radius).get());
    osg::StateSet* ss = root->getOrCreateStateSet();
    osg::ref_ptr<osg::LightModel> lightModel = new osg::LightModel;
    lightModel->setAmbientIntensity(osg::Vec4(kAmbientLinear, kAmbientLinear, kAmbientLinear, 1.0f));
    ss->setAttributeAndModes(lightModel.get(), osg::StateAttribute::ON);
    const osg::Vec4 clear = toDisplay(kClearLinear);
    if (opt.fogDensity > 0.0f) {
        osg::ref_ptr<osg::Fog> fog = new osg::Fog;
        fog->setMode(osg::Fog::EXP2);
        fog->setDensity(opt.fogDensity);
        fog->setColor(clear);
        ss->setAttributeAndModes(fog.get(), osg::StateAttribute::ON);
    }

    osgViewer::Viewer viewer;
    viewer.setThreadingModel(osgViewer::Viewer::SingleThreaded);
    viewer.setUpViewerAsEmbeddedInWindow(0, 0, opt.width, opt.height);
    viewer.setSceneData(root.get());
    viewer.setLightingMode(osg::View::SKY_LIGHT); // fixed in world space, like sgfx's sun
    osg::Vec3 toSun = -kSunTravel;
    toSun.normalize();
    osg::Light* sun = viewer.getLight();
    sun->setPosition(osg::Vec4(toSun, 0.0f));
    sun->setAmbient(osg::Vec4(0, 0, 0, 1));
    const float s = kSunLinear;
    sun->setDiffuse(osg::Vec4(s, s, s, 1));
    sun->setSpecular(osg::Vec4(s, s, s, 1));

    // ---- sgfx-view's camera (CameraManipulator::home, then setPerspective(40, d/50, 20 d))
    osg::Camera* camera = viewer.getCamera();
    camera->setClearColor(clear);
    camera->setComputeNearFarMode(osg::CullSettings::DO_NOT_COMPUTE_NEAR_FAR);
    camera->setCullingMode(osg::CullSettings::VIEW_FRUSTUM_CULLING);
    const double aspect = double(opt.width) / double(opt.height);
    const float halfY = osg::DegreesToRadians(kFovyDegrees) * 0.5f;
    const float halfX = std::atan(std::tan(halfY) * std::max(float(aspect), 1e-3f));
    const float distance = 1.05f * radius / std::sin(std::min(halfX, halfY));
    const float yaw = osg::DegreesToRadians(opt.yaw), pitch = osg::DegreesToRadians(opt.pitch);
    const osg::Vec3 look{-std::sin(yaw) * std::cos(pitch), std::cos(yaw) * std::cos(pitch), -std::sin(pitch)};
    const osg::Vec3 centre = box.center();
    camera->setViewMatrixAsLookAt(centre - look * distance, centre, osg::Vec3(0, 0, 1));
    camera->setProjectionMatrixAsPerspective(kFovyDegrees, aspect, distance * 0.02, distance * 20.0);
    viewer.realize();
    // --orbit: the pose of frame i (the header's formula).
    auto pose = [&](int i) {
        if (!opt.orbit) return;
        const float a = osg::DegreesToRadians(opt.yaw + 360.0f * float(i) / float(opt.frames));
        const float e = osg::DegreesToRadians(30.0f);
        const osg::Vec3 dir{-std::sin(a) * std::cos(e), std::cos(a) * std::cos(e), -std::sin(e)};
        camera->setViewMatrixAsLookAt(centre - dir * (1.5f * radius), centre, osg::Vec3(0, 0, 1));
        camera->setProjectionMatrixAsPerspective(60.0, aspect, 0.01 * radius, 4.0 * radius);
    };
    pose(0);
    viewer.frame();
    glFinish();
    if (opt.frames > 0) {
        using clock = std::chrono::steady_clock;
        for (int i = 0; i < 2; ++i) { // with the frame above, 3 warm-up frames
            viewer.frame();
            glFinish();
        }
        std::vector<double> ms;
        for (int i = 0; i < opt.frames; ++i) {
            pose(i);
            const auto t0 = clock::now();
            const double c0 = processCpuMs();
            viewer.frame();
            glFinish();
            ms.push_back(opt.cpuTime ? processCpuMs() - c0
                                     : std::chrono::duration<double, std::milli>(clock::now() - t0).count());
        }
        const double mean = std::accumulate(ms.begin(), ms.end(), 0.0) / double(ms.size());
        std::printf(
            "BENCH osg ms_per_frame=%.3f fps=%.2f frames=%d median_ms=%.3f size=%dx%d camera=%s fog=%d "
            "fog_density=%g drawables=%zu triangles=%zu renderer=%s\n",
            mean, 1000.0 / mean, opt.frames, median(ms), opt.width, opt.height, opt.orbit ? "orbit" : "home",
            int(opt.fogDensity > 0.0f), double(opt.fogDensity), count.drawables, count.triangles, renderer);
        if (!writePng) return 0;
    }

    // ---- the frame as PNG, top row first, as drawn (display values, see the header)
    const std::size_t row = std::size_t(opt.width) * 3;
    std::vector<unsigned char> px(row * std::size_t(opt.height)), flipped(px.size());
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, opt.width, opt.height, GL_RGB, GL_UNSIGNED_BYTE, px.data());
    for (int y = 0; y < opt.height; ++y)
        std::memcpy(flipped.data() + std::size_t(y) * row, px.data() + std::size_t(opt.height - 1 - y) * row,
                    row);
    if (!stbi_write_png(opt.out.c_str(), opt.width, opt.height, 3, flipped.data(), int(row))) {
        std::fprintf(stderr, "osg_view: cannot write %s\n", opt.out.c_str());
        return 1;
    }
    std::printf(
        "osg_view: wrote %s (%dx%d): %zu drawables, %zu triangles, bounds (%.3f,%.3f,%.3f)-(%.3f,%.3f,"
        "%.3f), renderer %s\n",
        opt.out.c_str(), opt.width, opt.height, count.drawables, count.triangles, box.xMin(), box.yMin(),
        box.zMin(), box.xMax(), box.yMax(), box.zMax(), renderer);
    return 0; // the viewer goes first (its GL objects released in our context), then the context
}

// Peer benchmark: renders an OBJ exported by the sgfx "polygon" demo (`polygon --export-obj FILE`)
// with OpenSceneGraph 3.6 on Mesa's software rasterizer (llvmpipe through OSMesa), along the same
// deterministic camera path, so sgfx/OSG frame-time ratios can be reported on the same machine.
//
//   osg_polygon FILE.obj [--size WxH] [--frames N] [--out FILE.png] [--optimize] [--osg-culling]
//               [--osg-stats] [--linear-png] [--sun-dir X,Y,Z] [--sun R,G,B] [--ambient R,G,B]
//               [--clear R,G,B] [--fog DENSITY] [--shadows N] [--shadow-map S] [--shadow-distance M]
//               [--check-shadow]
//
// Headless, no display: we create the OSMesa context ourselves and run osgViewer::Viewer
// "embedded" in it (GraphicsWindowEmbedded, single-threaded), calling viewer.frame() ourselves.
//
// libGL vs OSMesa: Debian's libosg links libGL.so.1 (glvnd), whose gl* are libGLdispatch stubs
// that do nothing without a GLX context (glGetString returns NULL under OSMesa). Two paths must
// reach OSMesa instead:
//  1. Plain gl* calls from libosg: the dynamic linker binds them to the first library in the global
//     scope that defines them. OSMesa is linked first (before any OSG library, see
//     bench/CMakeLists.txt), so it precedes libGL (only an indirect dependency) and its gl* win.
//  2. Entry points OSG looks up at run time (VBOs, shaders...): Debian's OSG 3.6.5 resolves them in
//     osg::getGLExtensionFuncPtr() with dlsym(RTLD_DEFAULT, name), which follows the same order, so
//     point 1 covers it (it does not go through glXGetProcAddressARB in this build).
// Both are checked at start-up; on failure the program stops rather than time a context that
// draws nothing. If a different link line ever puts libGL first, LD_PRELOAD=libOSMesa.so.8 fixes it.
//
// Shadows (--shadows N, the peer of sgfx's cascaded sun shadows): the root becomes an
// osgShadow::ShadowedScene with a ViewDependentShadowMap (orthographic maps of S x S texels up to M
// metres from the eye, near/far computed from primitives, light 0, maps on texture units 1 and up);
// the sun becomes an osg::LightSource inside it, lighting exactly as the view's SKY_LIGHT does, and
// the view adds no light (NO_LIGHT). Everything casts and receives (default masks). With OSG 3.6.5 on
// OSMesa (Mesa 22.3, llvmpipe), checked with --check-shadow (frame 0 without, then with, the technique):
//  - VDSM renders at most two shadow maps per light: its cull falls back to 2 ("numShadowMapsPerLight
//    of N is greater than maximum supported") and its split is hard-wired for two; the CASCADED hint
//    is not read by 3.6's VDSM. --shadows 3 and 4 therefore run with 2 (said on stderr).
//  - its receiver shading does not work as shipped: the default ShaderHint, NO_SHADERS, shades
//    through fixed-function texture units, which multiply the whole lit colour, ambient included, by
//    the depth comparison (black shadows); its own GLSL (PROVIDE_FRAGMENT_SHADER) does not compile on
//    Mesa (gl_TexCoord indexed by a uniform). MesaViewDependentShadowMap supplies the same shader with
//    constant indices: shadows keep the ambient light, lit pixels match the unshadowed image.
#include "osg_osmesa.h"

#include <osg/AlphaFunc>
#include <osg/CullFace>
#include <osg/Fog>
#include <osg/GLExtensions>
#include <osg/Geode>
#include <osg/Geometry>
#include <osg/Light>
#include <osg/LightModel>
#include <osg/LightSource>
#include <osg/Material>
#include <osg/NodeVisitor>
#include <osg/Program>
#include <osg/Texture2D>
#include <osg/TriangleFunctor>
#include <osgDB/ReadFile>
#include <osgShadow/ShadowSettings>
#include <osgShadow/ShadowedScene>
#include <osgShadow/ViewDependentShadowMap>
#include <osgUtil/Optimizer>
#include <osgUtil/SceneView>
#include <osgUtil/Statistics>
#include <osgViewer/Renderer>
#include <osgViewer/Viewer>

#include <stb/stb_image_write.h>

#include "../demos/polygon/CameraPath.h"

#include <dlfcn.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <numeric>
#include <string>
#include <vector>

namespace {

struct Options {
    std::string file;
    int width = 1280, height = 720;
    int frames = 300;
    std::string out;
    bool optimize = false;   // run osgUtil::Optimizer (DEFAULT_OPTIMIZATIONS) after loading
    bool osgCulling = false; // keep OSG's DEFAULT_CULLING (adds small-feature culling, no near/far planes)
    bool linearPng = false;  // write the PNG as rendered (linear) instead of sRGB-encoding it
    bool osgStats = false;   // collect OSG's per-camera cull/draw CPU times (osg::Stats)
    float fogDensity = 0.0f; // > 0: osg::Fog (EXP, fixed-function distance fog) with this density
    // Shadows: osgShadow::ViewDependentShadowMap (see the header comment).
    int shadows = 0;              // > 0: this many cascades (OSG 3.6 renders at most 2)
    int shadowMap = 2048;         // shadow map size in texels (square)
    float shadowDistance = 200.f; // shadows up to this distance from the eye (metres)
    bool checkShadow = false;     // render frame 0 without and with shadows and compare them
    // Lighting defaults follow demos/polygon/PolygonScene.cpp: a directional sun at azimuth -35 deg,
    // elevation 50 deg, colour (1, 0.95, 0.86) x 1.1, and an ambient light (0.30, 0.34, 0.42).
    osg::Vec3 toSun{0.5266f, -0.3687f, 0.7660f}; // towards the light (minus the travel direction)
    osg::Vec3 sun{1.1f, 1.045f, 0.946f};         // sun colour: diffuse and specular
    osg::Vec3 ambient{0.30f, 0.34f, 0.42f};      // ambient light (LightModel), multiplies material Ka
    osg::Vec3 clear{0.42f, 0.60f, 0.85f};        // linear sky-blue clear colour (the demo's kSkyColor)
};

[[noreturn]] void usage(const char* msg) {
    if (msg) std::fprintf(stderr, "osg_polygon: %s\n", msg);
    std::fprintf(
        stderr,
        "usage: osg_polygon FILE.obj [--size WxH] [--frames N] [--out FILE.png] [--optimize]\n"
        "                   [--osg-culling] [--osg-stats] [--linear-png] [--sun-dir X,Y,Z] [--sun R,G,B]\n"
        "                   [--ambient R,G,B] [--clear R,G,B] [--fog DENSITY] [--shadows N]\n"
        "                   [--shadow-map S] [--shadow-distance M] [--check-shadow]\n"
        "  --size WxH      viewport (default 1280x720)\n"
        "  --frames N      timed frames, one camera-path lap (default 300), after 3 warm-up frames\n"
        "  --out FILE.png  write the last frame (sRGB-encoded like sgfx's output unless --linear-png)\n"
        "  --optimize      run osgUtil::Optimizer DEFAULT_OPTIMIZATIONS after loading\n"
        "  --osg-culling   keep OSG's DEFAULT_CULLING (small-feature culling, no near/far planes)\n"
        "  --osg-stats     print OSG's own cull/draw CPU times per frame (osg::Stats)\n"
        "  --sun-dir X,Y,Z direction towards the sun (default 0.527,-0.369,0.766, the demo's)\n"
        "  --sun R,G,B     sun colour (default 1.1,1.045,0.946); --ambient R,G,B (0.30,0.34,0.42)\n"
        "  --clear R,G,B   linear clear colour (default 0.42,0.60,0.85)\n"
        "  --fog DENSITY   osg::Fog in EXP mode (distance only, no height) over the whole scene\n"
        "  --shadows N     sun shadows through osgShadow::ViewDependentShadowMap with N cascades\n"
        "                  (0 = off, the default; 1..4, OSG 3.6 renders at most 2, see the header)\n"
        "  --shadow-map S  shadow map size in texels (default 2048)\n"
        "  --shadow-distance M\n"
        "                  shadows up to M metres from the eye (default 200)\n"
        "  --check-shadow  render frame 0 without and with shadows (needs --shadows N) and print\n"
        "                  SHADOW_CHECK darker_fraction=X; exit 1 if X < 0.001\n");
    std::exit(msg ? 2 : 0);
}

Options parse(int argc, char** argv) {
    Options o;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto next = [&]() -> std::string {
            if (i + 1 >= argc) usage(("missing value after " + a).c_str());
            return argv[++i];
        };
        if (a == "--size") {
            const std::string v = next();
            if (std::sscanf(v.c_str(), "%dx%d", &o.width, &o.height) != 2 || o.width <= 0 || o.height <= 0)
                usage("--size expects WxH, e.g. 1280x720");
        } else if (a == "--frames") {
            o.frames = std::atoi(next().c_str());
            if (o.frames <= 0) usage("--frames expects a positive count");
        } else if (a == "--out") {
            o.out = next();
        } else if (a == "--optimize") {
            o.optimize = true;
        } else if (a == "--osg-culling") {
            o.osgCulling = true;
        } else if (a == "--linear-png") {
            o.linearPng = true;
        } else if (a == "--fog") {
            o.fogDensity = float(std::atof(next().c_str()));
            if (!(o.fogDensity > 0.0f)) usage("--fog expects a positive density");
        } else if (a == "--shadows") {
            o.shadows = std::atoi(next().c_str());
            if (o.shadows < 0 || o.shadows > 4) usage("--shadows expects 0 (off) to 4 cascades");
        } else if (a == "--shadow-map") {
            o.shadowMap = std::atoi(next().c_str());
            if (o.shadowMap < 16 || o.shadowMap > 16384)
                usage("--shadow-map expects a size from 16 to 16384");
        } else if (a == "--shadow-distance") {
            o.shadowDistance = float(std::atof(next().c_str()));
            if (!(o.shadowDistance > 0.0f)) usage("--shadow-distance expects a positive distance");
        } else if (a == "--check-shadow") {
            o.checkShadow = true;
        } else if (a == "--osg-stats") {
            o.osgStats = true;
        } else if (a == "--sun-dir" || a == "--sun" || a == "--ambient" || a == "--clear") {
            osg::Vec3& v = a == "--sun-dir"   ? o.toSun
                           : a == "--sun"     ? o.sun
                           : a == "--ambient" ? o.ambient
                                              : o.clear;
            const std::string s = next();
            if (std::sscanf(s.c_str(), "%f,%f,%f", &v.x(), &v.y(), &v.z()) != 3)
                usage((a + " expects three comma-separated numbers").c_str());
        } else if (a == "-h" || a == "--help") {
            usage(nullptr);
        } else if (!a.empty() && a[0] == '-') {
            usage(("unknown option " + a).c_str());
        } else if (o.file.empty()) {
            o.file = a;
        } else {
            usage("more than one input file");
        }
    }
    if (o.file.empty()) usage("no OBJ file given");
    if (o.checkShadow && o.shadows == 0) usage("--check-shadow needs --shadows N with N > 0");
    return o;
}

// Counts triangles of any triangle-type primitive set.
struct TriangleCounter {
    std::size_t n = 0;
    void operator()(const osg::Vec3&, const osg::Vec3&, const osg::Vec3&) { ++n; }
};

// Makes every geometry draw through VBOs (no display lists, the 3.6 default made explicit), counts
// drawables/triangles, restores the OBJ specular exponent (the obj plugin maps Ns, a Phong exponent
// as sgfx::writeObj writes it, to Ns/1000*128; fixed function caps it at 128) and turns face culling
// off for blended materials.
class PrepareVisitor : public osg::NodeVisitor {
public:
    // fix = false: count only (used again after the optimizer, which must not rescale twice).
    explicit PrepareVisitor(bool fix = true)
        : osg::NodeVisitor(TRAVERSE_ALL_CHILDREN)
        , fix_(fix) {}

    void apply(osg::Node& node) override {
        fixMaterial(node.getStateSet());
        traverse(node);
    }
    void apply(osg::Drawable& d) override {
        fixMaterial(d.getStateSet());
        ++drawables;
        if (osg::Geometry* g = d.asGeometry()) {
            if (fix_) {
                g->setUseDisplayList(false);
                g->setUseVertexBufferObjects(true);
            }
            osg::TriangleFunctor<TriangleCounter> tc;
            g->accept(tc);
            triangles += tc.n;
            if (const osg::Array* v = g->getVertexArray()) vertices += v->getNumElements();
            primitiveSets += g->getNumPrimitiveSets();
        }
    }

    std::size_t drawables = 0, triangles = 0, vertices = 0, primitiveSets = 0, materials = 0;
    std::size_t transparentMaterials = 0, maskedMaterials = 0;

private:
    void fixMaterial(osg::StateSet* ss) {
        if (!ss || !fix_) return;
        auto* m = dynamic_cast<osg::Material*>(ss->getAttribute(osg::StateAttribute::MATERIAL));
        if (m && fixed_.insert({m, true}).second) {
            ++materials;
            const float ns = m->getShininess(osg::Material::FRONT) * 1000.0f / 128.0f;
            m->setShininess(osg::Material::FRONT_AND_BACK, std::clamp(ns, 0.0f, 128.0f));
        }
        // Alpha-masked materials (sgfx's leaf cards) come as an RGBA map_Kd: cut them out at
        // sgfx's alpha cutoff (0.5) with the fixed-function alpha test, both faces drawn.
        auto* tex = dynamic_cast<osg::Texture2D*>(ss->getTextureAttribute(0, osg::StateAttribute::TEXTURE));
        if (tex && tex->getImage() && tex->getImage()->isImageTranslucent() &&
            masked_.insert({ss, true}).second) {
            ss->setAttributeAndModes(new osg::AlphaFunc(osg::AlphaFunc::GEQUAL, 0.5f),
                                     osg::StateAttribute::ON);
            ss->setMode(GL_CULL_FACE, osg::StateAttribute::OFF);
            // The plugin sends translucent maps to the blended bin: a cut-out is opaque.
            ss->setMode(GL_BLEND, osg::StateAttribute::OFF);
            ss->setRenderingHint(osg::StateSet::OPAQUE_BIN);
            ++maskedMaterials;
        }
        // The plugin puts materials with d < 1 in the blended transparent bin; sgfx's glass is
        // drawn without face culling, so do the same here.
        if (ss->getRenderingHint() == osg::StateSet::TRANSPARENT_BIN && !masked_.count(ss) &&
            transparent_.insert({ss, true}).second) {
            ss->setAttributeAndModes(new osg::CullFace(osg::CullFace::BACK),
                                     osg::StateAttribute::OFF | osg::StateAttribute::OVERRIDE);
            ++transparentMaterials;
        }
    }
    bool fix_;
    std::map<osg::Material*, bool> fixed_;
    std::map<osg::StateSet*, bool> transparent_, masked_;
};

// osgShadow::ViewDependentShadowMap with a receiver shader that Mesa compiles. OSG 3.6.5's VDSM
// defaults to ShadowSettings::NO_SHADERS: its shadow maps then act through fixed-function texture
// units (depth compare, GL_MODULATE), which multiply the whole lit colour, ambient included, by 0
// in shadow: black shadows. Its own shader (PROVIDE_FRAGMENT_SHADER), which keeps the ambient and
// emissive part (gl_FrontLightModelProduct.sceneColor) in shadow, indexes gl_TexCoord with uniform
// ints; gl_TexCoord is an unsized array in GLSL 1.10, which allows constant indices only, so Mesa
// rejects it ("unsized array index must be constant"), the program fails to link and the black
// fixed-function shadows come back. This is the same shader with the units as constants (base
// texture on unit 0, shadow maps on BaseShadowTextureUnit + i), plus --fog's EXP fog, which a
// fragment shader has to apply itself.
class MesaViewDependentShadowMap : public osgShadow::ViewDependentShadowMap {
public:
    explicit MesaViewDependentShadowMap(bool fog)
        : fog_(fog) {}

protected:
    void createShaders() override {
        // casting state, uniforms (baseTexture, shadowTextureI), the white fallback base texture
        osgShadow::ViewDependentShadowMap::createShaders();
        const osgShadow::ShadowSettings* settings = getShadowedScene()->getShadowSettings();
        const unsigned maps = settings->getNumShadowMapsPerLight();
        std::string fs = "uniform sampler2D baseTexture;\n";
        std::string lit = "1.0";
        for (unsigned i = 0; i < maps; ++i) {
            const std::string n = std::to_string(i);
            const std::string unit = std::to_string(settings->getBaseShadowTextureUnit() + i);
            fs += "uniform sampler2DShadow shadowTexture" + n + ";\n";
            lit += " * shadow2DProj(shadowTexture" + n + ", gl_TexCoord[" + unit + "]).r";
        }
        fs += "void main(void) {\n    float lit = " + lit + ";\n";
        fs += "    vec4 color = texture2D(baseTexture, gl_TexCoord[0].xy) *\n"
              "                 mix(gl_FrontLightModelProduct.sceneColor, gl_Color, lit);\n";
        if (fog_)
            fs += "    float f = clamp(exp(-gl_Fog.density * gl_FogFragCoord), 0.0, 1.0);\n"
                  "    color.rgb = mix(gl_Fog.color.rgb, color.rgb, f);\n";
        fs += "    gl_FragColor = color;\n}\n";
        _program = new osg::Program;
        _program->addShader(new osg::Shader(osg::Shader::FRAGMENT, fs));
    }

private:
    bool fog_;
};

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

} // namespace

int main(int argc, char** argv) {
    const Options opt = parse(argc, argv);
    using clock = std::chrono::steady_clock;

    // ---- OSMesa context, checked to reach OSMesa (see the header comment and osg_osmesa.h)
    const auto gl = OsgOsmesaContext::open("osg_polygon", opt.width, opt.height);
    if (!gl) return 1;
    const char* renderer = gl->renderer();
    std::printf("GL_RENDERER: %s\nGL_VERSION: %s\n", renderer, gl->version());
    if (!std::strstr(renderer, "llvmpipe"))
        std::fprintf(stderr, "osg_polygon: warning: renderer is not llvmpipe, timings are not comparable\n");
    if (const char* t = std::getenv("LP_NUM_THREADS")) std::printf("LP_NUM_THREADS=%s\n", t);

    // ---- load: the obj plugin makes one Geode+Geometry per (object, material) state, so objects stay
    // separate drawables. "noRotation": our OBJ is Z up already (the plugin rotates Y-up to Z-up by
    // default). Its default mesh optimisation (osgUtil::optimizeMesh: indexing + vertex cache order)
    // stays on; without it every face would be its own DrawArrays.
    const auto tl0 = clock::now();
    osg::ref_ptr<osgDB::Options> readOptions = new osgDB::Options("noRotation");
    osg::ref_ptr<osg::Node> model = osgDB::readRefNodeFile(opt.file, readOptions.get());
    if (!model) {
        std::fprintf(stderr, "osg_polygon: cannot load %s\n", opt.file.c_str());
        return 1;
    }
    const double loadMs = std::chrono::duration<double, std::milli>(clock::now() - tl0).count();
    PrepareVisitor before;
    model->accept(before);
    std::printf(
        "loaded %s in %.0f ms: %zu drawables, %zu triangles, %zu vertices, %zu primitive sets, %zu materials "
        "(%zu blended, %zu alpha-tested)\n",
        opt.file.c_str(), loadMs, before.drawables, before.triangles, before.vertices, before.primitiveSets,
        before.materials, before.transparentMaterials, before.maskedMaterials);
    if (opt.optimize) {
        const auto to0 = clock::now();
        osgUtil::Optimizer optimizer;
        optimizer.optimize(model.get(), osgUtil::Optimizer::DEFAULT_OPTIMIZATIONS);
        PrepareVisitor after(false);
        model->accept(after);
        std::printf("osgUtil::Optimizer DEFAULT_OPTIMIZATIONS in %.0f ms: %zu drawables, %zu triangles\n",
                    std::chrono::duration<double, std::milli>(clock::now() - to0).count(), after.drawables,
                    after.triangles);
    } else {
        std::printf("osgUtil::Optimizer: not run (scene graph as loaded; --optimize to run it)\n");
    }

    // ---- shadows (--shadows N): the root becomes an osgShadow::ShadowedScene with a
    // ViewDependentShadowMap. Casters and receivers are selected by ShadowSettings' default traversal
    // masks (~0), which every node's default mask (~0) matches: everything casts and receives.
    osg::ref_ptr<osgShadow::ShadowedScene> shadowedScene;
    osg::ref_ptr<osgShadow::ViewDependentShadowMap> vdsm;
    // OSG 3.6's VDSM renders at most two shadow maps per light (its cull falls back to 2, and its
    // shaders sample one map unless exactly two are asked for): ask for what it can do.
    const int shadowMaps = std::min(opt.shadows, 2);
    if (opt.shadows > 2)
        std::fprintf(stderr,
                     "osg_polygon: note: OSG 3.6's ViewDependentShadowMap renders at most 2 shadow maps per "
                     "light: --shadows %d runs with 2\n",
                     opt.shadows);
    if (opt.shadows > 0) {
        shadowedScene = new osgShadow::ShadowedScene;
        osgShadow::ShadowSettings* settings = shadowedScene->getShadowSettings();
        settings->setTextureSize(osg::Vec2s(short(opt.shadowMap), short(opt.shadowMap)));
        settings->setNumShadowMapsPerLight(unsigned(shadowMaps));
        settings->setMultipleShadowMapHint(osgShadow::ShadowSettings::CASCADED);
        settings->setShadowMapProjectionHint(osgShadow::ShadowSettings::ORTHOGRAPHIC_SHADOW_MAP);
        settings->setComputeNearFarModeOverride(osg::CullSettings::COMPUTE_NEAR_FAR_USING_PRIMITIVES);
        settings->setMaximumShadowMapDistance(opt.shadowDistance);
        settings->setLightNum(0);
        settings->setBaseShadowTextureUnit(1);
        settings->setShaderHint(osgShadow::ShadowSettings::PROVIDE_FRAGMENT_SHADER); // ours, see above
        vdsm = new MesaViewDependentShadowMap(opt.fogDensity > 0.0f);
        // --check-shadow renders its first frame without the technique (attached after it)
        if (!opt.checkShadow) shadowedScene->setShadowTechnique(vdsm.get());
    }

    // ---- global state: lighting on, one-sided, back faces culled (sgfx's default), local viewer like
    // sgfx's Blinn-Phong (which uses the true view vector)
    osg::ref_ptr<osg::Group> root = shadowedScene ? shadowedScene.get() : new osg::Group;
    root->addChild(model.get());
    osg::StateSet* ss = root->getOrCreateStateSet();
    osg::ref_ptr<osg::LightModel> lightModel = new osg::LightModel;
    lightModel->setTwoSided(false);
    lightModel->setLocalViewer(true);
    lightModel->setAmbientIntensity(osg::Vec4(opt.ambient, 1.0f));
    ss->setAttributeAndModes(lightModel.get(), osg::StateAttribute::ON);
    ss->setMode(GL_LIGHTING, osg::StateAttribute::ON);
    ss->setAttributeAndModes(new osg::CullFace(osg::CullFace::BACK), osg::StateAttribute::ON);
    if (opt.fogDensity > 0.0f) {
        osg::ref_ptr<osg::Fog> fog = new osg::Fog;
        fog->setMode(osg::Fog::EXP);
        fog->setDensity(opt.fogDensity);
        fog->setColor(osg::Vec4(0.70f, 0.74f, 0.80f, 1.0f)); // sgfx's default fog colour
        ss->setAttributeAndModes(fog.get(), osg::StateAttribute::ON);
    }

    // ---- viewer embedded in our context
    osgViewer::Viewer viewer;
    viewer.setThreadingModel(osgViewer::Viewer::SingleThreaded);
    viewer.setUpViewerAsEmbeddedInWindow(0, 0, opt.width, opt.height);
    viewer.setSceneData(root.get());
    // Sun: one directional light fixed in world space (SKY_LIGHT); its position (w = 0) points
    // towards the light. Its ambient is 0: the ambient light lives in the LightModel, as in sgfx.
    // With shadows the same light is an osg::LightSource at the top of the ShadowedScene instead (VDSM
    // finds its light among the positional state the cull collected) and the view adds none (NO_LIGHT).
    // RELATIVE_RF, not ABSOLUTE_RF: under the root the model-view matrix is the view matrix, which is
    // what SKY_LIGHT positions its light with, and VDSM maps the light's direction to world space with
    // it. An ABSOLUTE_RF light source is positioned with no matrix at all, i.e. in eye space: GL would
    // light the scene with a camera-fixed sun while VDSM cast the shadows along the world direction.
    osg::Light* sun = nullptr;
    if (shadowedScene) {
        viewer.setLightingMode(osg::View::NO_LIGHT);
        osg::ref_ptr<osg::LightSource> sunSource = new osg::LightSource;
        sunSource->setReferenceFrame(osg::LightSource::RELATIVE_RF);
        sun = sunSource->getLight();
        sun->setLightNum(0);
        sunSource->setStateSetModes(*ss, osg::StateAttribute::ON); // GL_LIGHT0 on
        root->insertChild(0, sunSource.get());
    } else {
        viewer.setLightingMode(osg::View::SKY_LIGHT);
        sun = viewer.getLight();
    }
    osg::Vec3 toSun = opt.toSun;
    toSun.normalize();
    sun->setPosition(osg::Vec4(toSun, 0.0f));
    sun->setAmbient(osg::Vec4(0, 0, 0, 1));
    sun->setDiffuse(osg::Vec4(opt.sun, 1));
    sun->setSpecular(osg::Vec4(opt.sun, 1));
    if (shadowedScene) {
        std::printf(
            "shadows: osgShadow::ViewDependentShadowMap, %d shadow map(s) of %dx%d texels, up to %g m, "
            "light 0, texture units 1..%d\n",
            shadowMaps, opt.shadowMap, opt.shadowMap, double(opt.shadowDistance), shadowMaps);
    }

    osg::Camera* camera = viewer.getCamera();
    camera->setClearColor(osg::Vec4(opt.clear, 1.0f));
    camera->setComputeNearFarMode(osg::CullSettings::DO_NOT_COMPUTE_NEAR_FAR);
    // sgfx culls each node's bounding sphere against all six frustum planes and nothing else; OSG's
    // default culls against the sides only (it expects to compute near/far) and adds small-feature
    // culling. Match sgfx unless --osg-culling.
    if (!opt.osgCulling) camera->setCullingMode(osg::CullSettings::VIEW_FRUSTUM_CULLING);
    const double aspect = double(opt.width) / double(opt.height);
    camera->setProjectionMatrixAsPerspective(polygon::kPathFovyDegrees, aspect, polygon::kPathNear,
                                             polygon::kPathFar);
    viewer.realize();
    // No sRGB encode-on-write here: OSMesa's window-system framebuffer is linear and not
    // sRGB-capable (GL_FRAMEBUFFER_SRGB has no effect), so OSG output stays linear; --out encodes
    // the PNG on the CPU instead so it can be compared with sgfx's images.
    osg::Stats* cameraStats = camera->getStats();
    if (opt.osgStats && cameraStats) cameraStats->collectStats("rendering", true);

    auto setPose = [&](int i) {
        const float t = float(i) / float(opt.frames);
        const polygon::CameraPose p = polygon::cameraPose(t, 800.f);
        camera->setViewMatrixAsLookAt(osg::Vec3d(p.eye.x, p.eye.y, p.eye.z),
                                      osg::Vec3d(p.target.x, p.target.y, p.target.z),
                                      osg::Vec3d(p.up.x, p.up.y, p.up.z));
    };
    auto frame = [&]() {
        viewer.frame();
        glFinish();
    };

    // Draw statistics of the last frame (outside the timed region).
    auto* osgRenderer = dynamic_cast<osgViewer::Renderer*>(camera->getRenderer());
    auto lastFrameStats = [&](osgUtil::Statistics& stats) {
        if (!osgRenderer) return false;
        for (unsigned k = 0; k < 2; ++k) {
            osgUtil::SceneView* sv = osgRenderer->getSceneView(k);
            stats.reset();
            if (sv && sv->getStats(stats) && stats.numDrawables > 0) return true;
        }
        return false;
    };

    // ---- --check-shadow: frame 0 without the shadow technique (the ShadowedScene then traverses
    // its children like a plain group, same light and state), then with it; shadows must darken some
    // of the image and brighten (almost) none of it
    if (opt.checkShadow) {
        auto readLuminance = [&]() {
            std::vector<unsigned char> px(std::size_t(opt.width) * std::size_t(opt.height) * 3);
            glPixelStorei(GL_PACK_ALIGNMENT, 1);
            glReadPixels(0, 0, opt.width, opt.height, GL_RGB, GL_UNSIGNED_BYTE, px.data());
            std::vector<float> lum(px.size() / 3);
            for (std::size_t i = 0; i < lum.size(); ++i) // linear Rec. 709 luminance, 0..255
                lum[i] = 0.2126f * px[3 * i] + 0.7152f * px[3 * i + 1] + 0.0722f * px[3 * i + 2];
            return lum;
        };
        setPose(0);
        frame();
        const std::vector<float> off = readLuminance();
        shadowedScene->setShadowTechnique(vdsm.get());
        frame();
        const std::vector<float> on = readLuminance();
        std::size_t darker = 0, brighter = 0;
        for (std::size_t i = 0; i < on.size(); ++i) {
            // a drop of more than 20 % (and of more than one 8-bit step, so near-black noise does not count)
            if (on[i] < 0.8f * off[i] && off[i] - on[i] > 1.0f) ++darker;
            if (on[i] > 1.2f * off[i] && on[i] - off[i] > 1.0f) ++brighter;
        }
        const double darkerFraction = double(darker) / double(on.size());
        std::printf(
            "SHADOW_CHECK darker_fraction=%.4f brighter_fraction=%.4f (frame 0, luminance change > 20 %%)\n",
            darkerFraction, double(brighter) / double(on.size()));
        if (darkerFraction < 0.001) {
            std::fprintf(stderr, "osg_polygon: --check-shadow: the shadow technique darkens no part of the "
                                 "image, shadows are not drawn\n");
            return 1;
        }
    }

    // ---- warm-up at t = 0 like `polygon --bench` (GL objects are compiled on first draw), then the
    // timed lap
    setPose(0);
    for (int i = 0; i < 3; ++i)
        frame();
    std::vector<double> ms;
    ms.reserve(std::size_t(opt.frames));
    double drawablesSum = 0, trianglesSum = 0, cullSum = 0, drawSum = 0;
    int statFrames = 0, timeFrames = 0;
    for (int i = 0; i < opt.frames; ++i) {
        setPose(i);
        const auto t0 = clock::now();
        frame();
        ms.push_back(std::chrono::duration<double, std::milli>(clock::now() - t0).count());
        if (opt.osgStats && cameraStats) {
            const unsigned fn = viewer.getFrameStamp()->getFrameNumber();
            double cull = 0, draw = 0;
            if (cameraStats->getAttribute(fn, "Cull traversal time taken", cull) &&
                cameraStats->getAttribute(fn, "Draw traversal time taken", draw)) {
                cullSum += cull * 1000.0;
                drawSum += draw * 1000.0;
                ++timeFrames;
            }
        }
        osgUtil::Statistics stats;
        if (lastFrameStats(stats)) {
            ++statFrames;
            drawablesSum += stats.numDrawables;
            unsigned tris = 0;
            for (const auto& [mode, count] : stats.getPrimitiveCountMap())
                if (mode == GL_TRIANGLES || mode == GL_TRIANGLE_STRIP || mode == GL_TRIANGLE_FAN)
                    tris += count;
            trianglesSum += tris;
        }
    }

    const double mean = std::accumulate(ms.begin(), ms.end(), 0.0) / double(ms.size());
    const double med = median(ms);
    std::printf("frames: %d at %dx%d (after 3 warm-up frames)\n", opt.frames, opt.width, opt.height);
    std::printf("ms/frame: mean %.3f  median %.3f  min %.3f  max %.3f\n", mean, med,
                *std::min_element(ms.begin(), ms.end()), *std::max_element(ms.begin(), ms.end()));
    std::printf("fps: %.2f (from mean)\n", 1000.0 / mean);
    if (statFrames > 0)
        std::printf("per frame (mean over %d frames): %.0f drawables drawn, %.0f triangles submitted\n",
                    statFrames, drawablesSum / statFrames, trianglesSum / statFrames);
    if (timeFrames > 0)
        std::printf("OSG camera stats (mean over %d frames): cull %.3f ms, draw dispatch %.3f ms (CPU, "
                    "before glFinish)\n",
                    timeFrames, cullSum / timeFrames, drawSum / timeFrames);
    std::printf("BENCH osg ms_per_frame=%.3f fps=%.2f frames=%d median_ms=%.3f size=%dx%d drawables=%.0f "
                "triangles=%.0f cull_ms=%.3f",
                mean, 1000.0 / mean, opt.frames, med, opt.width, opt.height,
                statFrames ? drawablesSum / statFrames : 0.0, statFrames ? trianglesSum / statFrames : 0.0,
                timeFrames ? cullSum / timeFrames : -1.0);
    if (shadowedScene)
        std::printf(" shadows=%d shadow_maps=%d shadow_map=%d shadow_distance=%g", opt.shadows, shadowMaps,
                    opt.shadowMap, double(opt.shadowDistance));
    std::printf("\n");

    // ---- the last frame as PNG, top row first
    if (!opt.out.empty()) {
        const std::size_t row = std::size_t(opt.width) * 3;
        std::vector<unsigned char> px(row * std::size_t(opt.height)), flipped(px.size());
        glPixelStorei(GL_PACK_ALIGNMENT, 1);
        glReadPixels(0, 0, opt.width, opt.height, GL_RGB, GL_UNSIGNED_BYTE, px.data());
        for (int y = 0; y < opt.height; ++y)
            std::memcpy(flipped.data() + std::size_t(y) * row,
                        px.data() + std::size_t(opt.height - 1 - y) * row, row);
        if (!opt.linearPng) {
            unsigned char lut[256];
            for (int i = 0; i < 256; ++i) {
                const double c = i / 255.0;
                const double e = c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055;
                lut[i] = static_cast<unsigned char>(std::lround(std::clamp(e, 0.0, 1.0) * 255.0));
            }
            for (unsigned char& c : flipped)
                c = lut[c];
        }
        if (!stbi_write_png(opt.out.c_str(), opt.width, opt.height, 3, flipped.data(), int(row))) {
            std::fprintf(stderr, "osg_polygon: cannot write %s\n", opt.out.c_str());
            return 1;
        }
        std::printf("wrote %s\n", opt.out.c_str());
    }

    return 0; // the viewer is destroyed first (its GL objects released in our context), then the context
}

// Reliability: GL error discipline, resource accounting over many create/destroy cycles, resize
// storms, a table-driven sweep of bad inputs, and the GL thread contract.
#include "GltfAnimDoc.h"
#include "TestUtil.h"

#include <CameraPath.h>
#include <PolygonScene.h>
#include <ProcessMemory.h>
#include <sgfx/CullVisitor.h>
#include <sgfx/Geometry.h>
#include <sgfx/GltfLoader.h>
#include <sgfx/GltfWriter.h>
#include <sgfx/Group.h>
#include <sgfx/LOD.h>
#include <sgfx/MeshTools.h>
#include <sgfx/ModelLoader.h>
#include <sgfx/ObjWriter.h>
#include <sgfx/ShaderComposer.h>
#include <sgfx/Shapes.h>
#include <sgfx/Simplify.h>
#include <sgfx/gl/Objects.h>
#include <sgfx/nodes/ao/AmbientOcclusionNode.h>
#include <sgfx/nodes/debugtint/DebugTintNode.h>
#include <sgfx/nodes/fog/FogNode.h>
#include <sgfx/nodes/particles/ParticleSystemNode.h>
#include <sgfx/nodes/sky/SkyNode.h>
#include <sgfx/nodes/transparency/TransparencyBin.h>
#include <sgfx/nodes/volume/VolumeNode.h>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>
#include <sgfx_glad/gl.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <random>
#include <set>
#include <span>
#include <thread>

using namespace sgfx;
using namespace sgfx::test;

namespace {

std::shared_ptr<Node> flatQuad(float size, glm::vec3 color, glm::vec3 pos = {0, 0, 0}) {
    auto t = Transform::create(glm::translate(glm::mat4(1.0f), pos));
    auto q = shapes::quad(size, size);
    auto m = Material::create();
    m->ambient = glm::vec3(0);
    m->diffuse = {0, 0, 0, 1};
    m->emissive = color;
    q->getOrCreateStateSet().material.set(m);
    t->addChild(q);
    return t;
}

// A blended flat quad (straight alpha, double-sided).
std::shared_ptr<Node> glassQuad(float size, glm::vec3 color, float alpha, glm::vec3 pos = {0, 0, 0}) {
    auto t = flatQuad(size, color, pos);
    auto& ss = static_cast<Group&>(*t).child(0)->getOrCreateStateSet();
    ss.material.value->get()->diffuse.a = alpha;
    ss.blend.set(BlendMode::Alpha);
    ss.cullFace.set(CullFace::None);
    return t;
}

std::vector<std::string> glErrors(Viewer& v) {
    return v.renderer().takeGlErrors();
}

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

} // namespace

// ------------------------------------------------------------------------ GL error discipline

TEST(GlErrors, AnErrorIsReportedWithItsCallSite) {
    auto v = orthoTopViewer(32, 2.0f);
    v->renderer().options().glErrors = RendererOptions::GlErrorPolicy::Collect;
    // A foreign shader whose uniform is a vec3, fed an int: GL_INVALID_OPERATION in glProgramUniform.
    const char* vs = "#version 450 core\nlayout(location = 0) in vec3 p;\nuniform mat4 sgfx_model;\n"
                     "void main() { gl_Position = sgfx_model * vec4(p * 0.1, 1.0); }\n";
    const char* fs = "#version 450 core\nuniform vec3 tint;\nlayout(location = 0) out vec4 o;\n"
                     "void main() { o = vec4(tint, 1.0); }\n";
    auto q = shapes::quad(1, 1);
    q->name = "misfed_quad";
    q->getOrCreateStateSet().program.set(ShaderProgram::create("misfed", vs, fs));
    q->getOrCreateStateSet().setUniform("tint", 3);
    v->setSceneData(q);
    v->frame();
    const auto errors = glErrors(*v);
    ASSERT_FALSE(errors.empty()) << "the driver reported nothing for a mistyped uniform";
    EXPECT_NE(errors[0].find("[main pass] drawing 'misfed_quad' with misfed"), std::string::npos)
        << errors[0];
    // Once drained, a clean frame reports nothing.
    q->getOrCreateStateSet().setUniform("tint", glm::vec3(1, 0, 0));
    v->frame();
    EXPECT_TRUE(glErrors(*v).empty());
    // Under the Throw policy (the test suite's default) the same mistake fails the frame.
    v->renderer().options().glErrors = RendererOptions::GlErrorPolicy::Throw;
    q->getOrCreateStateSet().setUniform("tint", 3);
    try {
        v->frame();
        FAIL() << "GL error did not throw";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("drawing 'misfed_quad'"), std::string::npos) << e.what();
    }
}

TEST(GlErrors, IncompleteOrImpossibleTargetsSayWhy) {
    auto v = orthoTopViewer(16, 1.0f);
    GLint maxTex = 0;
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &maxTex);
    v->camera()->setViewport(0, 0, maxTex + 1, 4);
    try {
        v->frame();
        FAIL() << "a target larger than the driver allows was accepted";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("outside the driver's 1x1.."), std::string::npos) << e.what();
    }
    v->camera()->setViewport(0, 0, 16, 16);
    EXPECT_NO_THROW(v->frame());
    EXPECT_TRUE(glErrors(*v).empty());
}

// ------------------------------------------------------------------------ resource accounting

TEST(Resources, ProvingGroundWithEveryEffectLeavesNothingBehind) {
    ASSERT_EQ(gl::liveObjects().total(), 0);
    {
        polygon::SceneOptions so;
        so.scale = 0.05f;
        const polygon::PolygonScene scene = polygon::buildPolygonScene(so);
        auto tint = DebugTintNode::create({0, 0, 1, 0.3f});
        tint->addChild(scene.vehicle);
        auto rtt = Camera::create(); // a render-to-texture camera is an effect on the frame too
        rtt->setViewport(0, 0, 32, 32);
        rtt->setLookAt({0, -30, 20}, {0, 0, 0});
        rtt->setPerspective(40, 1, 500);
        rtt->renderTarget = Texture::create(nullptr);
        rtt->addChild(scene.vehicle);
        auto fogNode = FogNode::create(FogParameters::ground());
        auto aoNode = AmbientOcclusionNode::create();
        aoNode->addChild(scene.root);
        fogNode->addChild(aoNode);
        auto root = Group::create();
        root->addChild(fogNode);
        root->addChild(tint);
        root->addChild(rtt);
        // Particles under the fog: soft smoke (its depth copies) and rain, their paths changing.
        auto smoke = ParticleSystemNode::smoke(1.0f, 200);
        auto rain = ParticleSystemNode::rain({20, 20}, 500);
        aoNode->addChild(smoke);
        aoNode->addChild(rain);
        // A smoke volume (its depth copy, half-size targets, slices) and the sky behind it all.
        auto cloud = VolumeNode::create({}, VolumeGrid::noise(16, 2, 2, 0.4f));
        auto cloudAt =
            Transform::create(glm::scale(glm::translate(glm::mat4(1.0f), {0, 0, 5}), glm::vec3(10.0f)));
        cloudAt->addChild(cloud);
        aoNode->addChild(cloudAt);
        auto skyNode = SkyNode::create();
        skyNode->attachFog(fogNode);
        root->addChild(skyNode);
        auto v = Viewer::createHeadless(96, 64);
        v->camera()->setLookAt({40, -60, 25}, {0, 0, 2});
        v->setSceneData(root);
        // Self-overlapping glass: the cabin's triangles sorted per view.
        TransparencyDetails perTriangle;
        perTriangle.sortTriangles = true;
        scene.glassBin->setDetails(perTriangle);
        for (FogMode mode : {FogMode::ForwardSplit, FogMode::PostProcess, FogMode::Forward})
            for (TransparencyMode t : {TransparencyMode::WeightedBlended, TransparencyMode::Sorted}) {
                fogNode->setMode(mode); // each mode's passes make their targets
                scene.glassBin->setMode(t);
                AmbientOcclusionParameters ap;
                ap.halfResolution = t == TransparencyMode::Sorted;
                ap.gbuffer = mode == FogMode::Forward ? AoGBuffer::PaperPositions : AoGBuffer::LinearDepth;
                aoNode->setParameters(ap);
                static const AntiAliasing modes[] = {AntiAliasing::msaa(4), AntiAliasing::ssaa(2),
                                                     AntiAliasing::fxaa(), AntiAliasing::taa(),
                                                     AntiAliasing::none()};
                static int m = 0;
                v->camera()->setAntiAliasing(modes[m++ % 5]);
                VolumeParameters vp;
                vp.scattering = 0.5f;
                vp.halfResolution = m % 3 == 1;
                vp.method = m % 3 == 2 ? VolumeMethod::Slicing : VolumeMethod::Raymarch;
                cloud->setParameters(vp);
                for (auto& p : {smoke, rain}) {
                    ParticleSettings ps = p->settings();
                    ps.path = ParticlePath(m % 5);
                    ps.layout = ParticleLayout(m % 2);
                    ps.capacity += 10; // grown: the buffers are remade with the live particles
                    p->setSettings(ps);
                }
                v->frame();
            }
        EXPECT_TRUE(glErrors(*v).empty());
        EXPECT_GT(gl::liveObjects().total(), 50);
    }
    EXPECT_EQ(gl::liveObjects().total(), 0);
    for (int k = 0; k < int(gl::Kind::Count); ++k)
        EXPECT_EQ(gl::liveObjects()[gl::Kind(k)], 0) << "kind " << k;
}

// A scene outlives the viewer that drew it (a model viewer reopening its window, a trainer
// restarting a headless render): ~Viewer must release the effect nodes' own targets while its
// context is current, and a second viewer must make them again and draw the same image.
TEST(Resources, AnEffectSceneOutlivesItsViewerAndIsDrawnTheSameByTheNext) {
    ASSERT_EQ(gl::liveObjects().total(), 0);
    auto root = Group::create();
    auto fogNode = FogNode::create(FogParameters::ground());
    auto aoNode = AmbientOcclusionNode::create();
    auto bin = TransparencyBin::create(TransparencyMode::WeightedBlended);
    bin->addChild(glassQuad(3, {0.2f, 0.8f, 0.3f}, 0.5f, {0, 0, 1.5f}));
    aoNode->addChild(flatQuad(20, {0.3f, 0.3f, 0.3f}));
    aoNode->addChild(shapes::box({2, 2, 2}));
    aoNode->addChild(bin);
    auto cloud = VolumeNode::create({}, VolumeGrid::noise(8, 2, 2, 0.4f));
    auto cloudAt = Transform::create(glm::translate(glm::mat4(1.0f), {3, 0, 2}));
    cloudAt->addChild(cloud);
    aoNode->addChild(cloudAt);
    fogNode->addChild(aoNode);
    auto skyNode = SkyNode::create();
    skyNode->attachFog(fogNode);
    root->addChild(fogNode);
    root->addChild(skyNode);
    auto light = Light::create(LightType::Directional);
    light->direction = glm::normalize(glm::vec3(-0.3f, 0.2f, -1.0f));
    root->addChild(light);

    for (FogMode mode : {FogMode::ForwardSplit, FogMode::PostProcess}) {
        fogNode->setMode(mode);
        auto draw = [&] {
            auto v = Viewer::createHeadless(64, 48);
            v->camera()->setLookAt({6, -9, 5}, {0, 0, 1});
            v->camera()->setAntiAliasing(AntiAliasing::msaa(4));
            v->setSceneData(root);
            v->frame();
            v->frame();
            EXPECT_TRUE(glErrors(*v).empty());
            return v->capture();
        };
        const Image first = draw();
        EXPECT_EQ(gl::liveObjects().total(), 0) << "GL objects kept after the viewer died";
        const Image second = draw();
        EXPECT_EQ(gl::liveObjects().total(), 0);
        EXPECT_EQ(channelsDiffering(first, second, 0), 0) << "fog mode " << int(mode);
    }
}

TEST(Resources, ThousandCreateDestroyCyclesOfEachEffectKeepMemoryFlat) {
    auto v = orthoTopViewer(24, 2.0f);
    auto root = Group::create();
    root->addChild(flatQuad(4, {0.2f, 0.4f, 0.6f}));
    v->setSceneData(root);
    const long baseline = gl::liveObjects().total();
    auto cycle = [&](int kind) {
        if (kind == 0) {
            auto tint = DebugTintNode::create({1, 0, 0, 0.5f});
            tint->addChild(flatQuad(1, {1, 1, 1}, {0, 0, 0.5f}));
            root->addChild(tint);
            v->frame();
            root->removeChild(tint.get());
        } else if (kind == 3) {
            // A transparency bin whose mode changes each cycle: OIT targets, per-triangle orders.
            static int n = 0;
            auto bin = TransparencyBin::create(TransparencyMode(n++ % 2));
            TransparencyDetails d;
            d.sortTriangles = true;
            bin->setDetails(d);
            bin->addChild(glassQuad(1, {1, 0, 0}, 0.5f, {0, 0, 0.5f}));
            bin->addChild(glassQuad(1, {0, 1, 0}, 0.5f, {0.2f, 0, 0.7f}));
            root->addChild(bin);
            v->frame();
            root->removeChild(bin.get());
        } else if (kind == 5) {
            // A render-to-texture camera with anti-aliasing, each cycle another mode.
            static int n = 0;
            static const AntiAliasing modes[] = {AntiAliasing::msaa(4), AntiAliasing::ssaa(2),
                                                 AntiAliasing::fxaa(), AntiAliasing::taa(),
                                                 AntiAliasing::none()};
            auto rtt = Camera::create();
            rtt->setViewport(0, 0, 8, 8);
            rtt->setLookAt({0, 0, 5}, {0, 0, 0}, {0, 1, 0});
            rtt->projectionMatrix = glm::ortho(-1.f, 1.f, -1.f, 1.f, 0.1f, 10.f);
            rtt->renderTarget = Texture::create(nullptr);
            rtt->setAntiAliasing(modes[n++ % 5]);
            rtt->addChild(flatQuad(1, {1, 1, 0}));
            root->addChild(rtt);
            v->frame();
            root->removeChild(rtt.get());
            v->frame(); // the renderer drops the dead camera's targets and AA state
        } else if (kind == 4) {
            // Ambient occlusion alternating full and half resolution, depth and position G-buffers.
            static int n = 0;
            AmbientOcclusionParameters p;
            p.halfResolution = n % 2 == 0;
            p.gbuffer = AoGBuffer(n++ / 2 % 2);
            auto ao = AmbientOcclusionNode::create(p);
            ao->addChild(flatQuad(1, {1, 1, 1}, {0, 0, 0.5f}));
            root->addChild(ao);
            v->frame();
            root->removeChild(ao.get());
        } else if (kind == 6) {
            // A particle system whose path, layout and shape change each cycle, soft every other.
            static int n = 0;
            ParticleSettings s;
            s.capacity = 64;
            s.path = ParticlePath(n % 5);
            s.layout = ParticleLayout(n / 5 % 2);
            s.shape = ParticleShape(n / 10 % 4);
            s.softness = n % 2 ? 0.5f : 0.0f;
            ++n;
            auto p = ParticleSystemNode::create(s);
            p->getOrCreateStateSet().blend.set(BlendMode::Premultiplied);
            root->addChild(p);
            v->frame();
            root->removeChild(p.get());
        } else if (kind == 7) {
            // A volume (raymarched, half size, sliced in turn) with a sky behind it.
            static int n = 0;
            VolumeParameters p;
            p.scattering = 0.3f;
            p.halfResolution = n % 3 == 1;
            p.method = n % 3 == 2 ? VolumeMethod::Slicing : VolumeMethod::Raymarch;
            ++n;
            auto group = Group::create();
            group->addChild(VolumeNode::create(p, VolumeGrid::sphere(8)));
            group->addChild(SkyNode::create());
            root->addChild(group);
            v->frame();
            root->removeChild(group.get());
        } else if (kind == 2) {
            // Fog in a mode that changes each cycle: pre-pass, sky and post-process targets.
            static int n = 0;
            auto fogNode = FogNode::create(FogParameters::ground(), FogMode(n++ % 3));
            fogNode->addChild(flatQuad(1, {1, 1, 1}, {0, 0, 0.5f}));
            root->addChild(fogNode);
            v->frame();
            root->removeChild(fogNode.get());
        } else {
            auto rtt = Camera::create();
            rtt->setViewport(0, 0, 8, 8);
            rtt->setLookAt({0, 0, 5}, {0, 0, 0}, {0, 1, 0});
            rtt->projectionMatrix = glm::ortho(-1.f, 1.f, -1.f, 1.f, 0.1f, 10.f);
            rtt->renderTarget = Texture::create(nullptr);
            rtt->addChild(flatQuad(1, {1, 1, 0}));
            root->addChild(rtt);
            v->frame();
            root->removeChild(rtt.get());
            v->frame(); // the renderer drops the dead camera's target
        }
    };
    const char* names[] = {"tint", "rtt", "fog", "transparency", "ao", "aa", "particles", "volume+sky"};
    for (int kind = 0; kind < 8; ++kind) {
        // Warm-up: program variants, and llvmpipe pools that level off after ~1000 frames.
        for (int i = 0; i < 1000; ++i)
            cycle(kind);
        // The renderer's pool keeps frame-graph textures for three frames after their last use.
        for (int i = 0; i < 4; ++i)
            v->frame();
        const long objects0 = gl::liveObjects().total();
        // Two blocks of 500 cycles. Mesa's state caches and malloc's arenas grow RSS in single
        // steps (1 MB jumps seen here, once 4.1 MB on CI) that level off; a leak grows in every
        // block, so only growth in both blocks fails.
        long growth[2] = {};
        for (long& g : growth) {
            const long rss0 = sgfxdemo::residentKb();
            for (int i = 0; i < 500; ++i)
                cycle(kind);
            for (int i = 0; i < 4; ++i)
                v->frame(); // the last cycle's dead camera target goes at the next frame, pooled ones later
            g = sgfxdemo::residentKb() - rss0;
        }
        const long steady = std::min(growth[0], growth[1]);
        RecordProperty(std::string(names[kind]) + "_rss_growth_kb", int(growth[0] + growth[1]));
        std::printf("effect %s: 2 x 500 cycles, RSS growth %ld + %ld kB\n", names[kind], growth[0],
                    growth[1]);
#ifndef __SANITIZE_ADDRESS__
        EXPECT_LT(steady, 2048) << "RSS grew by " << growth[0] << " and " << growth[1]
                                << " kB in two blocks of 500 cycles";
#else
        (void)steady; // AddressSanitizer's quarantine holds freed memory: RSS says nothing here
#endif
        // Every object a cycle made died with it (targets of dead cameras included).
        EXPECT_EQ(gl::liveObjects().total(), objects0);
        EXPECT_GE(objects0, baseline);
        EXPECT_TRUE(glErrors(*v).empty());
    }
}

// ------------------------------------------------------------------------ resize storm

namespace {

// Every effect visible at once: fog over everything, AO darkening a box's contact with the floor
// (ambient light), a tint, half-transparent glass in a switchable bin, opaque still particles,
// an emitting half-resolution volume. `without` names one effect to leave out ("" for none).
struct StormScene {
    std::shared_ptr<FogNode> root;
    std::shared_ptr<TransparencyBin> bin;
    std::shared_ptr<AmbientOcclusionNode> ao;
};

StormScene stormScene(const std::string& without = "") {
    FogParameters air;
    air.density = without == "fog" ? 0.0f : 0.04f;
    air.falloff = 0.0f;
    air.color = {0.6f, 0.2f, 0.6f};
    StormScene s{FogNode::create(air), TransparencyBin::create(), AmbientOcclusionNode::create()};
    auto ambient = Light::create(LightType::Ambient);
    ambient->color = glm::vec3(0.8f);
    s.root->addChild(ambient);
    auto lit = [](glm::vec3 c) {
        auto m = Material::create();
        m->ambient = c;
        m->diffuse = {0, 0, 0, 1};
        return m;
    };
    auto floor = shapes::quad(4.0f, 4.0f);
    floor->getOrCreateStateSet().material.set(lit({0.2f, 0.9f, 0.3f}));
    auto box = shapes::box({1.0f, 1.0f, 1.0f});
    box->getOrCreateStateSet().material.set(lit({0.9f, 0.9f, 0.9f}));
    auto boxAt = Transform::create(glm::translate(glm::mat4(1.0f), {-0.8f, 0.6f, 0.5f}));
    boxAt->addChild(box);
    auto occluded = Group::create();
    occluded->addChild(floor);
    occluded->addChild(boxAt);
    if (without == "ao")
        s.root->addChild(occluded);
    else {
        s.ao->addChild(occluded);
        s.root->addChild(s.ao);
    }
    auto orange = flatQuad(1.0f, {1.0f, 0.5f, 0.0f}, {0.9f, -0.9f, 0.05f});
    if (without == "tint")
        s.root->addChild(orange);
    else {
        auto tint = DebugTintNode::create({0, 0, 1, 0.25f});
        tint->addChild(orange);
        s.root->addChild(tint);
    }
    if (without != "glass") {
        s.bin->addChild(glassQuad(1.2f, {0.1f, 0.2f, 1.0f}, 0.5f, {0.9f, 0.9f, 0.4f}));
        s.root->addChild(s.bin);
    }
    if (without != "particles") {
        ParticleSettings still; // every particle at the emitter, never moving or ageing visibly
        still.capacity = 8;
        still.emitter.size = {0.0f, 0.0f};
        still.emitter.acceleration = glm::vec3(0.0f);
        still.emitter.lifetime = 1e5f;
        still.start = particles::StartMode::Burst;
        still.sizeStart = still.sizeEnd = 0.6f;
        still.colorStart = still.colorEnd = {1.0f, 1.0f, 0.0f, 1.0f};
        still.softness = 0.2f;
        auto at = Transform::create(glm::translate(glm::mat4(1.0f), {-1.2f, -1.2f, 1.0f}));
        at->addChild(ParticleSystemNode::create(still));
        s.root->addChild(at);
    }
    if (without != "volume") {
        VolumeParameters glow;
        glow.size = glm::vec3(0.8f);
        glow.absorption = 2.0f;
        glow.emission = {1.5f, 0.3f, 0.0f};
        glow.halfResolution = true;
        auto at = Transform::create(glm::translate(glm::mat4(1.0f), {0.0f, -1.2f, 0.5f}));
        at->addChild(VolumeNode::create(glow));
        s.root->addChild(at);
    }
    return s;
}

// One setting of the storm: bin mode, AO resolution, anti-aliasing, fog mode by frame index.
void stormSettings(StormScene& s, Viewer& v, int index, int w, int h, int maxW, int maxH) {
    s.bin->setMode(TransparencyMode(index % 2));
    AmbientOcclusionParameters ap;
    ap.halfResolution = index % 4 < 2;
    s.ao->setParameters(ap);
    // Anti-aliasing modes in turn; SSAA only where twice the size fits the driver.
    const AntiAliasing modes[] = {AntiAliasing::msaa(4),  AntiAliasing::fxaa(),  AntiAliasing::taa(),
                                  AntiAliasing::none(),   AntiAliasing::ssaa(2), AntiAliasing::smaa(),
                                  AntiAliasing::smaaT2x()};
    AntiAliasing aa = modes[index % 7];
    if (aa.mode == AntiAliasing::Mode::Ssaa && (2 * w > maxW || 2 * h > maxH)) aa = AntiAliasing::none();
    v.camera()->setAntiAliasing(aa);
    s.root->setMode(FogMode(index % 3));
    v.camera()->setViewport(0, 0, w, h);
}

// A perspective view from the south-west, above: the box's contact with the floor in sight.
std::unique_ptr<Viewer> stormViewer() {
    auto v = Viewer::createHeadless(32, 32);
    v->camera()->setPerspective(60.0f, 0.3f, 50.0f);
    v->camera()->computeNearFar = false;
    v->camera()->setLookAt({-1.6f, -3.0f, 2.6f}, {0.1f, 0.0f, 0.3f});
    v->camera()->clearColor = {0.1f, 0.1f, 0.3f, 1.0f};
    return v;
}

// The final setting (index 200: MSAA 4x, post-process fog, half-resolution AO, OIT) drawn once
// by a fresh viewer.
Image freshStormImage(const std::string& without, int index) {
    auto v = stormViewer();
    StormScene s = stormScene(without);
    v->setSceneData(s.root);
    stormSettings(s, *v, index, 64, 48, 1 << 14, 1 << 14);
    v->frame();
    return v->capture();
}

} // namespace

TEST(ResizeStorm, TwoHundredSizesIncludingExtremesThenTheImageAFreshViewerDraws) {
    // Every effect is visible, so a target left at a stale size, a lost history or a pass that
    // stopped drawing after the storm shows in the final image, which must equal the image a
    // fresh viewer draws of the same scene with the same settings.
    auto v = stormViewer();
    StormScene scene = stormScene();
    v->setSceneData(scene.root);
    GLint maxDims[2] = {0, 0}, maxTex = 0;
    glGetIntegerv(GL_MAX_VIEWPORT_DIMS, maxDims);
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &maxTex);
    const int maxW = std::min(maxDims[0], maxTex), maxH = std::min(maxDims[1], maxTex);
    std::vector<std::pair<int, int>> sizes = {{1, 1}, {maxW, 1}, {1, maxH}, {2, 3}};
    std::mt19937 rng(12345);
    std::uniform_int_distribution<int> side(1, 300);
    while (sizes.size() < 200)
        sizes.emplace_back(side(rng), side(rng));
    sizes.emplace_back(64, 48);
    int index = 0;
    for (const auto& [w, h] : sizes) {
        stormSettings(scene, *v, index++, w, h, maxW, maxH);
        ASSERT_NO_THROW(v->frame()) << w << "x" << h;
        const auto errors = glErrors(*v);
        ASSERT_TRUE(errors.empty()) << w << "x" << h << ": " << errors[0];
    }
    const int last = index - 1;
    const Image img = v->capture();
    ASSERT_EQ(img.width, 64);
    ASSERT_EQ(img.height, 48);
    const Image fresh = freshStormImage("", last);
    EXPECT_EQ(channelsDiffering(img, fresh, 2), 0)
        << "the image after the storm differs from a fresh viewer's";
    // Each effect is visible in that image: leaving it out changes many pixels.
    for (const char* effect : {"fog", "ao", "tint", "glass", "particles", "volume"}) {
        const int changed = channelsDiffering(fresh, freshStormImage(effect, last), 8);
        std::printf("resize storm: without %s, %d channels change\n", effect, changed);
        EXPECT_GT(changed, 30) << effect << " is not visible in the storm's scene";
    }
}

// ------------------------------------------------------------------------ bad-input sweep

namespace {

struct BadInput {
    std::string component;
    std::string label;
    std::function<void()> call;                // must throw std::exception
    std::string expect;                        // text the message must contain
    std::function<bool()> unchanged = nullptr; // previous state still in force
};

} // namespace

TEST(BadInputs, EverySetterAndLoaderRefusesWithAClearMessageAndKeepsItsState) {
    auto v = orthoTopViewer(16, 1.0f);
    auto scene = Group::create();
    auto quad = flatQuad(1, {1, 1, 1});
    scene->addChild(quad);
    v->setSceneData(scene);
    v->frame();

    std::vector<BadInput> cases;
    const float badFloats[] = {kNaN, kInf, -kInf, -1.0f, 0.0f, 1e30f};
    const std::string badNames[] = {"NaN", "+Inf", "-Inf", "negative", "zero", "huge"};

    // Camera
    auto cam = Camera::create();
    cam->setViewport(0, 0, 100, 50);
    cam->setPerspective(45, 1, 100);
    cam->setLookAt({0, -5, 2}, {0, 0, 0});
    const glm::mat4 camProj = cam->projectionMatrix, camView = cam->viewMatrix;
    auto camSame = [=] {
        return cam->projectionMatrix == camProj && cam->viewMatrix == camView && cam->fovy() == 45.0f &&
               cam->zNear() == 1.0f && cam->zFar() == 100.0f && cam->viewport.width == 100;
    };
    for (int i = 0; i < 6; ++i) {
        if (badNames[i] != "huge")
            cases.push_back({"Camera", "setPerspective fovy " + badNames[i],
                             [=] { cam->setPerspective(badFloats[i], 1, 100); }, "fovy", camSame});
        if (badNames[i] != "huge")
            cases.push_back({"Camera", "setPerspective near " + badNames[i],
                             [=] { cam->setPerspective(45, badFloats[i], 100); }, "near", camSame});
        cases.push_back({"Camera", "setPerspective far " + badNames[i],
                         [=] { cam->setPerspective(45, 1e31f, badFloats[i]); }, "near", camSame});
        if (std::isnan(badFloats[i]) || std::isinf(badFloats[i]))
            cases.push_back({"Camera", "setLookAt eye " + badNames[i],
                             [=] {
                                 cam->setLookAt({badFloats[i], 0, 0}, {0, 0, 0});
                             },
                             "setLookAt", camSame});
    }
    cases.push_back(
        {"Camera", "setPerspective fovy 180", [=] { cam->setPerspective(180, 1, 100); }, "fovy", camSame});
    cases.push_back({"Camera", "setLookAt eye == centre",
                     [=] {
                         cam->setLookAt({1, 1, 1}, {1, 1, 1});
                     },
                     "eye", camSame});
    cases.push_back({"Camera", "setLookAt along up",
                     [=] {
                         cam->setLookAt({0, 0, 5}, {0, 0, 0});
                     },
                     "parallel", camSame});
    cases.push_back({"Camera", "setLookAt zero up",
                     [=] {
                         cam->setLookAt({0, -5, 0}, {0, 0, 0}, {0, 0, 0});
                     },
                     "parallel", camSame});
    for (auto [w, h] : {std::pair{0, 10}, {10, 0}, {-5, 10}, {10, -5}, {std::numeric_limits<int>::min(), 1}})
        cases.push_back({"Camera", "setViewport " + std::to_string(w) + "x" + std::to_string(h),
                         [=] { cam->setViewport(0, 0, w, h); }, "must be positive", camSame});
    cases.push_back({"Camera", "viewport beyond the driver, at frame time",
                     [&] {
                         v->camera()->setViewport(0, 0, 1 << 30, 1 << 30);
                         struct Restore {
                             Viewer& viewer;
                             ~Restore() { viewer.camera()->setViewport(0, 0, 16, 16); }
                         } restore{*v};
                         v->frame();
                     },
                     "outside the driver's",
                     [&] {
                         v->frame();
                         return v->capture().width == 16;
                     }});

    // Transform
    auto xf = Transform::create(glm::translate(glm::mat4(1), {1, 2, 3}));
    const glm::mat4 xfm = xf->matrix();
    for (int i = 0; i < 3; ++i) {
        cases.push_back({"Transform", "setMatrix with " + badNames[i],
                         [=] {
                             glm::mat4 m(1.0f);
                             m[3][1] = badFloats[i];
                             xf->setMatrix(m);
                         },
                         "non-finite", [=] { return xf->matrix() == xfm; }});
        cases.push_back({"Transform", "create with " + badNames[i],
                         [=] { (void)Transform::create(glm::mat4(badFloats[i])); }, "non-finite"});
    }

    // Group
    auto g = Group::create();
    g->name = "holder";
    auto kid = Group::create();
    g->addChild(kid);
    auto gSame = [=] { return g->numChildren() == 1 && g->child(0) == kid && kid->parents().size() == 1; };
    cases.push_back({"Group", "addChild null", [=] { g->addChild(nullptr); }, "null child", gSame});
    cases.push_back({"Group", "addChild self", [=] { g->addChild(g); }, "cycle", gSame});
    cases.push_back({"Group", "addChild ancestor", [=] { kid->addChild(g); }, "cycle", gSame});
    cases.push_back({"Group", "insertChild null", [=] { g->insertChild(0, nullptr); }, "null child", gSame});
    cases.push_back({"Group", "replaceChild out of range", [=] { g->replaceChild(7, Group::create()); },
                     "out of range", gSame});
    cases.push_back(
        {"Group", "replaceChild null", [=] { g->replaceChild(0, nullptr); }, "null child", gSame});
    cases.push_back({"Group", "replaceChild cycle", [=] { g->replaceChild(0, g); }, "cycle", gSame});

    // DebugTintNode
    auto tint = DebugTintNode::create({0.1f, 0.2f, 0.3f, 0.4f});
    auto tintSame = [=] { return tint->tint() == glm::vec4(0.1f, 0.2f, 0.3f, 0.4f); };
    for (int c = 0; c < 4; ++c)
        for (int i = 0; i < 3; ++i)
            cases.push_back({"DebugTintNode", "setTint component " + std::to_string(c) + " " + badNames[i],
                             [=] {
                                 glm::vec4 t(0.5f);
                                 t[c] = badFloats[i];
                                 tint->setTint(t);
                             },
                             "not finite", tintSame});
    for (float a : {-0.1f, 1.5f, 1e30f})
        cases.push_back({"DebugTintNode", "setTint amount " + std::to_string(a),
                         [=] {
                             tint->setTint({1, 1, 1, a});
                         },
                         "must be in [0, 1]", tintSame});
    cases.push_back({"DebugTintNode", "create with NaN",
                     [] {
                         (void)DebugTintNode::create({kNaN, 0, 0, 0});
                     },
                     "not finite"});

    // FogNode
    auto fogNode = FogNode::create(FogParameters::ground(), FogMode::ForwardSplit);
    auto fogSame = [=] {
        return fogNode->parameters().density == 1e-3f && fogNode->parameters().falloff == 4.5e-3f &&
               fogNode->mode() == FogMode::ForwardSplit;
    };
    auto fogCase = [&](std::string label, std::function<void(FogParameters&)> edit, std::string expect) {
        cases.push_back({"FogNode", std::move(label),
                         [=] {
                             FogParameters p = FogParameters::ground();
                             edit(p);
                             fogNode->setParameters(p);
                         },
                         std::move(expect), fogSame});
    };
    for (int i = 0; i < 6; ++i) {
        const float bad = badFloats[i];
        const bool finite = std::isfinite(bad);
        if (badNames[i] != "zero") {
            if (bad < 0.0f || !finite || bad > 1e6f)
                fogCase(
                    "density " + badNames[i], [=](FogParameters& p) { p.density = bad; },
                    finite ? "outside" : "finite");
            fogCase(
                "skyDistance " + badNames[i], [=](FogParameters& p) { p.skyDistance = bad; }, "skyDistance");
        } else {
            fogCase(
                "up zero", [](FogParameters& p) { p.up = glm::vec3(0.0f); }, "zero length");
            fogCase(
                "skyDistance zero", [](FogParameters& p) { p.skyDistance = 0.0f; }, "skyDistance");
        }
        if (bad < 0.0f || !finite || bad > 1e3f)
            fogCase(
                "falloff " + badNames[i], [=](FogParameters& p) { p.falloff = bad; },
                finite ? "outside" : "finite");
        if (bad < 0.0f || !finite || bad > 1e6f)
            for (int c = 0; c < 3; ++c)
                fogCase(
                    "color[" + std::to_string(c) + "] " + badNames[i],
                    [=](FogParameters& p) { p.color[c] = bad; }, "color[" + std::to_string(c) + "]");
        if (!finite) {
            fogCase(
                "referenceHeight " + badNames[i], [=](FogParameters& p) { p.referenceHeight = bad; },
                "referenceHeight");
            fogCase(
                "up.y " + badNames[i], [=](FogParameters& p) { p.up.y = bad; }, "up[1]");
        }
        if (bad < 0.0f || !finite || bad > 1.0f)
            fogCase(
                "maxOpacity " + badNames[i], [=](FogParameters& p) { p.maxOpacity = bad; }, "maxOpacity");
    }
    fogCase(
        "response 7", [](FogParameters& p) { p.response = FogResponse(7); }, "response");
    fogCase(
        "sky 9", [](FogParameters& p) { p.sky = FogSky(9); }, "sky has an invalid");
    cases.push_back({"FogNode", "setMode 3", [=] { fogNode->setMode(FogMode(3)); }, "invalid mode", fogSame});
    cases.push_back({"FogNode", "create with NaN density",
                     [] {
                         FogParameters p;
                         p.density = kNaN;
                         (void)FogNode::create(p);
                     },
                     "density"});

    // TransparencyBin and TransparencyDetails
    auto bin = TransparencyBin::create(TransparencyMode::WeightedBlended);
    auto binSame = [=] {
        return bin->mode() == TransparencyMode::WeightedBlended && bin->oitParameters().depthScale == 1.0f &&
               bin->oitParameters().weight == OitWeight::Depth7 && !bin->stateSet()->transparency.value;
    };
    cases.push_back({"TransparencyBin", "setMode 2", [=] { bin->setMode(TransparencyMode(2)); },
                     "invalid mode", binSame});
    cases.push_back({"TransparencyBin", "weight 5",
                     [=] {
                         OitParameters p;
                         p.weight = OitWeight(5);
                         bin->setOitParameters(p);
                     },
                     "weight", binSame});
    for (int i = 0; i < 6; ++i) {
        cases.push_back({"TransparencyBin", "depthScale " + badNames[i],
                         [=] {
                             OitParameters p;
                             p.depthScale = badFloats[i];
                             bin->setOitParameters(p);
                         },
                         "depthScale", binSame});
        if (std::isnan(badFloats[i]) || std::isinf(badFloats[i]) || badNames[i] == "huge")
            cases.push_back({"TransparencyBin", "setDetails depthBias " + badNames[i],
                             [=] {
                                 TransparencyDetails d;
                                 d.depthBias = badFloats[i];
                                 bin->setDetails(d);
                             },
                             "depthBias", binSame});
        if (badNames[i] != "zero")
            cases.push_back({"TransparencyBin", "setDetails resortAngle " + badNames[i],
                             [=] {
                                 TransparencyDetails d;
                                 d.resortAngle = badNames[i] == "negative" ? -1.0f : badFloats[i];
                                 bin->setDetails(d);
                             },
                             "resortAngle", binSame});
    }
    cases.push_back({"StateSet", "transparency depthBias NaN, at frame time",
                     [&] {
                         TransparencyDetails d;
                         d.depthBias = kNaN;
                         auto pane = glassQuad(1, {1, 1, 1}, 0.5f);
                         static_cast<Group&>(*pane).child(0)->getOrCreateStateSet().transparency.set(d);
                         scene->addChild(pane);
                         struct Remove {
                             Group& g;
                             Node* n;
                             ~Remove() { g.removeChild(n); }
                         } remove{*scene, pane.get()};
                         v->frame();
                     },
                     "depthBias",
                     [&] {
                         v->frame();
                         return scene->numChildren() == 1 && glErrors(*v).empty();
                     }});

    // Camera::setAntiAliasing
    auto aaCam = Camera::create();
    aaCam->setAntiAliasing(AntiAliasing::msaa(4));
    auto aaSame = [=] { return aaCam->antiAliasing() == AntiAliasing::msaa(4); };
    auto aaCase = [&](std::string label, AntiAliasing a, std::string expect) {
        cases.push_back({"AntiAliasing", std::move(label), [=] { aaCam->setAntiAliasing(a); },
                         std::move(expect), aaSame});
    };
    for (int n : {0, -1, 65, 1 << 30})
        aaCase("msaa samples " + std::to_string(n), AntiAliasing::msaa(n), "samples");
    for (int f : {0, -2, 5, 100})
        aaCase("ssaa factor " + std::to_string(f), AntiAliasing::ssaa(f), "factor");
    for (float fb : {kNaN, kInf, -0.1f, 0.99f, 1.0f})
        aaCase("taa feedback " + std::to_string(fb), AntiAliasing::taa(fb), "taaFeedback");
    {
        AntiAliasing m;
        m.mode = AntiAliasing::Mode(9);
        aaCase("mode 9", m, "mode");
        AntiAliasing q = AntiAliasing::fxaa();
        q.fxaaQuality = AntiAliasing::FxaaQuality(7);
        aaCase("fxaa quality 7", q, "fxaaQuality");
    }

    // ParticleSystemNode: every bad value is refused and the running system keeps its settings
    // (its own viewer: the draw-time cases below break the shared scene's state on purpose)
    std::shared_ptr<Viewer> particleViewer = orthoTopViewer(16, 1.0f);
    auto particles = ParticleSystemNode::create();
    particleViewer->setSceneData(particles);
    particleViewer->frame();
    Viewer* viewer = particleViewer.get();
    auto particlesSame = [=] {
        viewer->frame(); // still stepping and drawing
        const ParticleSettings& s = particles->settings();
        return s.capacity == 10000 && s.emitter.lifetime == 1.0f && s.sizeStart == 0.1f &&
               particles->readRecords().size() == 10000;
    };
    auto particleCase = [&](std::string label, std::function<void(ParticleSettings&)> edit,
                            std::string expect) {
        cases.push_back({"ParticleSystemNode", std::move(label),
                         [=] {
                             ParticleSettings s;
                             edit(s);
                             particles->setSettings(s);
                         },
                         std::move(expect), particlesSame});
    };
    for (int i = 0; i < 6; ++i) {
        const float bad = badFloats[i];
        const bool finiteOk = badNames[i] == "zero" || badNames[i] == "huge";
        if (badNames[i] != "huge")
            particleCase(
                "tmax " + badNames[i], [=](auto& s) { s.emitter.lifetime = bad; }, "tmax");
        if (!finiteOk) {
            particleCase(
                "W " + badNames[i], [=](auto& s) { s.emitter.size.x = bad; }, "W");
            particleCase(
                "kv " + badNames[i], [=](auto& s) { s.emitter.velocitySpread = bad; }, "kv");
            particleCase(
                "kvel " + badNames[i], [=](auto& s) { s.emitter.rotationSpeed = bad; }, "kvel");
            particleCase(
                "sizeEnd " + badNames[i], [=](auto& s) { s.sizeEnd = bad; }, "sizeEnd");
            particleCase(
                "softness " + badNames[i], [=](auto& s) { s.softness = bad; }, "softness");
            particleCase(
                "stretch " + badNames[i], [=](auto& s) { s.stretch = bad; }, "stretch");
        }
        if (badNames[i] != "negative" && !finiteOk) { // vectors may point anywhere, but be finite
            particleCase(
                "v0 " + badNames[i], [=](auto& s) { s.emitter.velocity.x = bad; }, "v0");
            particleCase(
                "acceleration " + badNames[i], [=](auto& s) { s.emitter.acceleration.z = bad; },
                "acceleration");
        }
        if (badNames[i] != "zero")
            particleCase(
                "krot " + badNames[i], [=](auto& s) { s.emitter.rotationRange = bad; }, "krot");
    }
    for (std::uint32_t n : {0u, ParticleSystemNode::kMaxCapacity + 1, 0xffffffffu})
        particleCase(
            "capacity " + std::to_string(n), [=](auto& s) { s.capacity = n; }, "capacity");
    particleCase(
        "shape 7", [](auto& s) { s.shape = ParticleShape(7); }, "shape");
    particleCase(
        "path 9", [](auto& s) { s.path = ParticlePath(9); }, "path");
    particleCase(
        "layout 3", [](auto& s) { s.layout = ParticleLayout(3); }, "layout");
    particleCase(
        "respawn 4", [](auto& s) { s.respawn = particles::Respawn(4); }, "respawn");
    particleCase(
        "colorStart alpha 2", [](auto& s) { s.colorStart.a = 2.0f; }, "colorStart");
    cases.push_back(
        {"ParticleSystemNode", "advance NaN", [=] { particles->advance(kNaN); }, "dt", particlesSame});
    cases.push_back(
        {"ParticleSystemNode", "queueStep -1", [=] { particles->queueStep(-1.0f); }, "dt", particlesSame});
    cases.push_back({"ParticleSystemNode", "waterJet direction 0",
                     [] { (void)ParticleSystemNode::waterJet(glm::vec3(0.0f)); }, "direction"});

    // VolumeNode and SkyNode
    auto volumeNode = VolumeNode::create();
    auto volumeSame = [=] {
        return volumeNode->parameters().absorption == 1.0f && volumeNode->parameters().steps == 64;
    };
    auto volumeCase = [&](std::string label, std::function<void(VolumeParameters&)> edit,
                          std::string expect) {
        cases.push_back({"VolumeNode", std::move(label),
                         [=] {
                             VolumeParameters p;
                             edit(p);
                             volumeNode->setParameters(p);
                         },
                         std::move(expect), volumeSame});
    };
    for (int i = 0; i < 6; ++i) {
        const float bad = badFloats[i];
        if (badNames[i] != "zero" && badNames[i] != "huge") {
            volumeCase(
                "absorption " + badNames[i], [=](auto& p) { p.absorption = bad; }, "absorption");
            volumeCase(
                "scattering " + badNames[i], [=](auto& p) { p.scattering = bad; }, "scattering");
            volumeCase(
                "emission " + badNames[i], [=](auto& p) { p.emission.g = bad; }, "emission");
            volumeCase(
                "densityScale " + badNames[i], [=](auto& p) { p.densityScale = bad; }, "densityScale");
            volumeCase(
                "stepLength " + badNames[i], [=](auto& p) { p.stepLength = bad; }, "stepLength");
        }
        if (badNames[i] != "huge")
            volumeCase(
                "size " + badNames[i], [=](auto& p) { p.size.x = bad; }, "size");
        if (badNames[i] != "zero" && badNames[i] != "negative")
            volumeCase(
                "g " + badNames[i], [=](auto& p) { p.g = bad; }, "g");
        if (badNames[i] != "huge" && badNames[i] != "negative")
            volumeCase(
                "earlyTermination " + badNames[i], [=](auto& p) { p.earlyTermination = bad; },
                "earlyTermination");
    }
    for (int n : {0, -3, 5000})
        volumeCase(
            "steps " + std::to_string(n), [=](auto& p) { p.steps = n; }, "steps");
    for (int n : {0, 300})
        volumeCase(
            "lightSteps " + std::to_string(n), [=](auto& p) { p.lightSteps = n; }, "lightSteps");
    for (int n : {1, 5000})
        volumeCase(
            "slices " + std::to_string(n), [=](auto& p) { p.slices = n; }, "slices");
    volumeCase(
        "lightDirection zero", [](auto& p) { p.lightDirection = glm::vec3(0.0f); }, "lightDirection");
    volumeCase(
        "phase 7", [](auto& p) { p.phase = VolumePhase(7); }, "phase");
    volumeCase(
        "method 4", [](auto& p) { p.method = VolumeMethod(4); }, "method");
    volumeCase(
        "integration 3", [](auto& p) { p.integration = volume::Integration(3); }, "integration");
    cases.push_back({"VolumeNode", "grid with a NaN voxel",
                     [=] {
                         VolumeGrid grid = VolumeGrid::constant(1.0f);
                         grid.values[5] = kNaN;
                         volumeNode->setGrid(grid);
                     },
                     "voxel 5", volumeSame});
    cases.push_back({"VolumeNode", "grid of size 0",
                     [=] {
                         VolumeGrid grid;
                         volumeNode->setGrid(grid);
                     },
                     "size", volumeSame});
    cases.push_back({"VolumeNode", "R8 grid above 1",
                     [=] {
                         VolumeGrid grid = VolumeGrid::constant(2.0f);
                         grid.format = VolumeGrid::Format::R8;
                         volumeNode->setGrid(grid);
                     },
                     "R8", volumeSame});
    cases.push_back(
        {"VolumeNode", "raw file missing",
         [] {
             (void)VolumeGrid::loadRaw("/nonexistent/cloud.raw", {4, 4, 4}, VolumeGrid::Format::R8);
         },
         "cannot open"});
    cases.push_back({"VolumeNode", "raw size 0",
                     [] {
                         (void)VolumeGrid::loadRaw("/dev/null", {0, 4, 4}, VolumeGrid::Format::R8);
                     },
                     "size"});
    cases.push_back(
        {"VolumeNode", "empty density function", [] { (void)VolumeNode::createFunction({}, ""); }, "empty"});
    auto skyNode = SkyNode::create();
    auto skySame = [=] {
        return skyNode->parameters().steps == 16 && skyNode->parameters().sunIntensity == 20.0f;
    };
    auto skyCase = [&](std::string label, std::function<void(SkyParameters&)> edit, std::string expect) {
        cases.push_back({"SkyNode", std::move(label),
                         [=] {
                             SkyParameters p;
                             edit(p);
                             skyNode->setParameters(p);
                         },
                         std::move(expect), skySame});
    };
    for (int i = 0; i < 6; ++i) {
        const float bad = badFloats[i];
        if (badNames[i] != "zero" && badNames[i] != "huge") {
            skyCase(
                "sunIntensity " + badNames[i], [=](auto& p) { p.sunIntensity = bad; }, "sunIntensity");
            skyCase(
                "rayleigh " + badNames[i], [=](auto& p) { p.atmosphere.rayleigh.b = bad; }, "rayleigh");
            skyCase(
                "mie " + badNames[i], [=](auto& p) { p.atmosphere.mie = bad; }, "mie");
        }
        skyCase(
            "rayleighHeight " + badNames[i], [=](auto& p) { p.atmosphere.rayleighHeight = bad; },
            "rayleighHeight");
    }
    skyCase(
        "sunDirection zero", [](auto& p) { p.sunDirection = glm::vec3(0.0f); }, "sunDirection");
    skyCase(
        "atmosphere inside the planet", [](auto& p) { p.atmosphere.atmosphereRadius = 1000.0f; },
        "atmosphereRadius");
    skyCase(
        "steps 0", [](auto& p) { p.steps = 0; }, "steps");
    skyCase(
        "lightSteps 100", [](auto& p) { p.lightSteps = 100; }, "lightSteps");
    skyCase(
        "mieG 1", [](auto& p) { p.atmosphere.mieG = 1.0f; }, "mieG");

    // AmbientOcclusionNode
    auto aoNode = AmbientOcclusionNode::create();
    auto aoSame = [=] {
        const AmbientOcclusionParameters& p = aoNode->parameters();
        return p.samples == 32 && p.radius == 0.5f && p.bias == 0.025f && p.blurSize == 5;
    };
    auto aoCase = [&](std::string label, std::function<void(AmbientOcclusionParameters&)> edit,
                      std::string expect) {
        cases.push_back({"AmbientOcclusionNode", std::move(label),
                         [=] {
                             AmbientOcclusionParameters p;
                             edit(p);
                             aoNode->setParameters(p);
                         },
                         std::move(expect), aoSame});
    };
    for (int i = 0; i < 6; ++i) {
        const float bad = badFloats[i];
        aoCase(
            "radius " + badNames[i], [=](auto& p) { p.radius = bad; }, "radius");
        if (badNames[i] != "zero")
            aoCase(
                "bias " + badNames[i], [=](auto& p) { p.bias = bad; }, "bias");
        if (badNames[i] != "zero")
            aoCase(
                "intensity " + badNames[i], [=](auto& p) { p.intensity = bad; }, "intensity");
        aoCase(
            "power " + badNames[i], [=](auto& p) { p.power = bad; }, "power");
    }
    for (int m : {0, 7, 65, -32, 1 << 30})
        aoCase(
            "samples " + std::to_string(m), [=](auto& p) { p.samples = m; }, "samples");
    for (int n : {0, 2, 17, -1})
        aoCase(
            "blurSize " + std::to_string(n), [=](auto& p) { p.blurSize = n; }, "blurSize");
    aoCase(
        "kernel 9", [](auto& p) { p.kernel = AoKernel(9); }, "kernel");
    aoCase(
        "compare 9", [](auto& p) { p.compare = AoCompare(9); }, "compare");
    aoCase(
        "blur 9", [](auto& p) { p.blur = AoBlur(9); }, "blur has");
    aoCase(
        "gbuffer 9", [](auto& p) { p.gbuffer = AoGBuffer(9); }, "gbuffer");
    aoCase(
        "debugView 9", [](auto& p) { p.debugView = AoDebugView(9); }, "debugView");

    // Image and PNG files
    for (auto [w, h, c] : {std::tuple{0, 4, 4},
                           {4, 0, 4},
                           {-1, 4, 4},
                           {4, 4, 0},
                           {4, 4, 5},
                           {1 << 20, 1 << 20, 4},
                           {std::numeric_limits<int>::max(), 2, 1}})
        cases.push_back({"Image",
                         "create " + std::to_string(w) + "x" + std::to_string(h) + "x" + std::to_string(c),
                         [=] { (void)Image::create(w, h, c); }, "Image::create"});
    const auto tmp = std::filesystem::temp_directory_path();
    const auto garbage = tmp / "sgfx_not_a_png.png";
    std::ofstream(garbage) << "this is not a PNG file";
    const auto truncated = tmp / "sgfx_truncated.png";
    {
        writePng(truncated, *Image::create(8, 8, 3));
        std::filesystem::resize_file(truncated, 30);
    }
    for (const auto& [label, path] :
         std::vector<std::pair<std::string, std::filesystem::path>>{{"empty path", ""},
                                                                    {"missing file", "/nonexistent/x.png"},
                                                                    {"not a PNG", garbage},
                                                                    {"truncated", truncated},
                                                                    {"a directory", tmp}})
        cases.push_back({"PNG", "readPng " + label, [=] { (void)readPng(path); }, "could not read image"});
    cases.push_back({"PNG", "writePng empty image", [=] { writePng(tmp / "sgfx_x.png", Image{}); },
                     "empty or inconsistent"});
    cases.push_back({"PNG", "writePng bad directory",
                     [=] { writePng("/nonexistent/dir/x.png", *Image::create(2, 2, 4)); },
                     "could not write PNG"});
    cases.push_back({"PNG", "writePng short pixel buffer",
                     [=] {
                         Image img = *Image::create(4, 4, 4);
                         img.pixels.resize(3);
                         writePng(tmp / "sgfx_x.png", img);
                     },
                     "empty or inconsistent"});

    // glTF loader: files that are not glTF
    for (const auto& [label, path] :
         std::vector<std::pair<std::string, std::filesystem::path>>{{"empty path", ""},
                                                                    {"missing file", "/nonexistent/x.gltf"},
                                                                    {"a PNG-named text file", garbage},
                                                                    {"a truncated PNG", truncated},
                                                                    {"a directory", tmp}})
        cases.push_back({"glTF loader", "loadGltf " + label, [=] { (void)loadGltf(path); }, "sgfx: glTF"});
    // glTF loader: animations, skins and morph targets, one element broken each (GltfAnimDoc.h)
    for (const AnimBreak& b : animBreaks())
        cases.push_back({"glTF animation", std::string("loadGltfFromMemory ") + b.label,
                         [json = animDocument(b.from, b.to)] {
                             (void)loadGltfFromMemory(std::as_bytes(std::span(json.data(), json.size())), "x.gltf");
                         },
                         b.element});
    cases.push_back({"model loader", "loadModel unknown extension", [=] { (void)loadModel(tmp / "x.fbx"); },
                     ".gltf, .glb, .obj, .off, .ply, .stl"});
    // OpenSceneGraph formats: empty, garbage and cut files in each, through loadModel (loadOsg, or the
    // message saying the bridge is not built). Every one names its file.
    for (const char* ext : {".osgt", ".osgb", ".osgx", ".ive", ".osg", ".flt"}) {
        const auto empty = tmp / (std::string("sgfx_empty") + ext);
        std::ofstream(empty).close();
        const auto noise = tmp / (std::string("sgfx_noise") + ext);
        {
            std::ofstream out(noise, std::ios::binary);
            for (int i = 0; i < 2048; ++i)
                out.put(char((i * 2654435761u) >> 11));
        }
        const auto cut = tmp / (std::string("sgfx_cut") + ext);
        std::ofstream(cut)
            << "#Ascii Scene\n#Version 161\nosg::Group {\n  UniqueID 1\n  Children 1 {\n    osg::Geode {";
        for (const auto& [label, path] : std::vector<std::pair<std::string, std::filesystem::path>>{
                 {"empty", empty}, {"garbage", noise}, {"cut after a node's opening", cut}}) {
            // The old .osg reader takes this cut .osgt text as an empty scene (osg_loader_test
            // cuts real .osg files).
            if (std::string(ext) == ".osg" && path == cut) continue;
            cases.push_back({"OSG loader", std::string("loadModel ") + ext + " " + label,
                             [=] { (void)loadModel(path); }, path.filename().string()});
        }
    }
    cases.push_back({"glTF writer", "writeGltf unwritable path",
                     [=] { (void)writeGltf(*scene, "/nonexistent/dir/x.glb"); }, "/nonexistent/dir/x.glb"});

    // Metallic-roughness material fields and texture mappings
    for (int i = 0; i < 6; ++i) {
        if (badNames[i] == "zero") continue; // 0 is a valid value for all of them
        const float b = badFloats[i];
        cases.push_back({"Material", "metallic " + badNames[i],
                         [=] {
                             auto m = Material::create();
                             m->metallic = b;
                             m->validate();
                         },
                         "metallic"});
        cases.push_back({"Material", "roughness " + badNames[i],
                         [=] {
                             auto m = Material::create();
                             m->roughness = b;
                             m->validate();
                         },
                         "roughness"});
        cases.push_back({"Material", "occlusionStrength " + badNames[i],
                         [=] {
                             auto m = Material::create();
                             m->occlusionStrength = b;
                             m->validate();
                         },
                         "occlusionStrength"});
        if (!std::isfinite(b))
            cases.push_back({"Material", "mapping rotation " + badNames[i],
                             [=] {
                                 auto m = Material::create();
                                 m->mapping(MaterialMap::Normal).rotation = b;
                                 m->validate();
                             },
                             "mappings[2]"});
    }
    for (int set : {-1, 2, 7})
        cases.push_back({"Material", "mapping texCoord " + std::to_string(set),
                         [=] {
                             auto m = Material::create();
                             m->mapping(MaterialMap::Occlusion).texCoord = set;
                             m->validate();
                         },
                         "mappings[4]"});
    cases.push_back({"Material", "shading model 9",
                     [] {
                         auto m = Material::create();
                         m->model = ShadingModel(9);
                         m->validate();
                     },
                     "ShadingModel"});
    cases.push_back({"Geometry", "NaN instance matrix",
                     [] {
                         auto geo = shapes::quad(1, 1);
                         geo->instances = {glm::mat4(1.0f), glm::mat4(kNaN)};
                         geo->validate();
                     },
                     "instances[1]"});
    // Mesh processing
    cases.push_back({"MeshTools", "computeNormals NaN crease",
                     [] { computeNormals(*shapes::quad(1, 1), kNaN); }, "crease angle"});
    cases.push_back({"MeshTools", "computeNormals on lines",
                     [] {
                         auto geo = Geometry::create();
                         geo->positions = {{0, 0, 0}, {1, 0, 0}};
                         geo->mode = PrimitiveMode::Lines;
                         computeNormals(*geo, 0.0f);
                     },
                     "not made of triangles"});
    cases.push_back({"MeshTools", "computeTangents without texcoords",
                     [] {
                         auto geo = shapes::quad(1, 1);
                         geo->texcoords.clear();
                         computeTangents(*geo);
                     },
                     "needs normals and texcoords"});
    for (int i = 0; i < 6; ++i) {
        if (badNames[i] == "huge") continue;
        const float b = badFloats[i];
        cases.push_back(
            {"Simplify", "ratio " + badNames[i], [=] { (void)simplify(*shapes::sphere(1), b); }, "ratio"});
        cases.push_back({"LOD", "range min " + badNames[i],
                         [=] {
                             auto lod = LOD::create();
                             lod->addChild(shapes::quad(1, 1), b, b < 0 ? 10.0f : b - 1.0f);
                         },
                         "LOD"});
    }

    // Procedural shapes (the loaders' procedural part)
    for (int i = 0; i < 6; ++i) {
        if (badNames[i] == "huge") continue; // a huge size is a valid (if odd) shape
        const float b = badFloats[i];
        cases.push_back({"shapes", "box " + badNames[i],
                         [=] {
                             (void)shapes::box({1, b, 1});
                         },
                         "box size y"});
        cases.push_back({"shapes", "quad " + badNames[i], [=] { (void)shapes::quad(b, 1); }, "quad width"});
        cases.push_back({"shapes", "cylinder radius " + badNames[i], [=] { (void)shapes::cylinder(b, 1); },
                         "cylinder radius"});
        cases.push_back(
            {"shapes", "cone height " + badNames[i], [=] { (void)shapes::cone(1, b); }, "cone height"});
        cases.push_back(
            {"shapes", "sphere radius " + badNames[i], [=] { (void)shapes::sphere(b); }, "sphere radius"});
        cases.push_back(
            {"shapes", "heightfield size " + badNames[i],
             [=] { (void)shapes::heightfield(0, 0, b, 1, 2, 2, [](float, float) { return 0.0f; }); },
             "heightfield size x"});
    }
    for (int n : {0, 2, -1, 1 << 20, std::numeric_limits<int>::max()}) {
        cases.push_back({"shapes", "cylinder segments " + std::to_string(n),
                         [=] { (void)shapes::cylinder(1, 1, n); }, "segments"});
        cases.push_back({"shapes", "sphere segments " + std::to_string(n),
                         [=] { (void)shapes::sphere(1, n, 8); }, "segments"});
        if (n != 2)
            cases.push_back(
                {"shapes", "heightfield cells " + std::to_string(n),
                 [=] { (void)shapes::heightfield(0, 0, 1, 1, n, n, [](float, float) { return 0.0f; }); },
                 "cells along x"});
    }
    cases.push_back({"shapes", "heightfield NaN height",
                     [] { (void)shapes::heightfield(0, 0, 1, 1, 2, 2, [](float, float) { return kNaN; }); },
                     "not finite"});
    cases.push_back({"shapes", "heightfield null function",
                     [] { (void)shapes::heightfield(0, 0, 1, 1, 2, 2, nullptr); }, "height function"});
    cases.push_back(
        {"shapes", "heightfield NaN origin",
         [] { (void)shapes::heightfield(kNaN, 0, 1, 1, 2, 2, [](float, float) { return 0.0f; }); },
         "origin"});

    // OBJ export
    cases.push_back({"ObjWriter", "unwritable path",
                     [=] { (void)writeObj(*scene, "/nonexistent/dir/x.obj"); }, "cannot write OBJ"});
    cases.push_back({"ObjWriter", "empty path", [=] { (void)writeObj(*scene, ""); }, "cannot write OBJ"});

    // Content that is only checked when drawn: the frame throws, names the culprit, and the
    // next frame with the content fixed works (the viewer's state is intact).
    auto drawCase = [&](std::string label, std::function<void(Geometry&, Material&, StateSet&)> breakIt,
                        std::string expect) {
        cases.push_back({"draw-time content", label,
                         [&, breakIt] {
                             auto geo = shapes::quad(1, 1);
                             geo->name = "victim";
                             auto mat = Material::create();
                             geo->getOrCreateStateSet().material.set(mat);
                             breakIt(*geo, *mat, geo->getOrCreateStateSet());
                             scene->addChild(geo);
                             struct Remove {
                                 Group& s;
                                 Node* n;
                                 ~Remove() { s.removeChild(n); }
                             } remove{*scene, geo.get()};
                             v->frame();
                         },
                         expect,
                         [&] {
                             v->frame();
                             return glErrors(*v).empty() && scene->numChildren() == 1;
                         }});
    };
    for (int i = 0; i < 3; ++i) {
        const float b = badFloats[i];
        drawCase(
            "material diffuse " + badNames[i], [=](Geometry&, Material& m, StateSet&) { m.diffuse.g = b; },
            "Material colours");
        drawCase(
            "material shininess " + badNames[i], [=](Geometry&, Material& m, StateSet&) { m.shininess = b; },
            "shininess");
        drawCase(
            "material alphaCutoff " + badNames[i],
            [=](Geometry&, Material& m, StateSet&) { m.alphaCutoff = b; }, "alphaCutoff");
    }
    drawCase(
        "material ambient negative", [](Geometry&, Material& m, StateSet&) { m.ambient = glm::vec3(-1); },
        "Material colours");
    drawCase(
        "geometry index out of range",
        [](Geometry& geo, Material&, StateSet&) { geo.indices.push_back(1000); }, "'victim' index");
    drawCase(
        "geometry normals short", [](Geometry& geo, Material&, StateSet&) { geo.normals.pop_back(); },
        "normals");
    drawCase(
        "geometry colours too many",
        [](Geometry& geo, Material&, StateSet&) { geo.colors.assign(9, glm::vec4(1)); }, "colors");
    drawCase(
        "wrong PrimitiveMode", [](Geometry& geo, Material&, StateSet&) { geo.mode = PrimitiveMode(99); },
        "PrimitiveMode");
    drawCase(
        "wrong BlendMode", [](Geometry&, Material&, StateSet& s) { s.blend.set(BlendMode(99)); },
        "BlendMode");
    drawCase(
        "wrong CullFace", [](Geometry&, Material&, StateSet& s) { s.cullFace.set(CullFace(77)); },
        "CullFace");
    drawCase(
        "wrong CompareFunc",
        [](Geometry&, Material&, StateSet& s) {
            s.depth.set(DepthState{true, true, CompareFunc(42)});
        },
        "CompareFunc");
    drawCase(
        "texture without image",
        [](Geometry&, Material& m, StateSet&) { m.baseColorTexture = Texture::create(nullptr); }, "no image");
    drawCase(
        "texture filter out of range",
        [](Geometry&, Material& m, StateSet&) {
            m.baseColorTexture = Texture::create(Image::create(2, 2, 4));
            m.baseColorTexture->minFilter = Filter(17);
        },
        "Filter or Wrap");
    drawCase(
        "texture wrap out of range",
        [](Geometry&, Material& m, StateSet&) {
            m.alphaTexture = Texture::create(Image::create(2, 2, 1), false);
            m.alphaTexture->wrapT = Wrap(200);
        },
        "Filter or Wrap");
    drawCase(
        "texture image with 7 channels",
        [](Geometry&, Material& m, StateSet&) {
            auto img = Image::create(2, 2, 4);
            img->channels = 7;
            m.baseColorTexture = Texture::create(img);
        },
        "channels");
    drawCase(
        "texture image too small",
        [](Geometry&, Material& m, StateSet&) {
            auto img = Image::create(4, 4, 4);
            img->pixels.resize(10);
            m.baseColorTexture = Texture::create(img);
        },
        "smaller than");
    drawCase(
        "foreign shader without #version",
        [](Geometry&, Material&, StateSet& s) {
            s.program.set(ShaderProgram::create("nover", "void main(){}", "void main(){}"));
        },
        "failed to");
    drawCase(
        "foreign shader empty",
        [](Geometry&, Material&, StateSet& s) { s.program.set(ShaderProgram::create("empty", "", "")); },
        "empty");
    cases.push_back({"RendererOptions", "wrong colorTarget",
                     [&] {
                         v->renderer().options().colorTarget = RendererOptions::ColorTarget(9);
                         struct Restore {
                             Viewer& viewer;
                             ~Restore() {
                                 viewer.renderer().options().colorTarget =
                                     RendererOptions::ColorTarget::Srgb8;
                             }
                         } restore{*v};
                         v->frame();
                     },
                     "colorTarget",
                     [&] {
                         v->frame();
                         return true;
                     }});
    cases.push_back({"RendererOptions", "wrong lighting",
                     [&] {
                         v->renderer().options().lighting = RendererOptions::Lighting(5);
                         struct Restore {
                             Viewer& viewer;
                             ~Restore() {
                                 viewer.renderer().options().lighting = RendererOptions::Lighting::PerPixel;
                             }
                         } restore{*v};
                         v->frame();
                     },
                     "lighting",
                     [&] {
                         v->frame();
                         return true;
                     }});
    cases.push_back(
        {"Viewer", "createHeadless 0x0", [] { (void)Viewer::createHeadless(0, 0); }, "must be positive"});
    cases.push_back(
        {"Viewer", "createHeadless -3x5", [] { (void)Viewer::createHeadless(-3, 5); }, "must be positive"});

    std::map<std::string, int> perComponent;
    for (const BadInput& c : cases) {
        SCOPED_TRACE(c.component + ": " + c.label);
        try {
            c.call();
            ADD_FAILURE() << "accepted without an error";
        } catch (const std::exception& e) {
            const std::string msg = e.what();
            EXPECT_NE(msg.find(c.expect), std::string::npos) << "message: " << msg;
            EXPECT_EQ(msg.rfind("sgfx", 0), 0u) << "message should say it comes from sgfx: " << msg;
        }
        if (c.unchanged) {
            EXPECT_TRUE(c.unchanged()) << "previous state changed";
        }
        ++perComponent[c.component];
    }
    std::filesystem::remove(garbage);
    std::filesystem::remove(truncated);
    int total = 0;
    for (const auto& [component, n] : perComponent) {
        std::printf("bad inputs: %-20s %3d\n", component.c_str(), n);
        RecordProperty("bad_inputs_" + component, n);
        total += n;
    }
    std::printf("bad inputs: %-20s %3d\n", "total", total);
    EXPECT_GE(total, 150);
}

// ------------------------------------------------------------------------ thread contract

TEST(ThreadContractDeathTest, GlWorkFromAnotherThreadAbortsWithAMessage) {
    GTEST_FLAG_SET(death_test_style, "threadsafe");
    EXPECT_DEATH(
        {
            auto v = Viewer::createHeadless(8, 8);
            std::thread other([&] { v->frame(); });
            other.join();
        },
        "from a thread that does not own it");
}

// ------------------------------------------------------------------------ automatic instancing

// Windows of differently coloured buildings: the windows' StateSet replaces everything the
// buildings set, so every path resolves to one state; the cull shares one pointer for it and the
// renderer draws them as one batch. A parent that overrides the material, or sets another
// attribute, keeps its own state.
TEST(StateSorting, PathsThatResolveToTheSameStateShareOneStateAndBatch) {
    auto cam = Camera::create();
    cam->setViewport(0, 0, 96, 64);
    cam->setPerspective(60.0f, 0.1f, 200.0f);
    cam->setLookAt({0, -30, 6}, {0, 0, 0});
    auto window = shapes::box({1.0f, 0.2f, 1.4f});
    auto windowState = StateSet::create();
    auto glassy = Material::create();
    glassy->diffuse = glm::vec4(0.1f, 0.2f, 0.5f, 1.0f);
    windowState->material.set(glassy);
    enum Kind { Plain, OverridesMaterial, SetsCullFace };
    std::vector<Kind> kinds;
    for (int b = 0; b < 8; ++b) {
        const Kind kind = b == 5 ? OverridesMaterial : b == 6 ? SetsCullFace : Plain;
        auto building = Transform::create(glm::translate(glm::mat4(1.0f), {float(b) * 3.0f - 10.0f, 0, 0}));
        auto colour = Material::create();
        colour->diffuse = glm::vec4(0.3f + 0.08f * float(b), 0.3f, 0.2f, 1.0f);
        building->getOrCreateStateSet().material.set(colour, kind == OverridesMaterial ? Override : Inherit);
        if (kind == SetsCullFace) building->getOrCreateStateSet().cullFace.set(CullFace::None);
        auto windows = Group::create();
        windows->setStateSet(windowState);
        for (int w = 0; w < 3; ++w) {
            auto at = Transform::create(glm::translate(glm::mat4(1.0f), {0, 0, float(w) * 2.0f}));
            at->addChild(window);
            windows->addChild(at);
        }
        building->addChild(windows);
        cam->addChild(building);
        kinds.push_back(kind);
    }
    RenderQueue q;
    CullVisitor cv(*cam, q);
    cv.run(*cam);
    ASSERT_EQ(q.opaque.size(), 24u);
    std::map<Kind, std::set<const ResolvedState*>> statesOf;
    for (const RenderItem& it : q.opaque) {
        const int b = int(std::lround((it.model[3].x + 10.0f) / 3.0f));
        ASSERT_TRUE(b >= 0 && b < 8);
        statesOf[kinds[std::size_t(b)]].insert(it.state);
        const bool overridden = kinds[std::size_t(b)] == OverridesMaterial;
        EXPECT_EQ(it.state->material.value->get() == glassy.get(), !overridden) << "building " << b;
    }
    EXPECT_EQ(statesOf[Plain].size(), 1u) << "six buildings, one resolved window state";
    EXPECT_EQ(statesOf[OverridesMaterial].size(), 1u);
    EXPECT_EQ(statesOf[SetsCullFace].size(), 1u);
    EXPECT_NE(*statesOf[Plain].begin(), *statesOf[OverridesMaterial].begin());
    EXPECT_NE(*statesOf[Plain].begin(), *statesOf[SetsCullFace].begin());
    EXPECT_EQ((*statesOf[SetsCullFace].begin())->cullFace.value, CullFace::None);

    // Drawn: the 18 windows of the six plain buildings, from one distance octave, are one batch
    // (six states interleaved by depth drew them in many runs).
    auto v = Viewer::createHeadless(96, 64);
    auto root = Group::create();
    for (std::size_t b = 0; b < kinds.size(); ++b)
        if (kinds[b] == Plain) root->addChild(cam->children()[b]);
    auto sun = Light::create(LightType::Directional);
    sun->direction = glm::normalize(glm::vec3(0.2f, 1.0f, -0.6f));
    root->addChild(sun);
    v->setSceneData(root);
    v->camera()->setPerspective(60.0f, 0.1f, 200.0f);
    v->camera()->setLookAt({0, -45, 4}, {0, 0, 2}); // every window 32..64 m away
    v->frame();
    EXPECT_EQ(v->stats().triangles, 18u * window->triangleCount());
    EXPECT_EQ(v->stats().drawCalls, 1u);
    EXPECT_EQ(v->stats().instanceBatches, 1u);
}

TEST(AutoInstancing, BatchesDrawTheSameImageInEveryPass) {
    // 60 copies of two meshes under Transforms that scale unevenly and mirror, under fog and AO
    // (a snippet, a depth pre-pass and a G-buffer pass): batched and one by one give the same
    // pixels, with far fewer draw calls.
    auto root = Group::create();
    auto fog = FogNode::create(FogParameters::ground());
    auto ao = AmbientOcclusionNode::create();
    fog->addChild(ao);
    root->addChild(fog);
    auto sun = Light::create(LightType::Directional);
    sun->direction = glm::normalize(glm::vec3(-0.3f, -0.5f, -1.0f));
    root->addChild(sun);
    auto meshes = {shapes::box({1, 1, 1}), shapes::sphere(0.6f, 12, 8)};
    auto mat = Material::create();
    mat->specular = glm::vec3(0.5f);
    int k = 0;
    for (const auto& m : meshes) {
        m->getOrCreateStateSet().material.set(mat);
        for (int i = 0; i < 30; ++i, ++k) {
            const glm::vec3 at(float(k % 10) * 2.2f - 10.0f, float(k / 10) * 2.2f - 6.0f, 0.0f);
            glm::mat4 t = glm::translate(glm::mat4(1.0f), at);
            t = glm::rotate(t, 0.3f * float(k), glm::vec3(0.2f, 0.5f, 1.0f));
            t = glm::scale(t, glm::vec3(1.0f + 0.05f * float(k % 7), k % 3 == 0 ? -1.0f : 0.8f, 1.2f));
            auto tr = Transform::create(t);
            tr->addChild(m);
            ao->addChild(tr);
        }
    }
    auto ground = shapes::quad(60.0f, 60.0f);
    ground->getOrCreateStateSet().material.set(Material::create());
    ao->addChild(Transform::create(glm::translate(glm::mat4(1.0f), {0, 0, -1.5f})));
    std::static_pointer_cast<Group>(ao->children().back())->addChild(ground);
    auto v = Viewer::createHeadless(160, 120);
    v->setSceneData(root);
    v->camera()->setPerspective(50, 0.5f, 200);
    v->camera()->setLookAt({0, -26, 18}, {0, -1, 0}, {0, 0, 1});
    Image images[2];
    std::size_t draws[2], batches[2];
    for (int on = 0; on < 2; ++on) {
        v->renderer().options().autoInstancing = on == 1;
        v->frame();
        images[on] = v->capture();
        draws[on] = v->stats().drawCalls;
        batches[on] = v->stats().instanceBatches;
    }
    EXPECT_EQ(batches[0], 0u);
    EXPECT_GE(batches[1], 2u);
    EXPECT_LT(draws[1] + 50, draws[0]) << draws[1] << " vs " << draws[0];
    ASSERT_EQ(images[0].pixels.size(), images[1].pixels.size());
    int worst = 0;
    for (std::size_t i = 0; i < images[0].pixels.size(); ++i)
        worst = std::max(worst, std::abs(int(images[0].pixels[i]) - int(images[1].pixels[i])));
    EXPECT_LE(worst, 2)
        << "batched drawing changed the image"; // the cofactor normal matrix rounds differently
    EXPECT_TRUE(glErrors(*v).empty());
}

// ------------------------------------------------------------------------ levels of detail

TEST(ProvingGroundLod, SkirtsCoverEveryStepBetweenTerrainLevels) {
    // Along every tile edge, each level's skirt must reach below the edge of every other level
    // (neighbours sample the shared edge alike): then, from either side of a boundary between
    // two levels, the nearer tile's skirt fills the step. Read from the built geometry.
    polygon::SceneOptions so;
    so.scale = 0.25f;
    const polygon::PolygonScene scene = polygon::buildPolygonScene(so);
    int lods = 0;
    double worst = -1e9; // max over points of (skirt bottom of level i) - (edge of level j)
    for (const auto& child : scene.terrain->children()) {
        auto lod = std::dynamic_pointer_cast<LOD>(child);
        if (!lod) continue;
        ++lods;
        ASSERT_EQ(lod->children().size(), 3u);
        struct Level {
            const Geometry* g;
            std::size_t m; // vertices per edge
        };
        std::vector<Level> levels;
        for (const auto& c : lod->children()) {
            auto g = std::dynamic_pointer_cast<Geometry>(c);
            ASSERT_TRUE(g);
            // (n+1)^2 grid vertices, then per edge n+1 (top, bottom) pairs.
            const double total = double(g->positions.size());
            const auto m = std::size_t(std::lround((-8.0 + std::sqrt(64.0 + 4.0 * total)) / 2.0));
            ASSERT_EQ(m * m + 8 * m, g->positions.size());
            levels.push_back({g.get(), m});
        }
        auto edgeZ = [](const Level& l, int e, double t, int which) { // which 0: top, 1: bottom
            const double u = t * double(l.m - 1);
            const std::size_t k = std::min(std::size_t(u), l.m - 2);
            const double f = u - double(k);
            const std::size_t base = l.m * l.m + std::size_t(e) * 2 * l.m;
            return (1 - f) * l.g->positions[base + 2 * k + which].z +
                   f * l.g->positions[base + 2 * (k + 1) + which].z;
        };
        for (const Level& a : levels)
            for (const Level& b : levels)
                for (int e = 0; e < 4; ++e)
                    for (std::size_t k = 0; k < b.m; ++k) {
                        const double t = double(k) / double(b.m - 1);
                        worst = std::max(worst, edgeZ(a, e, t, 1) - edgeZ(b, e, t, 0));
                    }
    }
    EXPECT_GT(lods, 0);
    EXPECT_LT(worst, 0.0) << "a skirt ends " << worst << " m above another level's edge";
}

TEST(ProvingGroundLod, CoarseTerrainLevelsNeverRiseOverTheTerrain) {
    // Each coarser level is lowered by the largest rise of its triangles over the terrain,
    // measured per tile, so the roads laid on the terrain never sink into a distant tile. Read
    // from the built geometry: centroids and edge midpoints of every grid triangle, against the
    // terrain's height there. Flat tiles measure far less than the worst-case bound.
    polygon::SceneOptions so;
    so.scale = 0.25f;
    const polygon::PolygonScene scene = polygon::buildPolygonScene(so);
    const polygon::Terrain terrain(so.seed);
    double worstRise = -1e9, smallestDrop = 1e9, largestDrop = 0.0;
    int levels = 0;
    for (const auto& child : scene.terrain->children()) {
        auto lod = std::dynamic_pointer_cast<LOD>(child);
        if (!lod) continue;
        for (std::size_t level = 1; level < lod->children().size(); ++level) {
            auto g = std::dynamic_pointer_cast<Geometry>(lod->children()[level]);
            ASSERT_TRUE(g);
            ++levels;
            double drop = 0.0;
            for (std::size_t t = 0; t + 2 < g->indices.size(); t += 3) {
                const glm::vec3 a = g->positions[g->indices[t]], b = g->positions[g->indices[t + 1]],
                                c = g->positions[g->indices[t + 2]];
                if (std::abs(glm::cross(b - a, c - a).z) < 1e-6f) continue; // a skirt strip
                drop = std::max(drop, double(terrain.height(a.x, a.y) - a.z));
                for (const glm::vec3& p :
                     {(a + b + c) / 3.0f, (a + b) * 0.5f, (b + c) * 0.5f, (a + c) * 0.5f})
                    worstRise = std::max(worstRise, double(p.z - terrain.height(p.x, p.y)));
            }
            smallestDrop = std::min(smallestDrop, drop);
            largestDrop = std::max(largestDrop, drop);
        }
    }
    EXPECT_GT(levels, 0);
    EXPECT_LE(worstRise, 1e-4) << "a coarse terrain level rises " << worstRise << " m over the terrain";
    EXPECT_LT(smallestDrop, 0.5 * largestDrop) << "drops are measured per tile, not one bound for all";
}

TEST(ProvingGroundLod, TerrainLevelsLeaveNoCracksAndCutTriangles) {
    // A magenta backdrop lies under the ground, the size of the ground: a crack between tiles of
    // different levels, looked through, shows it; past the ground's edge the eye sees the sky.
    polygon::SceneOptions so;
    so.scale = 0.25f;
    const polygon::PolygonScene scene = polygon::buildPolygonScene(so);
    ASSERT_GT(scene.info.terrainLods, 0);
    auto makeRoot = [](const polygon::PolygonScene& sc) {
        auto root = Group::create();
        for (const auto& c : sc.root->children())
            if (c != sc.glass) root->addChild(c);
        auto backdrop =
            shapes::quad(sc.terrain->bound().radius * 1.4142f, sc.terrain->bound().radius * 1.4142f);
        auto mat = Material::create();
        mat->ambient = mat->specular = glm::vec3(0.0f);
        mat->diffuse = glm::vec4(0, 0, 0, 1);
        mat->emissive = glm::vec3(1, 0, 1);
        backdrop->getOrCreateStateSet().material.set(mat);
        backdrop->getOrCreateStateSet().cullFace.set(CullFace::None);
        auto below = Transform::create(glm::translate(glm::mat4(1.0f), {0, 0, -30.0f}));
        below->addChild(backdrop);
        root->addChild(below);
        return root;
    };
    auto v = Viewer::createHeadless(256, 144);
    v->setSceneData(makeRoot(scene));
    auto& cam = *v->camera();
    cam.setPerspective(polygon::kPathFovyDegrees, polygon::kPathNear, polygon::kPathFar);
    std::vector<glm::vec3> eyes;
    std::size_t lodTriangles = 0;
    for (int i = 0; i < 6; ++i) {
        // Low over the ground, looking across it: level boundaries are seen edge-on, where a
        // step between levels opens a slit unless a skirt fills it.
        const float a = float(i) * 1.05f;
        eyes.emplace_back(330.0f * std::cos(a), 330.0f * std::sin(a), 14.0f + 6.0f * float(i));
        cam.setLookAt(eyes.back(), glm::vec3(-0.2f * eyes.back().x, -0.2f * eyes.back().y, -20.0f),
                      {0, 0, 1});
        v->frame();
        lodTriangles += v->stats().triangles;
        const Image img = v->capture();
        if (std::getenv("SGFX_DUMP")) writePng("/tmp/lod" + std::to_string(i) + ".png", img);
        int holes = 0;
        for (std::size_t p = 0; p < img.pixels.size(); p += 4)
            holes += img.pixels[p] == 255 && img.pixels[p + 1] == 0 && img.pixels[p + 2] == 255;
        EXPECT_EQ(holes, 0) << "view " << i << ": the backdrop shows through the ground";
    }
    // The same views without levels of detail draw many more triangles.
    so.lod = false;
    const polygon::PolygonScene full = polygon::buildPolygonScene(so);
    v->setSceneData(makeRoot(full));
    std::size_t fullTriangles = 0;
    for (const glm::vec3& eye : eyes) {
        cam.setLookAt(eye, glm::vec3(-0.2f * eye.x, -0.2f * eye.y, -20.0f), {0, 0, 1});
        v->frame();
        fullTriangles += v->stats().triangles;
    }
    EXPECT_LT(double(lodTriangles), 0.8 * double(fullTriangles)) << lodTriangles << " vs " << fullTriangles;
}

// ------------------------------------------------------------------------ culling is conservative

// The proving ground at a tenth of its triangles in a 128 x 72 headless viewer with the camera
// path's lens; at(i, n) puts the camera at path time i / n.
struct SmallProvingGround {
    polygon::SceneOptions options{.scale = 0.1f};
    polygon::PolygonScene scene = polygon::buildPolygonScene(options);
    std::unique_ptr<Viewer> viewer = Viewer::createHeadless(128, 72);
    SmallProvingGround() {
        viewer->setSceneData(scene.root);
        viewer->camera()->setPerspective(polygon::kPathFovyDegrees, polygon::kPathNear, polygon::kPathFar);
    }
    void at(int i, int n) {
        const polygon::CameraPose pose = polygon::cameraPose(float(i) / float(n), options.extent);
        viewer->camera()->setLookAt(pose.eye, pose.target, pose.up);
    }
};

// RendererOptions::submitTriangles only changes when the driver starts rasterising: submitting
// before every draw, every 500 triangles or once per frame gives the same pixels.
TEST(Submission, FlushingWhileDrawingDrawsTheSameImage) {
    SmallProvingGround ground;
    Viewer& v = *ground.viewer;
    v.renderer().options().submitsPerFrame = 0; // the intervals below exactly, uncapped
    for (int i = 0; i < 3; ++i) {
        ground.at(i, 3);
        v.renderer().options().submitTriangles = 0;
        v.frame();
        const Image once = v.capture();
        ASSERT_GT(v.stats().triangles, 1000u);
        for (std::uint64_t every : {std::uint64_t(1), std::uint64_t(500)}) {
            v.renderer().options().submitTriangles = every;
            v.frame();
            EXPECT_EQ(v.capture().pixels, once.pixels) << "view " << i << ", a submission every " << every;
        }
    }
}

// RendererOptions::submitsPerFrame caps the submissions a frame from the last frame's triangles,
// never submits more often than submitTriangles asks, and FrameStats::submissions counts them.
TEST(Submission, SubmitsPerFrameCapsTheCount) {
    SmallProvingGround ground;
    Viewer& v = *ground.viewer;
    ground.at(1, 3);
    RendererOptions& o = v.renderer().options();
    o.submitTriangles = 100;
    o.submitsPerFrame = 0;
    v.frame();
    const std::size_t triangles = v.stats().triangles;
    ASSERT_GT(triangles, 2000u);
    // Uncapped: one before the first item past every 100 triangles (items end past the mark).
    EXPECT_GT(v.stats().submissions, 3u);
    EXPECT_LE(v.stats().submissions, triangles / 100);
    o.submitsPerFrame = 3;
    v.frame(); // the interval comes from the frame before: triangles / 3
    EXPECT_GE(v.stats().submissions, 1u);
    EXPECT_LE(v.stats().submissions, 3u);
    o.submitTriangles = triangles * 2; // longer than the cap's interval: it wins
    v.frame();
    EXPECT_EQ(v.stats().submissions, 0u);
    o.submitTriangles = 0; // none at all, whatever the cap
    v.frame();
    EXPECT_EQ(v.stats().submissions, 0u);
}

TEST(Culling, NeverDropsAVisibleObjectOnTheProvingGround) {
    SmallProvingGround ground;
    auto& v = ground.viewer;
    auto& cam = *v->camera();
    int culledSomewhere = 0;
    for (int i = 0; i < 8; ++i) {
        ground.at(i, 8);
        cam.cullingEnabled = true;
        v->frame();
        const Image culled = v->capture();
        const std::size_t culledDraws = v->stats().drawCalls;
        culledSomewhere += v->stats().culledNodes > 0;
        cam.cullingEnabled = false;
        v->frame();
        const Image all = v->capture();
        EXPECT_LT(culledDraws, v->stats().drawCalls) << "view " << i << " culled nothing";
        EXPECT_EQ(culled.pixels, all.pixels) << "view " << i << ": culling changed the image";
    }
    EXPECT_EQ(culledSomewhere, 8);
}

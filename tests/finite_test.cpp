// Every pixel finite: float-target sweeps over the places where a shader could produce NaN or
// infinity (a zero vector normalised, a degenerate derivative plane, a NaN spread by a blur).
// The sky's own sweep (zenith, nadir, horizon) is in sky_test.cpp.
#include "TestUtil.h"

#include <sgfx/Geometry.h>
#include <sgfx/Group.h>
#include <sgfx/ShaderComposer.h>
#include <sgfx/Shapes.h>
#include <sgfx/nodes/ao/AmbientOcclusionNode.h>
#include <sgfx/nodes/particles/ParticleSystemNode.h>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <random>

using namespace sgfx;
using namespace sgfx::test;

namespace {

constexpr int kSize = 96;

std::unique_ptr<Viewer> floatViewer(glm::vec3 eye, glm::vec3 target) {
    auto v = Viewer::createHeadless(kSize, kSize);
    v->renderer().options().colorTarget = RendererOptions::ColorTarget::Rgba32F;
    auto& cam = *v->camera();
    cam.setPerspective(60.0f, 0.1f, 200.0f);
    const glm::vec3 dir = glm::normalize(target - eye);
    cam.setLookAt(eye, target, std::abs(dir.z) > 0.99f ? glm::vec3(0, 1, 0) : glm::vec3(0, 0, 1));
    cam.computeNearFar = false;
    cam.clearColor = {0.2f, 0.3f, 0.4f, 1.0f};
    return v;
}

// Pixels whose linear value is NaN or infinite in any channel.
int nonFinitePixels(Viewer& v) {
    const FloatImage img = v.renderer().readPixelsLinear();
    int bad = 0;
    for (std::size_t i = 0; i < img.rgba.size(); i += 4)
        bad += !(std::isfinite(img.rgba[i]) && std::isfinite(img.rgba[i + 1]) &&
                 std::isfinite(img.rgba[i + 2]) && std::isfinite(img.rgba[i + 3]));
    return bad;
}

// Triangles that are degenerate (a repeated corner, three collinear corners) or slivers (width
// 1e-2 .. 1e-9 m across a 2 m side), standing at random angles over the floor.
std::shared_ptr<Geometry> sliversAndDegenerates(bool withNormals) {
    auto g = Geometry::create();
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    auto add = [&](glm::vec3 a, glm::vec3 b, glm::vec3 c) {
        for (const glm::vec3& p : {a, b, c}) {
            g->indices.push_back(std::uint32_t(g->positions.size()));
            g->positions.push_back(p);
            if (withNormals) g->normals.push_back(glm::normalize(glm::vec3(u(rng), u(rng), 1.5f)));
        }
    };
    for (int i = 0; i < 40; ++i) {
        const glm::vec3 base(u(rng) * 3.0f, u(rng) * 3.0f, 0.3f + 0.5f * (u(rng) + 1.0f));
        const glm::vec3 along = glm::normalize(glm::vec3(u(rng), u(rng), u(rng)));
        glm::vec3 across = glm::cross(along, glm::vec3(0.3f, 0.5f, 0.8f));
        across = glm::normalize(across);
        const float width = std::pow(10.0f, -2.0f - 7.0f * float(i % 8) / 7.0f);
        add(base, base + 2.0f * along, base + along + width * across); // sliver
        if (i % 4 == 0) add(base, base, base + along);                 // a repeated corner
        if (i % 4 == 1) add(base, base + along, base + 2.0f * along);  // collinear
    }
    auto m = Material::create();
    m->ambient = glm::vec3(1.0f);
    m->diffuse = glm::vec4(0.5f, 0.5f, 0.5f, 1.0f);
    g->getOrCreateStateSet().material.set(m);
    g->getOrCreateStateSet().cullFace.set(CullFace::None);
    return g;
}

} // namespace

TEST(Finite, SliversAndDegenerateTrianglesUnderAoGiveFinitePixels) {
    // Flat normals from derivatives (no normals: the G-buffer's and the material's own flat path)
    // and given normals; the AO map raw, blurred and applied; seen from above, grazing and edge-on.
    const glm::vec3 eyes[] = {{0, -6, 5}, {6, 0.5f, 0.6f}, {0.01f, 0.0f, 9.0f}, {-4, -4, 0.5f}};
    for (const bool withNormals : {false, true})
        for (const AoDebugView view : {AoDebugView::Off, AoDebugView::Raw, AoDebugView::Blurred})
            for (const glm::vec3& eye : eyes) {
                auto root = Group::create();
                root->addChild(Light::create(LightType::Ambient));
                auto sun = Light::create(LightType::Directional);
                sun->direction = {-0.3f, -0.2f, -0.9f};
                root->addChild(sun);
                AmbientOcclusionParameters p;
                p.debugView = view;
                auto ao = AmbientOcclusionNode::create(p);
                auto floor = shapes::quad(20.0f, 20.0f);
                floor->getOrCreateStateSet().material.set(Material::create());
                ao->addChild(floor);
                ao->addChild(sliversAndDegenerates(withNormals));
                root->addChild(ao);
                auto v = floatViewer(eye, {0, 0, 0.5f});
                v->setSceneData(root);
                v->frame();
                EXPECT_EQ(nonFinitePixels(*v), 0)
                    << (withNormals ? "normals" : "flat") << ", AO view " << int(view) << ", eye " << eye.x
                    << "," << eye.y << "," << eye.z;
            }
}

TEST(Finite, AParticleAtTheEyeGivesFinitePixels) {
    // One system's emitter (W = H = 0, still) sits exactly at the eye; another's is in view, so
    // the frame draws real particles beside the one with no direction to the eye.
    for (const ParticlePath path : {ParticlePath::GeometryShader, ParticlePath::Instanced,
                                    ParticlePath::Pulled, ParticlePath::PointSprite})
        for (const ParticleShape shape : {ParticleShape::Sprite, ParticleShape::Hexagon}) {
            if (path == ParticlePath::PointSprite && shape != ParticleShape::Sprite) continue;
            auto root = Group::create();
            root->addChild(Light::create(LightType::Ambient));
            const glm::vec3 eye(1.0f, -2.0f, 1.5f);
            for (const glm::vec3& at : {eye, glm::vec3(0.0f, 0.0f, 1.0f)}) {
                ParticleSettings s;
                s.capacity = 4;
                s.emitter.size = {0.0f, 0.0f};
                s.emitter.acceleration = glm::vec3(0.0f);
                s.emitter.lifetime = 1000.0f;
                s.start = particles::StartMode::Burst;
                s.shape = shape;
                s.sizeStart = s.sizeEnd = 0.5f;
                s.path = path;
                auto t = Transform::create(glm::translate(glm::mat4(1.0f), at));
                t->addChild(ParticleSystemNode::create(s));
                root->addChild(t);
            }
            auto v = floatViewer(eye, {0, 0, 1});
            v->setSceneData(root);
            v->frame(0.0);
            v->frame(0.016);
            EXPECT_EQ(nonFinitePixels(*v), 0) << "path " << int(path) << " shape " << int(shape);
            // The particle in view is drawn: the middle of the image is not the clear colour.
            const FloatImage img = v->renderer().readPixelsLinear();
            const float* mid = &img.rgba[(std::size_t(kSize / 2) * kSize + kSize / 2) * 4];
            EXPECT_GT(std::abs(mid[0] - 0.2f) + std::abs(mid[2] - 0.4f), 0.05f) << "path " << int(path);
        }
}

TEST(Finite, FlatNormalsWhoseDerivativesUnderflowGiveFinitePixels) {
    // A quad without normals seen through an orthographic view 1e-19 m across: the screen-space
    // derivatives of its position are about 1e-21 m a pixel and their cross product underflows
    // to zero (denormals flush on llvmpipe), which is what a sliver's parallel derivatives give:
    // normalising it is NaN. Drawn with the built-in material (its flat path and its AO G-buffer
    // variant) and with an application's program (AO's flat G-buffer shader), under AO.
    auto render = [&](bool foreign, float half) {
        auto g = Geometry::create();
        g->positions = {{-half, -half, 0}, {half, -half, 0}, {half, half, 0}, {-half, half, 0}};
        g->indices = {0, 1, 2, 0, 2, 3};
        if (foreign)
            g->getOrCreateStateSet().program.set(
                ShaderProgram::create("app_flat", kForeignVert, kForeignAoFrag));
        else
            g->getOrCreateStateSet().material.set(Material::create());
        g->getOrCreateStateSet().cullFace.set(CullFace::None);
        auto root = Group::create();
        root->addChild(Light::create(LightType::Ambient));
        auto sun = Light::create(LightType::Directional); // the flat normal enters the lighting
        sun->direction = {-0.3f, -0.2f, -0.9f};
        root->addChild(sun);
        auto ao = AmbientOcclusionNode::create();
        ao->addChild(g);
        root->addChild(ao);
        auto v = floatViewer({0.0f, -0.5f, 10.0f}, {0, 0, 0});
        v->camera()->projectionMatrix = glm::ortho(-half, half, -half, half, 0.1f, 100.0f);
        v->setSceneData(root);
        v->frame();
        EXPECT_EQ(nonFinitePixels(*v), 0)
            << (foreign ? "foreign program" : "built-in material") << ", view " << half << " m";
        const FloatImage img = v->renderer().readPixelsLinear();
        const float* c = &img.rgba[(std::size_t(kSize / 2) * kSize + kSize / 2) * 4];
        return glm::vec3(c[0], c[1], c[2]);
    };
    // The microscopic quad looks like the same quad 2 mm across (whose flat normal is exact):
    // the stand-in normal faces the eye, 3° off the quad's. A NaN normal shows as black rather
    // than as NaN on llvmpipe (its max() drops the NaN of N·L), so the colours are compared.
    for (const bool foreign : {false, true}) {
        const glm::vec3 tiny = render(foreign, 1e-19f), normal = render(foreign, 1e-3f);
        for (int ch = 0; ch < 3; ++ch)
            EXPECT_NEAR(tiny[ch], normal[ch], 0.03f * normal[ch] + 1e-3f)
                << (foreign ? "foreign program" : "built-in material") << " channel " << ch;
    }
}

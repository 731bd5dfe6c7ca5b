// FogNode rendered on OSMesa (≤ 128×128) against the closed form: every pixel of a large plane,
// sky pixels, fog through glass composited physically, foreign shaders, nesting, bad input.
#include "TestUtil.h"

#include <sgfx/FrameSetup.h>
#include <sgfx/Geometry.h>
#include <sgfx/Group.h>
#include <sgfx/PassCommands.h>
#include <sgfx/RenderQueue.h>
#include <sgfx/ShaderComposer.h>
#include <sgfx/Shapes.h>
#include <sgfx/nodes/fog/FogMath.h>
#include <sgfx/nodes/fog/FogNode.h>
#include <sgfx/nodes/particles/ParticleSystemNode.h>
#include <sgfx/nodes/transparency/TransparencyBin.h>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

using namespace sgfx;
using namespace sgfx::test;

namespace {

constexpr int kSize = 96;

// A quad placed by `m` with an emissive colour (exact: no lights in these scenes).
std::shared_ptr<Node> panel(float w, float h, const glm::mat4& m, std::shared_ptr<Material> mat) {
    auto t = Transform::create(m);
    auto q = shapes::quad(w, h);
    q->getOrCreateStateSet().material.set(std::move(mat));
    t->addChild(q);
    return t;
}

// Vertical panel at distance y facing the camera (−Y), centred at height z.
glm::mat4 facingCamera(float y, float z) {
    return glm::rotate(glm::translate(glm::mat4(1.0f), {0, y, z}), glm::radians(90.0f), glm::vec3(1, 0, 0));
}

std::unique_ptr<Viewer> perspectiveViewer(glm::vec3 eye, glm::vec3 at, float nearPlane = 0.5f,
                                          float farPlane = 2000.0f) {
    auto v = Viewer::createHeadless(kSize, kSize);
    auto& cam = *v->camera();
    cam.setPerspective(60.0f, nearPlane, farPlane);
    cam.setLookAt(eye, at, {0, 0, 1});
    cam.computeNearFar = false;
    cam.clearColor = {0.05f, 0.1f, 0.3f, 1.0f};
    return v;
}

// World ray through the centre of pixel (x, y) of the image (top row first).
struct Ray {
    glm::dvec3 origin, dir;
};
Ray rayThrough(const Camera& cam, double x, double y) {
    const glm::dmat4 inv = glm::inverse(glm::dmat4(cam.projectionMatrix) * glm::dmat4(cam.viewMatrix));
    const double nx = x / kSize * 2 - 1, ny = 1 - y / kSize * 2;
    glm::dvec4 a = inv * glm::dvec4(nx, ny, -1, 1), b = inv * glm::dvec4(nx, ny, 1, 1);
    a /= a.w;
    b /= b.w;
    const glm::dvec3 eye = glm::inverse(glm::dmat4(cam.viewMatrix))[3];
    return {eye, glm::normalize(glm::dvec3(b) - glm::dvec3(a))};
}

double kOf(const FogParameters& p, glm::dvec3 a, glm::dvec3 b) {
    const glm::dvec3 up = glm::normalize(glm::dvec3(p.up));
    const double F = fog::opticalDepth<double>(p.density, p.falloff, glm::dot(a, up) - p.referenceHeight,
                                               glm::dot(b, up) - p.referenceHeight, glm::length(b - a));
    return fog::amount<double>(
        F, p.response == FogResponse::Linear ? fog::Response::Linear : fog::Response::Exponential,
        p.maxOpacity);
}

glm::dvec3 mixd(glm::dvec3 a, glm::dvec3 b, double k) {
    return a * (1 - k) + b * k;
}

int channelError(const Image& img, int x, int y, glm::dvec3 linear) {
    const glm::ivec4 p = pixelAt(img, x, y);
    int e = 0;
    for (int c = 0; c < 3; ++c)
        e = std::max(e, std::abs(p[c] - srgbByte(linear[c])));
    return e;
}

FogParameters testFog(FogResponse r) {
    FogParameters p;
    p.density = 0.02f;
    p.falloff = 0.08f;
    p.color = {0.8f, 0.8f, 0.9f};
    p.response = r;
    p.sky = FogSky::Distance;
    p.skyDistance = 500.0f;
    return p;
}

const char* modeName(FogMode m) {
    return m == FogMode::Forward ? "Forward" : m == FogMode::ForwardSplit ? "ForwardSplit" : "PostProcess";
}

// How the fog reaches the pixels: a mode, and for Forward whether the opaque items may be fogged
// by the full-screen pass after them (deferred) or keep the fog in their materials.
struct Path {
    FogMode mode = FogMode::Forward;
    bool defer = true;
};
const Path kDeferred{FogMode::Forward, true}, kInMaterials{FogMode::Forward, false};
const Path kPaths[] = {kDeferred, kInMaterials, {FogMode::ForwardSplit}, {FogMode::PostProcess}};

std::string pathName(Path p) {
    return p.mode != FogMode::Forward ? modeName(p.mode) : p.defer ? "Forward/deferred" : "Forward/materials";
}

void PrintTo(Path p, std::ostream* os) {
    *os << pathName(p);
}

std::shared_ptr<FogNode> fogOn(const FogParameters& params, Path path) {
    auto node = FogNode::create(params, path.mode);
    node->setDeferOpaque(path.defer);
    return node;
}

// After a frame whose opaque items all lie below the node: the pass ran exactly on that path.
void expectDeferredAsAsked(const FogNode& node, Path path) {
    EXPECT_EQ(node.lastFrameDeferred(), path.mode == FogMode::Forward && path.defer) << pathName(path);
}

} // namespace

// A 400 m × 400 m ground plane seen from 8 m: every pixel that sees the plane equals
// mix(surface, fog, k(O, P)) and every sky pixel mix(clear, fog, k(O, O + D·skyDistance)).
class FogPlane : public ::testing::TestWithParam<std::tuple<Path, FogResponse>> {};

TEST_P(FogPlane, EveryPixelMatchesTheClosedForm) {
    const auto [path, response] = GetParam();
    auto v = perspectiveViewer({0, 0, 8}, {0, 60, 0});
    const FogParameters params = testFog(response);
    auto fogNode = fogOn(params, path);
    const glm::vec3 surface(0.2f, 0.5f, 0.1f);
    const double half = 200.0, cy = 190.0;
    fogNode->addChild(panel(float(2 * half), float(2 * half),
                            glm::translate(glm::mat4(1.0f), {0, float(cy), 0}), flatMaterial(surface)));
    auto root = Group::create();
    root->addChild(fogNode);
    v->setSceneData(root);
    v->frame();
    expectNoGlErrors(*v);
    expectDeferredAsAsked(*fogNode, path);
    const Image img = v->capture();
    const Camera& cam = *v->camera();
    const glm::dvec3 clear(cam.clearColor);

    auto hit = [&](double x, double y, glm::dvec3& p) {
        const Ray r = rayThrough(cam, x, y);
        if (r.dir.z >= 0) return false;
        p = r.origin + r.dir * (-r.origin.z / r.dir.z);
        return std::abs(p.x) < half && std::abs(p.y - cy) < half;
    };
    int plane = 0, sky = 0, worst = 0;
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) {
            glm::dvec3 p, q;
            int corners = 0;
            for (int c = 0; c < 4; ++c)
                corners += hit(x + (c & 1), y + (c >> 1), q);
            glm::dvec3 expected;
            const Ray r = rayThrough(cam, x + 0.5, y + 0.5);
            if (corners == 4 && hit(x + 0.5, y + 0.5, p)) {
                expected = mixd(glm::dvec3(surface), glm::dvec3(params.color), kOf(params, r.origin, p));
                ++plane;
            } else if (corners == 0) {
                expected = mixd(clear, glm::dvec3(params.color),
                                kOf(params, r.origin, r.origin + r.dir * double(params.skyDistance)));
                ++sky;
            } else {
                continue; // an edge pixel: partial coverage
            }
            const int e = channelError(img, x, y, expected);
            worst = std::max(worst, e);
            EXPECT_LE(e, 2) << pathName(path) << " pixel (" << x << "," << y << ")";
        }
    EXPECT_GT(plane, kSize * kSize / 3);
    EXPECT_GT(sky, kSize * kSize / 8);
    std::printf("%s/%s: %d plane and %d sky pixels, worst error %d/255\n", pathName(path).c_str(),
                response == FogResponse::Linear ? "Linear" : "Exponential", plane, sky, worst);
}

INSTANTIATE_TEST_SUITE_P(AllModes, FogPlane,
                         ::testing::Combine(::testing::ValuesIn(kPaths),
                                            ::testing::Values(FogResponse::Linear, FogResponse::Exponential)),
                         [](const auto& param) {
                             std::string name =
                                 pathName(std::get<0>(param.param)) +
                                 (std::get<1>(param.param) == FogResponse::Linear ? "Linear" : "Exponential");
                             std::erase(name, '/');
                             return name;
                         });

// An opaque wall behind a pane of glass, looking horizontally through the centre pixel.
struct GlassResult {
    glm::ivec4 glass, noGlass;
    double kn, kf; // fog amounts on [O, Pn] and [Pn, P]
};

GlassResult renderGlass(Path path, float alpha, float glassDist, float wallDist) {
    const glm::vec3 wall(0.9f, 0.3f, 0.1f), pane(0.1f, 0.6f, 0.3f);
    FogParameters params = testFog(FogResponse::Exponential);
    params.density = 0.01f;
    params.falloff = 0.02f;
    GlassResult out{};
    for (bool withGlass : {true, false}) {
        auto v = perspectiveViewer({0, 0, 3}, {0, 10, 3});
        auto fogNode = fogOn(params, path);
        fogNode->addChild(panel(400, 400, facingCamera(wallDist, 3), flatMaterial(wall)));
        if (withGlass) {
            auto g = panel(20, 20, facingCamera(glassDist, 3), flatMaterial(pane, alpha));
            auto& ss = g->getOrCreateStateSet();
            ss.blend.set(BlendMode::Alpha);
            ss.cullFace.set(CullFace::None);
            // The seed's figure 2 setup: the glass is in the depth buffer ("depth-writing glass").
            TransparencyDetails details;
            details.writeDepth = true;
            ss.transparency.set(details);
            fogNode->addChild(g);
        }
        v->setSceneData(fogNode);
        v->frame();
        expectNoGlErrors(*v);
        expectDeferredAsAsked(*fogNode, path);
        const Image img = v->capture();
        (withGlass ? out.glass : out.noGlass) = pixelAt(img, kSize / 2, kSize / 2);
        const Ray r = rayThrough(*v->camera(), kSize / 2 + 0.5, kSize / 2 + 0.5);
        const glm::dvec3 pn = r.origin + r.dir * (glassDist / r.dir.y);
        const glm::dvec3 p = r.origin + r.dir * (wallDist / r.dir.y);
        out.kn = kOf(params, r.origin, pn);
        out.kf = kOf(params, pn, p);
    }
    return out;
}

// Both Forward paths: the glass fogs itself; the wall behind it is fogged by its material or,
// deferred, by the pass before the glass is drawn.
TEST(FogGlass, ForwardExponentialMatchesPhysicalCompositing) {
    const glm::dvec3 cb(0.9, 0.3, 0.1), cg(0.1, 0.6, 0.3), cf(0.8, 0.8, 0.9);
    for (Path path : {kDeferred, kInMaterials})
        for (auto [gd, wd] : {std::pair{5.0f, 30.0f}, std::pair{20.0f, 80.0f}, std::pair{2.0f, 150.0f}})
            for (float a : {0.0f, 0.3f, 1.0f}) {
                if (!path.defer && gd != 20.0f) continue; // the fallback: one distance is enough
                const GlassResult r = renderGlass(path, a, gd, wd);
                const glm::dvec3 physical =
                    (1 - r.kn) * (double(a) * cg + (1 - double(a)) * mixd(cb, cf, r.kf)) + r.kn * cf;
                for (int c = 0; c < 3; ++c)
                    EXPECT_NEAR(r.glass[c], srgbByte(physical[c]), 2)
                        << pathName(path) << " alpha " << a << " glass at " << gd;
                if (a == 0.0f) {
                    for (int c = 0; c < 3; ++c)
                        EXPECT_NEAR(r.glass[c], r.noGlass[c], 1) << "clear glass must not change the pixel";
                }
            }
}

// The glass test with a transmissive pane (KHR_materials_transmission: white, smooth, thin, no
// light on it): it shows the copy of the opaque scene. Forward fog fogged that copy on [O, P]; the
// fog's transmitted hook takes the [O, Pn] share out, so the pane's own fog puts it back once.
// ForwardSplit fogs what is behind the nearest surface on [Pn, P] only, so the copy is already
// what reaches the pane. Physical either way: (1 − kn)·(1 − F)·mix(wall, fog, kf) + kn·fog.
// Linear float target.
TEST(FogGlass, TransmissivePaneMatchesPhysicalCompositing) {
    const glm::dvec3 cb(0.9, 0.3, 0.1);
    FogParameters params = testFog(FogResponse::Exponential);
    params.density = 0.01f;
    params.falloff = 0.02f;
    const glm::dvec3 cf(params.color);
    double sensitivity = 0.0;
    for (Path path : {kDeferred, kInMaterials, Path{FogMode::ForwardSplit}})
        for (auto [gd, wd] : {std::pair{5.0f, 30.0f}, std::pair{20.0f, 80.0f}, std::pair{2.0f, 150.0f}}) {
            if (!path.defer && gd != 20.0f) continue; // the fallback: one distance is enough
            auto v = perspectiveViewer({0, 0, 3}, {0, 10, 3});
            v->renderer().options().colorTarget = RendererOptions::ColorTarget::Rgba32F;
            auto fogNode = fogOn(params, path);
            fogNode->addChild(panel(400, 400, facingCamera(wd, 3), flatMaterial(glm::vec3(cb))));
            auto m = metallicRoughness(glm::vec3(1.0f), 0.0f, 0.0f);
            m->transmission = 1.0f;
            fogNode->addChild(panel(20, 20, facingCamera(gd, 3), m));
            v->setSceneData(fogNode);
            v->frame();
            expectNoGlErrors(*v);
            expectDeferredAsAsked(*fogNode, path);
            const FloatImage img = v->renderer().readPixelsLinear();
            const float* p = &img.rgba[(std::size_t(kSize / 2) * std::size_t(kSize) + kSize / 2) * 4];
            const Ray r = rayThrough(*v->camera(), kSize / 2 + 0.5, kSize / 2 + 0.5);
            const glm::dvec3 pn = r.origin + r.dir * (gd / r.dir.y), pw = r.origin + r.dir * (wd / r.dir.y);
            const double kn = kOf(params, r.origin, pn), kf = kOf(params, pn, pw);
            const double F = 0.04 + 0.96 * std::pow(1.0 - r.dir.y, 5.0); // Schlick at the pane (normal −Y)
            const glm::dvec3 physical = (1 - kn) * (1 - F) * mixd(cb, cf, kf) + kn * cf;
            // Fogging the copy's [O, Pn] share twice would give this.
            const glm::dvec3 twice = (1 - kn) * (1 - F) * mixd(cb, cf, kOf(params, r.origin, pw)) + kn * cf;
            for (int c = 0; c < 3; ++c)
                EXPECT_NEAR(p[c], physical[c], 2e-3)
                    << pathName(path) << " glass at " << gd << " channel " << c;
            sensitivity = std::max(sensitivity, glm::length(physical - twice));
        }
    EXPECT_GT(sensitivity, 0.02) << "the cases tell single from double fog";
}

TEST(FogGlass, PaperModesAreCharacterised) {
    const glm::dvec3 cb(0.9, 0.3, 0.1), cg(0.1, 0.6, 0.3), cf(0.8, 0.8, 0.9);
    for (auto [gd, wd] : {std::pair{5.0f, 30.0f}, std::pair{20.0f, 80.0f}})
        for (float a : {0.0f, 0.3f, 1.0f}) {
            const double al = a;
            // ForwardSplit (seed §2): glass fogged on [O, Pn], the wall behind it on [Pn, P] only.
            const GlassResult s = renderGlass({FogMode::ForwardSplit}, a, gd, wd);
            const glm::dvec3 split = al * mixd(cg, cf, s.kn) + (1 - al) * mixd(cb, cf, s.kf);
            const glm::dvec3 physical = (1 - s.kn) * (al * cg + (1 - al) * mixd(cb, cf, s.kf)) + s.kn * cf;
            // PostProcess (seed §1): one k from the glass depth over the composited pixel.
            const GlassResult p = renderGlass({FogMode::PostProcess}, a, gd, wd);
            const glm::dvec3 post = mixd(al * cg + (1 - al) * cb, cf, p.kn);
            double splitErr = 0, postErr = 0;
            for (int c = 0; c < 3; ++c) {
                EXPECT_NEAR(s.glass[c], srgbByte(split[c]), 2) << "ForwardSplit alpha " << a;
                EXPECT_NEAR(p.glass[c], srgbByte(post[c]), 2) << "PostProcess alpha " << a;
                splitErr = std::max(splitErr, std::abs(double(s.glass[c] - srgbByte(physical[c]))));
                postErr = std::max(postErr, std::abs(double(p.glass[c] - srgbByte(physical[c]))));
            }
            std::printf("glass %.0f m, wall %.0f m, alpha %.1f: error vs physical ForwardSplit %.0f/255, "
                        "PostProcess %.0f/255\n",
                        double(gd), double(wd), al, splitErr, postErr);
            if (a < 1.0f) {
                // Both lose fog behind the glass: the wall seen through it is too clear.
                EXPECT_GT(splitErr, 2.0);
                EXPECT_GT(postErr, 2.0);
            }
        }
}

// Seed §2 with ε tied to depth precision: a wall 3 km away (near plane 0.5 m) is foreground
// everywhere, so ForwardSplit equals Forward. A fixed small ε would send pixels to the
// background branch and leave them unfogged.
TEST(FogSplit, EpsilonScalesWithDistance) {
    Image images[2];
    for (int i = 0; i < 2; ++i) {
        auto v = perspectiveViewer({0, 0, 30}, {0, 100, 30}, 0.5f, 20000.0f);
        FogParameters p = FogParameters::solid();
        p.sky = FogSky::Off;
        auto fogNode = FogNode::create(p, i ? FogMode::ForwardSplit : FogMode::Forward);
        auto ground = shapes::heightfield(-4000, 0, 8000, 6000, 64, 64, [](float x, float y) {
            return 20.0f * std::sin(x * 0.01f) + y * 0.01f;
        });
        ground->getOrCreateStateSet().material.set(flatMaterial({0.3f, 0.35f, 0.2f}));
        ground->getOrCreateStateSet().cullFace.set(CullFace::None);
        fogNode->addChild(ground);
        fogNode->addChild(panel(6000, 600, facingCamera(3000, 300), flatMaterial({0.5f, 0.5f, 0.5f})));
        v->setSceneData(fogNode);
        v->frame();
        expectNoGlErrors(*v);
        images[i] = v->capture();
    }
    EXPECT_EQ(channelsDiffering(images[0], images[1]), 0);
}

TEST(FogForeign, ApplicationShaderGetsTheSameFogAsTheBuiltInMaterial) {
    const glm::vec3 surface(0.2f, 0.5f, 0.1f);
    for (Path path : kPaths) {
        Image images[2];
        for (int foreign = 0; foreign < 2; ++foreign) {
            auto v = perspectiveViewer({0, 0, 8}, {0, 60, 0});
            auto fogNode = fogOn(testFog(FogResponse::Exponential), path);
            auto q = shapes::quad(400, 400);
            auto& ss = q->getOrCreateStateSet();
            if (foreign) {
                ss.program.set(ShaderProgram::create("app", kForeignVert, kForeignFrag));
                ss.setUniform("appColor", surface);
            } else {
                ss.material.set(flatMaterial(surface));
            }
            auto t = Transform::create(glm::translate(glm::mat4(1.0f), {0, 190, 0}));
            t->addChild(q);
            fogNode->addChild(t);
            v->setSceneData(fogNode);
            v->frame();
            expectNoGlErrors(*v);
            expectDeferredAsAsked(*fogNode, path);
            images[foreign] = v->capture();
        }
        EXPECT_EQ(channelsDiffering(images[0], images[1]), 0) << pathName(path);
    }
}

TEST(FogScope, OnlyTheSubtreeIsFoggedAndTheInnerNodeWins) {
    auto v = orthoTopViewer(64, 2.0f);
    FogParameters outerP = testFog(FogResponse::Exponential), innerP = outerP;
    outerP.sky = innerP.sky = FogSky::Off;
    outerP.density = 0.05f;
    outerP.falloff = 0.0f;
    innerP.density = 0.2f;
    innerP.falloff = 0.0f;
    innerP.color = {0.9f, 0.2f, 0.2f};
    auto outer = FogNode::create(outerP);
    auto inner = FogNode::create(innerP);
    outer->setDeferOpaque(true); // allowed, so the fallbacks below are the node's own choice
    inner->setDeferOpaque(true);
    const glm::vec3 c(0.1f, 0.4f, 0.2f);
    auto at = [](float x, float y) { return glm::translate(glm::mat4(1.0f), {x, y, 0}); };
    outer->addChild(panel(1, 1, at(-1, 1), flatMaterial(c)));
    inner->addChild(panel(1, 1, at(1, 1), flatMaterial(c)));
    outer->addChild(inner);
    auto root = Group::create();
    root->addChild(outer);
    root->addChild(panel(1, 1, at(0, -1), flatMaterial(c)));
    v->setSceneData(root);
    v->frame();
    expectNoGlErrors(*v);
    const Image img = v->capture();
    const glm::dvec3 eye(0, 0, 10);
    auto pixelOf = [](double wx, double wy) {
        return glm::ivec2(int((wx + 2) / 4 * 64), int((2 - wy) / 4 * 64));
    };
    struct Probe {
        double x, y;
        const FogParameters* fog;
    } probes[] = {{-1, 1, &outerP}, {1, 1, &innerP}, {0, -1, nullptr}};
    for (const Probe& p : probes) {
        const glm::ivec2 px = pixelOf(p.x, p.y);
        const glm::dvec3 world(-2 + (px.x + 0.5) / 16.0, 2 - (px.y + 0.5) / 16.0, 0);
        const glm::dvec3 expected =
            p.fog ? mixd(glm::dvec3(c), glm::dvec3(p.fog->color), kOf(*p.fog, eye, world)) : glm::dvec3(c);
        EXPECT_LE(channelError(img, px.x, px.y, expected), 2) << "probe at " << p.x << "," << p.y;
    }
    // Fog on a subtree falls back to the materials: the unfogged panel would get the pass's fog.
    EXPECT_FALSE(outer->lastFrameDeferred());
    EXPECT_FALSE(inner->lastFrameDeferred());
    // With the outer node over everything it still does: the inner fog's colour code runs after
    // it in the nested items, and a pass after the opaque items would swap the two.
    v->setSceneData(outer);
    v->frame();
    EXPECT_FALSE(outer->lastFrameDeferred());
    EXPECT_FALSE(inner->lastFrameDeferred());
}

TEST(FogSky, OffLeavesTheClearColourAndFarPlaneFogsToTheFarPlane) {
    for (Path path : {kDeferred, kInMaterials})
        for (FogSky sky : {FogSky::Off, FogSky::FarPlane}) {
            auto v = perspectiveViewer({0, 0, 8}, {0, 60, 20}, 0.5f, 300.0f);
            FogParameters p = testFog(FogResponse::Exponential);
            p.sky = sky;
            auto fogNode = fogOn(p, path);
            fogNode->addChild(
                panel(1, 1, glm::translate(glm::mat4(1.0f), {0, 5, 0}), flatMaterial({1, 1, 1})));
            v->setSceneData(fogNode);
            v->frame();
            expectNoGlErrors(*v);
            expectDeferredAsAsked(*fogNode, path);
            const Image img = v->capture();
            const Camera& cam = *v->camera();
            for (auto [x, y] : {std::pair{5, 5}, std::pair{kSize / 2, 10}, std::pair{kSize - 3, kSize / 3}}) {
                const Ray r = rayThrough(cam, x + 0.5, y + 0.5);
                // Where the ray meets the far plane (view-space depth = far).
                const glm::dvec3 fwd = -glm::dvec3(glm::transpose(glm::dmat3(cam.viewMatrix))[2]);
                const glm::dvec3 farPoint = r.origin + r.dir * (300.0 / glm::dot(r.dir, fwd));
                const double k = sky == FogSky::Off ? 0.0 : kOf(p, r.origin, farPoint);
                EXPECT_LE(channelError(img, x, y, mixd(glm::dvec3(cam.clearColor), glm::dvec3(p.color), k)),
                          2)
                    << pathName(path) << (sky == FogSky::Off ? " Off" : " FarPlane") << " pixel " << x << ","
                    << y << " k " << k << " got " << pixelAt(img, x, y)[0] << "," << pixelAt(img, x, y)[1]
                    << "," << pixelAt(img, x, y)[2];
            }
        }
}

// Whether the last frame ran a pass of this name (RendererOptions::timePasses on).
bool ranPass(Viewer& v, const std::string& name) {
    const auto& times = v.renderer().stats().passTimes;
    return std::any_of(times.begin(), times.end(), [&](const auto& t) { return t.name == name; });
}

// Looking steeply down from 40 m, every sky direction in view points under the horizon into fog
// that saturates at maxOpacity = 0.6: k is the same for every sky pixel, and the main pass's clear
// paints it (FogNode::setClearSky). The image equals the one the "fog sky" pass draws within 1 LSB
// and the closed form within 2; the pass does not run. Looking up, k varies and the pass runs.
TEST(FogSky, AUniformSkyIsPaintedByTheClearExactly) {
    FogParameters p = testFog(FogResponse::Exponential);
    p.maxOpacity = 0.6f;
    const glm::vec3 ground(0.2f, 0.5f, 0.1f);
    Image images[2];
    for (bool clearSky : {true, false}) {
        auto v = perspectiveViewer({0, 0, 40}, {0, 20, 0});
        v->renderer().options().timePasses = true;
        auto fogNode = fogOn(p, kInMaterials);
        fogNode->setClearSky(clearSky);
        fogNode->addChild(panel(30, 30, glm::translate(glm::mat4(1.0f), {0, 20, 0}), flatMaterial(ground)));
        v->setSceneData(fogNode);
        v->frame();
        expectNoGlErrors(*v);
        EXPECT_EQ(ranPass(*v, "fog sky"), !clearSky) << "clearSky " << clearSky;
        images[clearSky] = v->capture();
        const Camera& cam = *v->camera();
        for (auto [x, y] : {std::pair{2, 2}, std::pair{kSize - 3, 4}, std::pair{3, kSize - 3}}) {
            const Ray r = rayThrough(cam, x + 0.5, y + 0.5);
            ASSERT_LT(r.dir.z, -0.5); // under the horizon: the sky rule's ray dives into the fog
            const double k = kOf(p, r.origin, r.origin + r.dir * double(p.skyDistance));
            ASSERT_NEAR(k, 0.6, 1e-6); // maxOpacity, a float
            EXPECT_LE(channelError(images[clearSky], x, y,
                                   mixd(glm::dvec3(cam.clearColor), glm::dvec3(p.color), k)),
                      2)
                << "clearSky " << clearSky << " pixel " << x << "," << y;
        }
    }
    int worst = 0;
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x)
            for (int c = 0; c < 4; ++c)
                worst = std::max(worst, std::abs(pixelAt(images[0], x, y)[c] - pixelAt(images[1], x, y)[c]));
    EXPECT_LE(worst, 1);

    auto up = perspectiveViewer({0, 0, 8}, {0, 60, 20});
    up->renderer().options().timePasses = true;
    auto fogNode = fogOn(p, kInMaterials);
    fogNode->addChild(panel(1, 1, glm::translate(glm::mat4(1.0f), {0, 5, 0}), flatMaterial(ground)));
    up->setSceneData(fogNode);
    up->frame();
    EXPECT_TRUE(ranPass(*up, "fog sky")) << "k varies over a sky that rises out of the fog";
}

// An effect that declares a pass after the opaque items which draws nothing.
class AfterOpaquePass : public EffectNode {
public:
    std::string_view kind() const override { return "after_opaque_pass"; }
    const ShaderSnippet& snippet() const override {
        static const ShaderSnippet s = [] {
            ShaderSnippet sn;
            sn.name = "after_opaque_pass";
            return sn;
        }();
        return s;
    }
    void setupFrame(FrameSetup& f) const override {
        struct Data {
            ResourceId colour;
        };
        f.addPass<Data>(
            "after opaque", PassPhase::AfterOpaque,
            [](PassBuilder& b, Data& d) { d.colour = b.write(resources::ViewColour); },
            [](PassCommands& c, const Data& d) { c.target({d.colour}); });
    }
};

// The same uniform sky, but the panel does not write depth: its pixels stay at the far plane, so
// the sky rule fogs them again over the panel's own fog (what the pass does and the clear could
// not). The pass runs and the panel's centre is mix(mix(panel, fog, k_panel), fog, k_sky).
TEST(FogSky, TheClearIsNotUsedWhereItCouldDifferFromThePass) {
    FogParameters p = testFog(FogResponse::Exponential);
    p.maxOpacity = 0.6f;
    auto v = perspectiveViewer({0, 0, 40}, {0, 20, 0});
    v->renderer().options().timePasses = true;
    auto fogNode = fogOn(p, kInMaterials);
    const glm::vec3 colour(0.9f, 0.2f, 0.1f);
    auto quad = panel(30, 30, glm::translate(glm::mat4(1.0f), {0, 20, 0}), flatMaterial(colour));
    quad->getOrCreateStateSet().depth.set(DepthState{.test = true, .write = false});
    fogNode->addChild(quad);
    v->setSceneData(fogNode);
    v->frame();
    expectNoGlErrors(*v);
    EXPECT_TRUE(ranPass(*v, "fog sky"));
    const Image img = v->capture();
    const Camera& cam = *v->camera();
    const Ray r = rayThrough(cam, kSize / 2 + 0.5, kSize / 2 + 0.5);
    const glm::dvec3 onPanel = r.origin + r.dir * (-r.origin.z / r.dir.z);
    ASSERT_LT(std::abs(onPanel.y - 20.0), 10.0);
    const double kPanel = kOf(p, r.origin, onPanel),
                 kSky = kOf(p, r.origin, r.origin + r.dir * double(p.skyDistance));
    const glm::dvec3 expected =
        mixd(mixd(glm::dvec3(colour), glm::dvec3(p.color), kPanel), glm::dvec3(p.color), kSky);
    EXPECT_LE(channelError(img, kSize / 2, kSize / 2, expected), 2)
        << "k panel " << kPanel << " k sky " << kSky;

    // Neither may the clear stand in for the pass where an opaque-bin item blends over what is
    // there, where the view keeps last frame's depth, where the fog or the clear colour lies
    // outside [0, 1] (the target clamps the blend's inputs, the clear only its result), where an
    // opaque item is a drawable (it may set its own depth state in its draw), or where a pass
    // after the opaque items runs before the fog's (it may draw over the far plane).
    for (int variant = 0; variant < 6; ++variant) {
        auto view = perspectiveViewer({0, 0, 40}, {0, 20, 0});
        view->renderer().options().timePasses = true;
        FogParameters q = p;
        if (variant == 2) q.color = {1.5f, 0.8f, 0.9f};
        auto node = fogOn(q, kInMaterials);
        auto item = panel(30, 30, glm::translate(glm::mat4(1.0f), {0, 20, 0}), flatMaterial(colour));
        if (variant == 0) {
            item->getOrCreateStateSet().blend.set(BlendMode::Alpha);
            item->getOrCreateStateSet().renderBin.set(RenderBin::Opaque);
        }
        if (variant == 1) view->camera()->clearDepthEnabled = false;
        if (variant == 3) view->camera()->clearColor = {0.05f, 1.2f, 0.3f, 1.0f};
        node->addChild(item);
        if (variant == 4) { // a few unblended rain drops: an opaque-bin drawable
            auto drops = ParticleSystemNode::rain({4.0f, 4.0f}, 64);
            drops->getOrCreateStateSet().blend.set(BlendMode::Off);
            drops->getOrCreateStateSet().renderBin.set(RenderBin::Opaque);
            node->addChild(drops);
        }
        NodePtr scene = node;
        if (variant == 5) { // declares an after-opaque pass before the fog below it does
            auto outer = std::make_shared<AfterOpaquePass>();
            outer->addChild(node);
            scene = outer;
        }
        view->setSceneData(scene);
        view->frame();
        expectNoGlErrors(*view);
        EXPECT_TRUE(ranPass(*view, "fog sky")) << "variant " << variant;
    }
}

// The override FogNode uses: refused where the view keeps its colour or the colour is not finite;
// the last one set is the one the main pass clears to.
TEST(FogSky, SetClearColourIsRefusedWhereItCannotHold) {
    RenderQueue queue;
    ViewInfo keeps;
    keeps.clearsColour = false;
    FrameSetup kept(keeps, queue);
    EXPECT_THROW(kept.setClearColour(glm::vec4(0.5f)), std::logic_error);
    EXPECT_FALSE(kept.clearColourOverride().has_value());
    FrameSetup clears(ViewInfo{}, queue);
    EXPECT_THROW(clears.setClearColour(glm::vec4(0.5f, std::nanf(""), 0.5f, 1.0f)), std::logic_error);
    clears.setClearColour({0.1f, 0.2f, 0.3f, 1.0f});
    clears.setClearColour({0.4f, 0.5f, 0.6f, 1.0f});
    EXPECT_EQ(clears.clearColourOverride().value(), glm::vec4(0.4f, 0.5f, 0.6f, 1.0f));
}

// A lit scene of every kind of opaque item (lit material, alpha-masked, foreign shader) with
// blended glass in front, seen from an orbit: the deferred pass and the fog in the materials give
// the same image within 1 LSB (the deferred colour is stored in sRGB8 before it is fogged; where
// the lit colour exceeds 1 the target clips it before the pass, which it does not in a material). Then
// a multisampled view, which has no single depth per pixel, falls back.
TEST(FogDeferred, EqualsTheFogInTheMaterialsOnAnOrbit) {
    auto scene = [] {
        auto root = Group::create();
        auto ambient = Light::create(LightType::Ambient);
        ambient->color = glm::vec3(0.15f);
        root->addChild(ambient);
        auto sun = Light::create(LightType::Directional);
        sun->direction = {-0.3f, -0.5f, -0.8f};
        sun->color = glm::vec3(0.4f); // every surface stays below 1: an sRGB8 target clips above
        root->addChild(sun);
        auto ground = shapes::quad(300, 300);
        ground->getOrCreateStateSet().material.set(Material::create());
        root->addChild(ground);
        for (int i = 0; i < 6; ++i) {
            const float a = float(i) * 1.05f, r = 6.0f + 9.0f * float(i);
            auto t =
                Transform::create(glm::translate(glm::mat4(1.0f), {r * std::cos(a), r * std::sin(a), 1.5f}));
            t->addChild(shapes::box({2, 2, 3 + float(i)}));
            auto m = metallicRoughness({0.8f - 0.1f * float(i), 0.3f, 0.2f + 0.1f * float(i)}, 0.0f, 0.6f);
            if (i == 2) m->alphaCutoff = 0.5f; // the masked variant
            t->getOrCreateStateSet().material.set(m);
            root->addChild(t);
        }
        auto app = shapes::quad(4, 4);
        app->getOrCreateStateSet().program.set(ShaderProgram::create("app", kForeignVert, kForeignFrag));
        app->getOrCreateStateSet().setUniform("appColor", glm::vec3(0.2f, 0.5f, 0.1f));
        root->addChild(panel(4, 4, facingCamera(-4, 2), flatMaterial({0.3f, 0.3f, 0.3f})));
        auto appAt = Transform::create(facingCamera(4, 2));
        appAt->addChild(app);
        root->addChild(appAt);
        auto glass = panel(6, 4, facingCamera(0, 2), flatMaterial({0.1f, 0.6f, 0.3f}, 0.4f));
        glass->getOrCreateStateSet().blend.set(BlendMode::Alpha);
        glass->getOrCreateStateSet().cullFace.set(CullFace::None);
        root->addChild(glass);
        return root;
    };
    FogParameters p = FogParameters::ground();
    p.density = 0.03f;
    p.falloff = 0.1f;
    for (float angle : {0.4f, 2.2f}) {
        const glm::vec3 eye(30 * std::cos(angle), 30 * std::sin(angle), 6 + 4 * std::sin(angle));
        Image images[2];
        for (Path path : {kDeferred, kInMaterials}) {
            auto v = perspectiveViewer(eye, {0, 0, 1}, 0.5f, 1000.0f);
            auto fogNode = fogOn(p, path);
            fogNode->addChild(scene());
            v->setSceneData(fogNode);
            v->frame();
            expectNoGlErrors(*v);
            expectDeferredAsAsked(*fogNode, path);
            images[path.defer ? 0 : 1] = v->capture();
        }
        EXPECT_EQ(channelsDiffering(images[0], images[1], 1), 0) << "orbit angle " << angle;
        EXPECT_GT(channelsDiffering(images[0], images[1], 0), 0) << "the paths are really different";
    }
    auto v = perspectiveViewer({30, 0, 6}, {0, 0, 1});
    v->camera()->setAntiAliasing(AntiAliasing::msaa(4));
    auto fogNode = FogNode::create(p);
    fogNode->setDeferOpaque(true);
    fogNode->addChild(scene());
    v->setSceneData(fogNode);
    v->frame();
    expectNoGlErrors(*v);
    EXPECT_FALSE(fogNode->lastFrameDeferred());
}

// Only the opaque items decide: glass in an order-independent bin (colour code after the fog in
// the glass's effect set) keeps its forward fog, and the opaque items behind it still take the
// pass; the image equals the fog in the materials within 1 LSB, as on the orbit above.
TEST(FogDeferred, GlassInAnOitBinDoesNotStopThePass) {
    FogParameters p = FogParameters::ground();
    p.density = 0.03f;
    p.falloff = 0.1f;
    Image images[2];
    for (Path path : {kDeferred, kInMaterials}) {
        auto v = perspectiveViewer({30, 0, 6}, {0, 0, 1}, 0.5f, 1000.0f);
        auto root = Group::create();
        auto ground = shapes::quad(300, 300);
        ground->getOrCreateStateSet().material.set(Material::create());
        root->addChild(ground);
        root->addChild(panel(4, 4, facingCamera(-4, 2), flatMaterial({0.3f, 0.3f, 0.3f})));
        auto bin = TransparencyBin::create(TransparencyMode::WeightedBlended);
        ASSERT_FALSE(bin->snippet().colorCode.empty()) << "the bin must add colour code after the fog";
        auto glass = panel(6, 4, facingCamera(0, 2), flatMaterial({0.1f, 0.6f, 0.3f}, 0.4f));
        glass->getOrCreateStateSet().blend.set(BlendMode::Alpha);
        glass->getOrCreateStateSet().cullFace.set(CullFace::None);
        bin->addChild(glass);
        root->addChild(bin);
        auto fogNode = fogOn(p, path);
        fogNode->addChild(root);
        v->setSceneData(fogNode);
        v->frame();
        expectNoGlErrors(*v);
        expectDeferredAsAsked(*fogNode, path);
        images[path.defer ? 0 : 1] = v->capture();
    }
    EXPECT_EQ(channelsDiffering(images[0], images[1], 1), 0);
    EXPECT_GT(channelsDiffering(images[0], images[1], 0), 0) << "the paths are really different";
}

TEST(FogNodeApi, DeferringIsOffByDefault) {
    auto v = perspectiveViewer({30, 0, 6}, {0, 0, 1});
    auto fogNode = FogNode::create(FogParameters::ground());
    fogNode->addChild(panel(4, 4, glm::mat4(1.0f), flatMaterial({0.5f, 0.5f, 0.5f})));
    v->setSceneData(fogNode);
    v->frame();
    EXPECT_FALSE(fogNode->deferOpaque());
    EXPECT_FALSE(fogNode->lastFrameDeferred());
    fogNode->setDeferOpaque(true);
    v->frame();
    EXPECT_TRUE(fogNode->lastFrameDeferred()) << "the same scene defers once allowed";
}

TEST(FogNodeApi, BadParametersAreRefusedAndThePreviousOnesStay) {
    auto node = FogNode::create(FogParameters::ground());
    const float nan = std::nanf("");
    const float inf = std::numeric_limits<float>::infinity();
    auto with = [](auto edit) {
        FogParameters p;
        edit(p);
        return p;
    };
    const FogParameters bad[] = {
        with([](FogParameters& p) { p.density = -1e-4f; }),
        with([&](FogParameters& p) { p.density = nan; }),
        with([&](FogParameters& p) { p.density = inf; }),
        with([](FogParameters& p) { p.falloff = -1.0f; }),
        with([&](FogParameters& p) { p.falloff = nan; }),
        with([&](FogParameters& p) { p.color.g = nan; }),
        with([](FogParameters& p) { p.color.b = -0.5f; }),
        with([&](FogParameters& p) { p.referenceHeight = inf; }),
        with([](FogParameters& p) { p.up = glm::vec3(0.0f); }),
        with([&](FogParameters& p) { p.up.x = nan; }),
        with([](FogParameters& p) { p.maxOpacity = 1.5f; }),
        with([](FogParameters& p) { p.skyDistance = 0.0f; }),
        with([](FogParameters& p) { p.response = FogResponse(7); }),
        with([](FogParameters& p) { p.sky = FogSky(9); }),
    };
    for (const FogParameters& p : bad) {
        try {
            node->setParameters(p);
            ADD_FAILURE() << "accepted bad fog parameters";
        } catch (const std::invalid_argument& e) {
            EXPECT_EQ(std::string(e.what()).rfind("sgfx: FogParameters: ", 0), 0u) << e.what();
        }
        EXPECT_EQ(node->parameters().density, 1e-3f);
        EXPECT_EQ(node->parameters().falloff, 4.5e-3f);
    }
    EXPECT_THROW(node->setMode(FogMode(3)), std::invalid_argument);
    EXPECT_EQ(node->mode(), FogMode::Forward);
    EXPECT_NO_THROW(node->setParameters(with([](FogParameters& p) { p.up = {0, 2, 0}; })));
    EXPECT_FLOAT_EQ(node->parameters().up.y, 1.0f); // normalised
}

TEST(FogNodeApi, ModesSwitchAtRunTimeWithoutErrors) {
    auto v = perspectiveViewer({0, 0, 8}, {0, 60, 0});
    auto fogNode = FogNode::create(testFog(FogResponse::Exponential));
    fogNode->addChild(
        panel(400, 400, glm::translate(glm::mat4(1.0f), {0, 190, 0}), flatMaterial({0.2f, 0.5f, 0.1f})));
    v->setSceneData(fogNode);
    Image first;
    for (int i = 0; i < 7; ++i) {
        fogNode->setMode(FogMode(i % 3));
        v->frame();
        expectNoGlErrors(*v);
        if (i == 0) first = v->capture();
    }
    fogNode->setMode(FogMode::Forward);
    v->frame();
    EXPECT_EQ(v->capture().pixels, first.pixels);
    fogNode->enabled = false;
    v->frame();
    EXPECT_NE(v->capture().pixels, first.pixels);
}

// The split's pre-pass keeps alpha-mask cut-outs: the wall seen through the holes of a masked
// card (a tree's leaves) is foreground there, so ForwardSplit equals Forward pixel for pixel.
TEST(FogSplit, AlphaMaskCutOutsStayOutOfThePrePass) {
    Image images[2];
    for (int i = 0; i < 2; ++i) {
        auto v = perspectiveViewer({0, 0, 3}, {0, 10, 3});
        auto fogNode =
            FogNode::create(testFog(FogResponse::Exponential), i ? FogMode::ForwardSplit : FogMode::Forward);
        fogNode->addChild(panel(400, 400, facingCamera(60, 3), flatMaterial({0.9f, 0.3f, 0.1f})));
        auto mask = std::make_shared<Image>();
        mask->width = 4;
        mask->height = 1;
        mask->channels = 1;
        mask->pixels = {0, 255, 0, 255}; // vertical stripes: two holes
        auto tex = Texture::create(mask, false);
        tex->minFilter = tex->magFilter = Filter::Nearest;
        auto card = flatMaterial({0.1f, 0.6f, 0.3f});
        card->alphaTexture = tex;
        card->alphaCutoff = 0.5f;
        fogNode->addChild(panel(6, 6, facingCamera(10, 3), card));
        v->setSceneData(fogNode);
        v->frame();
        expectNoGlErrors(*v);
        images[i] = v->capture();
    }
    EXPECT_EQ(channelsDiffering(images[0], images[1]), 0);
}

// A render-to-texture camera with split fog inside: its pre-pass draws its own view's items
// (not the main view's), so its image equals the Forward one. Shown on a quad in the main view.
TEST(FogSplit, RenderToTextureViewsUseTheirOwnPrePass) {
    Image images[2];
    for (int i = 0; i < 2; ++i) {
        auto v = orthoTopViewer(64, 1.0f);
        auto rtt = Camera::create();
        rtt->setViewport(0, 0, 48, 48);
        rtt->setPerspective(60.0f, 0.5f, 2000.0f);
        rtt->setLookAt({0, 0, 3}, {0, 10, 3});
        rtt->clearColor = {0, 0, 0, 1};
        rtt->renderTarget = Texture::create(nullptr);
        auto fogNode =
            FogNode::create(testFog(FogResponse::Exponential), i ? FogMode::ForwardSplit : FogMode::Forward);
        fogNode->addChild(panel(400, 400, facingCamera(40, 3), flatMaterial({0.9f, 0.3f, 0.1f})));
        rtt->addChild(fogNode);
        // The display: ambient light 1 times the texture.
        auto screen = Material::create();
        screen->ambient = glm::vec3(1.0f);
        screen->diffuse = glm::vec4(0, 0, 0, 1);
        screen->baseColorTexture = rtt->renderTarget;
        auto display = panel(2, 2, glm::mat4(1.0f), screen);
        auto ambient = Light::create(LightType::Ambient);
        auto root = Group::create();
        root->addChild(ambient);
        root->addChild(rtt);
        root->addChild(display);
        v->setSceneData(root);
        v->frame();
        expectNoGlErrors(*v);
        images[i] = v->capture();
    }
    EXPECT_EQ(channelsDiffering(images[0], images[1]), 0);
    // And the fog is there: the centre is not the wall's own colour.
    EXPECT_GT(std::abs(pixelAt(images[1], 32, 32)[1] - srgbByte(0.3)), 10);
}

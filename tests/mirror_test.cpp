// Mirrored transforms (a negative determinant): the whole scene, lights included, under
// scale(-1, 1, 1) and seen by the mirrored camera must render as the unmirrored scene's image
// flipped left to right. glTF 2.0 (Meshes) and OpenGL flip the front winding with the sign of the
// determinant: without that, single-sided meshes show their insides, double-sided ones light the
// wrong side, and normal maps tilt the wrong way along the bitangent.
#include "TestUtil.h"

#include <sgfx/Geometry.h>
#include <sgfx/Group.h>
#include <sgfx/Material.h>
#include <sgfx/MeshTools.h>
#include <sgfx/Shapes.h>
#include <sgfx/Texture.h>

#include <functional>

using namespace sgfx;
using sgfx::test::pixelAt;

namespace {

constexpr int kWidth = 96;
constexpr int kHeight = 72;
const glm::mat4 kMirror = glm::scale(glm::mat4(1.0f), glm::vec3(-1.0f, 1.0f, 1.0f));

std::shared_ptr<Material> grey() {
    auto m = Material::create();
    m->diffuse = {0.7f, 0.6f, 0.5f, 1.0f};
    m->ambient = glm::vec3(0.1f);
    return m;
}

// A normal map that tilts the normal along the bitangent only (tangent-space (0, 0.6, 0.8)):
// a bitangent of the wrong sign tilts it the other way.
std::shared_ptr<Texture> bitangentTilt() {
    auto img = Image::create(1, 1, 3);
    const glm::dvec3 nt(0.0, 0.6, 0.8);
    for (int c = 0; c < 3; ++c)
        img->pixels[std::size_t(c)] = std::uint8_t(std::lround((nt[c] * 0.5 + 0.5) * 255.0));
    return Texture::create(img, false);
}

using Content = std::function<void(Group&)>;

// The scene: a sun and `content`, under `world` (identity or the mirror).
std::unique_ptr<Viewer> render(const Content& content, const glm::mat4& world) {
    auto v = Viewer::createHeadless(kWidth, kHeight);
    v->renderer().options().colorTarget = RendererOptions::ColorTarget::Rgba32F;
    auto root = Transform::create(world);
    auto sun = Light::create(LightType::Directional);
    sun->direction = glm::normalize(glm::vec3(-0.5f, 0.3f, -0.8f));
    root->addChild(sun);
    content(*root);
    v->setSceneData(root);
    const glm::vec3 eye = glm::vec3(world * glm::vec4(2.2f, -3.5f, 2.8f, 1.0f));
    const glm::vec3 centre = glm::vec3(world * glm::vec4(0.3f, 0.1f, 0.2f, 1.0f));
    v->camera()->setLookAt(eye, centre, {0, 0, 1});
    v->camera()->setPerspective(45.0f, 0.1f, 50.0f);
    v->camera()->clearColor = {0.05f, 0.1f, 0.2f, 1.0f};
    v->frame();
    return v;
}

struct Difference {
    double mean = 0.0;     // mean absolute difference per channel
    double agreeing = 0.0; // fraction of pixels within 0.02 on every channel
};

// a against b flipped left to right (flip = false: a against b as it is).
Difference compare(const FloatImage& a, const FloatImage& b, bool flip) {
    Difference d;
    std::size_t agree = 0;
    for (int y = 0; y < a.height; ++y)
        for (int x = 0; x < a.width; ++x) {
            const int xb = flip ? a.width - 1 - x : x;
            double worst = 0.0;
            for (int c = 0; c < 3; ++c) {
                const double e = std::abs(double(a.rgba[(std::size_t(y) * a.width + x) * 4 + c]) -
                                          double(b.rgba[(std::size_t(y) * b.width + xb) * 4 + c]));
                d.mean += e;
                worst = std::max(worst, e);
            }
            agree += worst <= 0.02 ? 1 : 0;
        }
    d.mean /= double(a.width) * a.height * 3;
    d.agreeing = double(agree) / (double(a.width) * a.height);
    return d;
}

void expectMirrorImage(const Content& content, const char* what) {
    const FloatImage plain = render(content, glm::mat4(1.0f))->renderer().readPixelsLinear();
    const FloatImage mirrored = render(content, kMirror)->renderer().readPixelsLinear();
    const Difference same = compare(mirrored, plain, true);
    // Edge pixels may differ (the fill rule is not mirror-symmetric); everything else must agree.
    EXPECT_GE(same.agreeing, 0.985) << what << ": mean difference " << same.mean;
    EXPECT_LT(same.mean, 0.004) << what;
    // The comparison has teeth: the scene is not left-right symmetric (most pixels are background,
    // so compare the disagreeing fractions).
    const Difference unflipped = compare(mirrored, plain, false);
    EXPECT_LT(unflipped.agreeing, 0.97) << what << ": the scene is too symmetric to test mirroring";
    EXPECT_GT(1.0 - unflipped.agreeing, 4.0 * (1.0 - same.agreeing)) << what;
}

} // namespace

TEST(Mirror, SingleSidedMeshesShowTheirOutside) {
    expectMirrorImage(
        [](Group& root) {
            auto box = shapes::box({1.2f, 0.7f, 0.9f});
            box->getOrCreateStateSet().material.set(grey());
            auto t = Transform::create(
                glm::rotate(glm::translate(glm::mat4(1.0f), {0.5f, 0.3f, 0.45f}), 0.4f, glm::vec3(0, 0, 1)));
            t->addChild(box);
            root.addChild(t);
            auto cone = shapes::cone(0.4f, 1.2f, 24);
            cone->getOrCreateStateSet().material.set(grey());
            auto c = Transform::create(glm::translate(glm::mat4(1.0f), {-0.8f, -0.4f, 0.0f}));
            c->addChild(cone);
            root.addChild(c);
        },
        "box and cone");
}

TEST(Mirror, DoubleSidedMeshesLightTheSideInView) {
    expectMirrorImage(
        [](Group& root) {
            // An open tube seen from above: its outside and, through the top, its inside.
            auto tube = shapes::cylinder(0.6f, 1.0f, 32, false);
            tube->getOrCreateStateSet().material.set(grey());
            tube->getOrCreateStateSet().cullFace.set(CullFace::None);
            auto t = Transform::create(glm::translate(glm::mat4(1.0f), {0.4f, 0.2f, 0.0f}));
            t->addChild(tube);
            root.addChild(t);
        },
        "open tube, double-sided");
}

TEST(Mirror, NormalMapsTiltAlongTheMirroredBitangent) {
    for (bool suppliedTangents : {true, false}) {
        expectMirrorImage(
            [&](Group& root) {
                auto m = grey();
                m->normalTexture = bitangentTilt();
                auto q = shapes::quad(2.5f, 2.0f);
                if (!suppliedTangents) q->tangents.clear(); // the screen-space frame
                q->getOrCreateStateSet().material.set(m);
                auto t = Transform::create(glm::rotate(glm::translate(glm::mat4(1.0f), {0.6f, 0.0f, 0.0f}),
                                                       0.5f, glm::vec3(0, 0, 1)));
                t->addChild(q);
                root.addChild(t);
            },
            suppliedTangents ? "normal-mapped quad, supplied tangents" : "normal-mapped quad, no tangents");
    }
}

TEST(Mirror, MirroredAndPlainCopiesAreNotBatchedTogether) {
    // The same mesh twice, once mirrored: auto-instancing would draw the two in one batch, with
    // one winding. Each copy's pixels must be what that copy alone (never batched) renders.
    // The left copy plain, the right one mirrored in y.
    auto copyMatrix = [](float x) {
        const glm::mat4 m = glm::translate(glm::mat4(1.0f), {x, 0.2f * x, 0.3f});
        return x > 0.0f ? m * glm::scale(glm::mat4(1.0f), glm::vec3(1.0f, -1.0f, 1.0f)) : m;
    };
    auto copies = [&](bool left, bool right) {
        return [=](Group& root) {
            // One mesh for both copies (GL objects belong to one viewer: a new mesh per render).
            auto box = shapes::box({0.8f, 0.5f, 0.6f});
            box->getOrCreateStateSet().material.set(grey());
            for (float x : {-0.9f, 0.9f}) {
                if ((x < 0.0f && !left) || (x > 0.0f && !right)) continue;
                auto t = Transform::create(copyMatrix(x));
                t->addChild(box);
                root.addChild(t);
            }
        };
    };
    auto both = render(copies(true, true), glm::mat4(1.0f));
    EXPECT_EQ(both->renderer().stats().instanceBatches, 0u) << "a mirrored and a plain copy were batched";
    const FloatImage together = both->renderer().readPixelsLinear();
    const FloatImage background =
        render(copies(false, false), glm::mat4(1.0f))->renderer().readPixelsLinear();
    std::size_t covered = 0;
    for (bool left : {true, false}) {
        const FloatImage alone = render(copies(left, !left), glm::mat4(1.0f))->renderer().readPixelsLinear();
        for (std::size_t i = 0; i < alone.rgba.size(); i += 4) {
            bool drawn = false;
            for (int c = 0; c < 3; ++c)
                drawn |= std::abs(alone.rgba[i + c] - background.rgba[i + c]) > 1e-4f;
            if (!drawn) continue;
            ++covered;
            for (int c = 0; c < 3; ++c)
                ASSERT_NEAR(together.rgba[i + c], alone.rgba[i + c], 1e-4f)
                    << (left ? "plain" : "mirrored") << " copy, pixel " << i / 4;
        }
    }
    EXPECT_GT(covered, std::size_t(kWidth * kHeight / 20)) << "the copies cover too little of the image";

    // The same two matrices as instances of one Geometry (one draw): the same pixels.
    auto instanced = shapes::box({0.8f, 0.5f, 0.6f});
    instanced->getOrCreateStateSet().material.set(grey());
    instanced->instances = {copyMatrix(0.9f), copyMatrix(-0.9f)}; // the mirrored one first
    const FloatImage drawnOnce = render([&](Group& root) { root.addChild(instanced); }, glm::mat4(1.0f))
                                     ->renderer()
                                     .readPixelsLinear();
    for (std::size_t i = 0; i < together.rgba.size(); ++i)
        ASSERT_NEAR(drawnOnce.rgba[i], together.rgba[i], 1e-4f) << "instanced, pixel " << i / 4;
}

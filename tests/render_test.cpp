// Headless render tests on OSMesa (llvmpipe), ≤ 256×256, compared with analytic values.
#include "TestUtil.h"

#include <sgfx/Geometry.h>
#include <sgfx/Group.h>
#include <sgfx/Shapes.h>
#include <sgfx/gl/Objects.h>
#include <sgfx/nodes/debugtint/DebugTintNode.h>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>
#include <sgfx_glad/gl.h>

#include <filesystem>

using namespace sgfx;
using namespace sgfx::test;

namespace {

constexpr int kSize = 64;
constexpr float kHalf = 2.0f; // ortho half-extent in metres

// World position of a pixel centre on the z = 0 plane for orthoTopViewer(kSize, kHalf).
glm::vec3 worldOfPixel(int px, int py) {
    return {-kHalf + (float(px) + 0.5f) / kSize * 2 * kHalf, kHalf - (float(py) + 0.5f) / kSize * 2 * kHalf,
            0.0f};
}

std::shared_ptr<Node> quadAt(float w, float h, glm::vec3 pos, std::shared_ptr<Material> m) {
    auto t = Transform::create(glm::translate(glm::mat4(1.0f), pos));
    auto q = shapes::quad(w, h);
    q->getOrCreateStateSet().material.set(std::move(m));
    t->addChild(q);
    return t;
}

void expectPixel(const Image& img, int x, int y, glm::dvec3 linear, int tol = 2) {
    const glm::ivec4 p = pixelAt(img, x, y);
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(p[c], srgbByte(linear[c]), tol) << "pixel (" << x << "," << y << ") channel " << c;
}

} // namespace

TEST(Render, ClearColourIsSrgbEncodedOnce) {
    auto v = Viewer::createHeadless(32, 32);
    for (glm::vec3 c :
         {glm::vec3(0.5f, 0.25f, 1.0f), glm::vec3(0.0f, 0.002f, 0.8f), glm::vec3(1.0f, 0.05f, 0.0f)}) {
        v->camera()->clearColor = glm::vec4(c, 1.0f);
        v->frame();
        const Image img = v->capture();
        ASSERT_EQ(img.width, 32);
        expectPixel(img, 0, 0, c, 1);
        expectPixel(img, 31, 31, c, 1);
    }
    EXPECT_NE(v->context().renderer().find("llvmpipe"), std::string::npos) << v->context().renderer();
    expectNoGlErrors(*v);
}

TEST(Render, LitQuadMatchesBlinnPhong) {
    auto v = orthoTopViewer(kSize, kHalf);
    auto root = Group::create();
    auto m = Material::create();
    m->ambient = {0.2f, 0.3f, 0.4f};
    m->diffuse = {0.6f, 0.4f, 0.2f, 1.0f};
    m->specular = {0.5f, 0.5f, 0.5f};
    m->shininess = 16.0f;
    m->emissive = {0.01f, 0.02f, 0.0f};
    root->addChild(quadAt(4.0f, 4.0f, {0, 0, 0}, m));
    auto sun = Light::create(LightType::Directional);
    sun->direction = glm::normalize(glm::vec3(-0.3f, -0.2f, -1.0f));
    sun->color = {0.9f, 0.8f, 0.7f};
    auto amb = Light::create(LightType::Ambient);
    amb->color = glm::vec3(0.25f);
    root->addChild(sun);
    root->addChild(amb);
    v->setSceneData(root);
    v->frame();
    const Image img = v->capture();
    const glm::dvec3 N(0, 0, 1), L = glm::normalize(-glm::dvec3(sun->direction));
    const glm::dvec3 eye(0, 0, 10);
    for (auto [px, py] : {std::pair{5, 5}, {32, 32}, {60, 10}, {20, 50}, {45, 45}}) {
        const glm::dvec3 P = worldOfPixel(px, py);
        const glm::dvec3 V = glm::normalize(eye - P);
        const glm::dvec3 H = glm::normalize(L + V);
        const double ndotl = std::max(glm::dot(N, L), 0.0);
        const double spec = std::pow(std::max(glm::dot(N, H), 0.0), double(m->shininess));
        const glm::dvec3 expected =
            glm::dvec3(m->emissive) + 0.25 * glm::dvec3(m->ambient) +
            glm::dvec3(sun->color) * (glm::dvec3(m->diffuse) * ndotl + glm::dvec3(m->specular) * spec);
        expectPixel(img, px, py, expected);
    }
    expectNoGlErrors(*v);
}

TEST(Render, DepthTestKeepsNearestWhateverTheOrder) {
    for (bool nearFirst : {true, false}) {
        auto v = orthoTopViewer(kSize, kHalf);
        auto root = Group::create();
        auto nearQuad = quadAt(2.0f, 2.0f, {0, 0, 1}, flatMaterial({1, 0, 0}));
        auto farQuad = quadAt(4.0f, 4.0f, {0, 0, 0}, flatMaterial({0, 0, 1}));
        root->addChild(nearFirst ? nearQuad : farQuad);
        root->addChild(nearFirst ? farQuad : nearQuad);
        v->setSceneData(root);
        v->frame();
        const Image img = v->capture();
        expectPixel(img, 32, 32, {1, 0, 0}, 0);
        expectPixel(img, 4, 4, {0, 0, 1}, 0);
    }
}

TEST(Render, AlphaMaskCutsBelowTheCutoff) {
    auto v = orthoTopViewer(kSize, kHalf);
    auto root = Group::create();
    // Alpha texture: left half 0.2, right half 0.9 (linear, nearest-sampled).
    auto mask = Image::create(2, 1, 1);
    mask->pixels = {51, 230};
    auto tex = Texture::create(mask, false);
    tex->minFilter = tex->magFilter = Filter::Nearest;
    auto m = flatMaterial({1, 0, 0});
    m->alphaTexture = tex;
    m->alphaCutoff = 0.5f;
    root->addChild(quadAt(4.0f, 4.0f, {0, 0, 1}, m));
    root->addChild(quadAt(4.0f, 4.0f, {0, 0, 0}, flatMaterial({0, 1, 0})));
    v->setSceneData(root);
    v->frame();
    const Image img = v->capture();
    expectPixel(img, 10, 32, {0, 1, 0}, 0); // cut: the green quad behind shows
    expectPixel(img, 54, 32, {1, 0, 0}, 0); // kept
    // Raising the cutoff above 0.9 cuts everything.
    m->alphaCutoff = 0.95f;
    v->frame();
    expectPixel(v->capture(), 54, 32, {0, 1, 0}, 0);
    expectNoGlErrors(*v);
}

TEST(Render, PngRoundTripKeepsPixelsAndOrientation) {
    auto v = orthoTopViewer(kSize, kHalf);
    auto root = Group::create();
    root->addChild(quadAt(4.0f, 2.0f, {0, 1, 0}, flatMaterial({1, 1, 0}))); // top half of the view (+Y is up)
    v->setSceneData(root);
    v->frame();
    const Image img = v->capture();
    expectPixel(img, 32, 5, {1, 1, 0}, 0);  // top row region
    expectPixel(img, 32, 58, {0, 0, 0}, 0); // bottom
    const auto path = std::filesystem::temp_directory_path() / "sgfx_roundtrip.png";
    writePng(path, img);
    const Image back = readPng(path);
    std::filesystem::remove(path);
    ASSERT_EQ(back.width, img.width);
    ASSERT_EQ(back.height, img.height);
    ASSERT_EQ(back.channels, 4);
    EXPECT_EQ(back.pixels, img.pixels);
    EXPECT_THROW(readPng("/nonexistent/x.png"), std::runtime_error);
    EXPECT_THROW(writePng("/nonexistent/dir/x.png", img), std::runtime_error);
}

TEST(Render, DebugTintAppliesThroughTheBuiltInMaterial) {
    auto v = orthoTopViewer(kSize, kHalf);
    auto tint = DebugTintNode::create({0, 0, 1, 0.25f});
    tint->addChild(quadAt(2.0f, 4.0f, {-1, 0, 0}, flatMaterial({1, 0.5f, 0})));
    auto root = Group::create();
    root->addChild(tint);
    root->addChild(quadAt(2.0f, 4.0f, {1, 0, 0}, flatMaterial({1, 0.5f, 0})));
    v->setSceneData(root);
    v->frame();
    const Image img = v->capture();
    expectPixel(img, 10, 32, glm::mix(glm::dvec3(1, 0.5, 0), glm::dvec3(0, 0, 1), 0.25));
    expectPixel(img, 54, 32, {1, 0.5, 0});
    EXPECT_THROW(tint->setTint({0, 0, 0, 2}), std::invalid_argument);
    EXPECT_THROW(tint->setTint({std::nanf(""), 0, 0, 0.5f}), std::invalid_argument);
    EXPECT_FLOAT_EQ(tint->tint().a, 0.25f); // unchanged after the refusals
    expectNoGlErrors(*v);
}

TEST(Render, LiveGlObjectCountReturnsToZeroAfterTeardown) {
    ASSERT_EQ(gl::liveObjects().total(), 0);
    {
        auto v = orthoTopViewer(kSize, kHalf);
        auto root = Group::create();
        auto m = flatMaterial({1, 0, 0});
        m->baseColorTexture = Texture::create(Image::create(4, 4, 4));
        root->addChild(quadAt(2, 2, {0, 0, 0}, m));
        auto tint = DebugTintNode::create();
        tint->addChild(quadAt(1, 1, {1, 1, 0.5f}, flatMaterial({0, 1, 0})));
        root->addChild(tint);
        v->setSceneData(root);
        v->frame();
        v->frame();
        EXPECT_GT(gl::liveObjects().total(), 5);
        EXPECT_GE(gl::liveObjects()[gl::Kind::Program], 2);
        // The scene outlives the viewer here: the viewer must release its GPU copies itself.
        static std::shared_ptr<Node> keepAlive;
        keepAlive = root;
        v.reset();
        EXPECT_EQ(gl::liveObjects().total(), 0);
        keepAlive.reset();
    }
    EXPECT_EQ(gl::liveObjects().total(), 0);
}

TEST(Render, GeometryEditsReachTheGpu) {
    auto v = orthoTopViewer(kSize, kHalf);
    auto q = shapes::quad(1.0f, 1.0f);
    q->getOrCreateStateSet().material.set(flatMaterial({1, 1, 1}));
    v->setSceneData(q);
    v->frame();
    expectPixel(v->capture(), 32, 32, {1, 1, 1}, 0);
    for (auto& p : q->positions)
        p += glm::vec3(1.5f, 0, 0);
    q->dirty();
    v->frame();
    const Image img = v->capture();
    expectPixel(img, 32, 32, {0, 0, 0}, 0);
    expectPixel(img, 56, 32, {1, 1, 1}, 0);
}

TEST(Contexts, EglHeadlessWhereAvailable) {
    std::unique_ptr<GraphicsContext> ctx;
    std::string why;
    try {
        ctx = std::make_unique<EglContext>();
    } catch (const ContextError& e) {
        why = e.what();
    }
    SGFX_REQUIRE(ctx, "an EGL context (libegl1, libegl-mesa0): " << why);
    Viewer v(std::move(ctx));
    v.camera()->setViewport(0, 0, 16, 16);
    v.camera()->clearColor = {0.25f, 0.5f, 0.75f, 1};
    v.frame();
    expectPixel(v.capture(), 8, 8, {0.25, 0.5, 0.75}, 1);
}

// OSMesa's own drawable (the default framebuffer) takes the size asked for: a clear reaches its
// last pixel at each size, and a size out of range is refused with the old one kept.
TEST(Contexts, OsmesaDrawableTakesTheSizeAskedFor) {
    OsmesaContext ctx(40, 12);
    auto lastPixel = [](int w, int h, float red) {
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        glViewport(0, 0, w, h);
        glClearColor(red, 0.5f, 0.25f, 1.0f);
        glClear(GL_COLOR_BUFFER_BIT);
        unsigned char px[4] = {77, 77, 77, 77}; // neither value a clear writes: a read that misses fails
        glReadPixels(w - 1, h - 1, 1, 1, GL_RGBA, GL_UNSIGNED_BYTE, px);
        return int(px[0]);
    };
    EXPECT_EQ(lastPixel(40, 12, 1.0f), 255);
    ctx.resizeDrawable(96, 64);
    EXPECT_EQ(lastPixel(96, 64, 0.0f), 0);
    EXPECT_THROW(ctx.resizeDrawable(0, 64), std::invalid_argument);
    EXPECT_THROW(ctx.resizeDrawable(96, 20000), std::invalid_argument);
    EXPECT_EQ(lastPixel(96, 64, 1.0f), 255);
    EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
}

// SGFX_HEADLESS only decides Headless::Default: an explicit kind is kept (the cluster's --egl,
// a test pinned to OSMesa). Whether Default already read the variable in this process does not
// matter here, so the test holds when the whole binary runs in one process.
TEST(Contexts, AnExplicitHeadlessKindIgnoresTheEnvironment) {
    const char* saved = std::getenv("SGFX_HEADLESS");
    const std::string keep = saved ? saved : "";
    setenv("SGFX_HEADLESS", "egl", 1);
    {
        auto v = Viewer::createHeadless(16, 16, Viewer::Headless::Osmesa);
        EXPECT_NE(dynamic_cast<OsmesaContext*>(&v->context()), nullptr);
    }
    setenv("SGFX_HEADLESS", "osmesa", 1);
    {
        auto v = Viewer::createHeadless(16, 16, Viewer::Headless::Egl);
        EXPECT_NE(dynamic_cast<EglContext*>(&v->context()), nullptr);
    }
    if (saved)
        setenv("SGFX_HEADLESS", keep.c_str(), 1);
    else
        unsetenv("SGFX_HEADLESS");
}

TEST(Contexts, WindowWithoutDisplaySaysSo) {
    const char* saved = std::getenv("DISPLAY");
    const std::string keep = saved ? saved : "";
    unsetenv("DISPLAY");
    const char* wl = std::getenv("WAYLAND_DISPLAY");
    const std::string keepWl = wl ? wl : "";
    unsetenv("WAYLAND_DISPLAY");
    try {
        GlfwWindow w(64, 64, "test");
        ADD_FAILURE() << "a window opened without a display";
    } catch (const ContextError& e) {
        EXPECT_NE(std::string(e.what()).find("no display"), std::string::npos) << e.what();
    }
    if (saved) setenv("DISPLAY", keep.c_str(), 1);
    if (wl) setenv("WAYLAND_DISPLAY", keepWl.c_str(), 1);
}

TEST(Render, NestedCameraRendersToATextureUsedInTheSameFrame) {
    auto v = orthoTopViewer(kSize, kHalf);
    // The sub-camera sees a 0.5-grey quad; its image textures a quad in the main view.
    auto rtt = Camera::create();
    rtt->setViewport(0, 0, 16, 16);
    rtt->setLookAt({0, 0, 10}, {0, 0, 0}, {0, 1, 0});
    rtt->projectionMatrix = glm::ortho(-1.0f, 1.0f, -1.0f, 1.0f, 0.1f, 100.0f);
    rtt->clearColor = {0, 0, 1, 1};
    rtt->addChild(quadAt(2.0f, 2.0f, {0, 0, 0}, flatMaterial({0.5f, 0.5f, 0.5f})));
    rtt->renderTarget = Texture::create(nullptr);
    auto screen = Material::create();
    screen->ambient = glm::vec3(1.0f);
    screen->diffuse = {0, 0, 0, 1};
    screen->baseColorTexture = rtt->renderTarget;
    auto amb = Light::create(LightType::Ambient);
    auto root = Group::create();
    root->addChild(amb);
    root->addChild(rtt);
    root->addChild(quadAt(2.0f, 2.0f, {0, 0, 0}, screen));
    v->setSceneData(root);
    v->frame();
    const Image img = v->capture();
    expectPixel(img, 32, 32, {0.5, 0.5, 0.5}); // sRGB-stored, decoded on sampling, encoded once
    expectPixel(img, 4, 4, {0, 0, 0}, 0);      // outside the screen quad: main clear colour
    expectNoGlErrors(*v);
    // The target follows the sub-camera's viewport.
    rtt->setViewport(0, 0, 8, 4);
    v->frame();
    expectPixel(v->capture(), 32, 32, {0.5, 0.5, 0.5});
}

TEST(Render, TexturesAreUprightOnShapes) {
    // Image top row red, bottom row green; on a quad seen from the front the top half is red.
    auto v = orthoTopViewer(kSize, kHalf);
    auto img = Image::create(1, 2, 3);
    img->pixels = {255, 0, 0, 0, 255, 0};
    auto tex = Texture::create(img, false);
    tex->minFilter = tex->magFilter = Filter::Nearest;
    auto m = Material::create();
    m->ambient = glm::vec3(1.0f);
    m->diffuse = {0, 0, 0, 1};
    m->baseColorTexture = tex;
    auto root = Group::create();
    root->addChild(Light::create(LightType::Ambient));
    root->addChild(quadAt(4.0f, 4.0f, {0, 0, 0}, m));
    v->setSceneData(root);
    v->frame();
    const Image out = v->capture();
    expectPixel(out, 32, 8, {1, 0, 0}, 0);
    expectPixel(out, 32, 56, {0, 1, 0}, 0);
}

TEST(Render, PerVertexLightingEqualsPerPixelOnAFlatDiffuseQuad) {
    // Directional light, no specular: the Gouraud option must give the same pixels.
    Image images[2];
    for (int mode = 0; mode < 2; ++mode) {
        auto v = orthoTopViewer(kSize, kHalf);
        v->renderer().options().lighting =
            mode ? RendererOptions::Lighting::PerVertex : RendererOptions::Lighting::PerPixel;
        auto m = Material::create();
        m->diffuse = {0.7f, 0.5f, 0.3f, 1};
        auto root = Group::create();
        auto sun = Light::create();
        sun->direction = glm::normalize(glm::vec3(0.2f, -0.5f, -1.0f));
        root->addChild(sun);
        root->addChild(quadAt(4.0f, 4.0f, {0, 0, 0}, m));
        v->setSceneData(root);
        v->frame();
        images[mode] = v->capture();
        const double ndotl = -sun->direction.z;
        expectPixel(images[mode], 32, 32, glm::dvec3(0.7, 0.5, 0.3) * ndotl); // no ambient light
    }
    EXPECT_EQ(images[0].pixels, images[1].pixels);
}

TEST(Render, TangentSpaceNormalMapTiltsTheShadingNormal) {
    // A constant normal map n_t = normalize(0.6, 0, 0.8) on a +Z quad whose tangent is +X:
    // the world normal becomes (0.6, 0, 0.8), so N·L follows the tilted normal.
    auto v = orthoTopViewer(kSize, kHalf);
    auto img = Image::create(1, 1, 3);
    const glm::dvec3 nt(0.6, 0.0, 0.8);
    for (int c = 0; c < 3; ++c)
        img->pixels[std::size_t(c)] = std::uint8_t(std::lround((nt[c] * 0.5 + 0.5) * 255.0));
    auto normalMap = Texture::create(img, false);
    normalMap->minFilter = normalMap->magFilter = Filter::Nearest;
    auto m = Material::create();
    m->diffuse = {0.8f, 0.8f, 0.8f, 1};
    m->ambient = glm::vec3(0);
    m->normalTexture = normalMap;
    auto sun = Light::create();
    sun->direction = glm::normalize(glm::vec3(-1.0f, 0.0f, -1.0f)); // towards the light: (1,0,1)/√2
    auto root = Group::create();
    root->addChild(sun);
    root->addChild(quadAt(4.0f, 4.0f, {0, 0, 0}, m));
    v->setSceneData(root);
    v->frame();
    // The texel stores n_t quantised to 8 bits; use the decoded value for the expectation.
    glm::dvec3 decoded;
    for (int c = 0; c < 3; ++c)
        decoded[c] = img->pixels[std::size_t(c)] / 255.0 * 2.0 - 1.0;
    const glm::dvec3 N = glm::normalize(decoded);
    const double ndotl = std::max(glm::dot(N, glm::normalize(glm::dvec3(1, 0, 1))), 0.0);
    const Image out = v->capture();
    expectPixel(out, 32, 32, glm::dvec3(0.8) * ndotl);
    // Without the map the flat normal gives a different value: the test can tell them apart.
    EXPECT_GT(std::abs(srgbByte(0.8 * ndotl) - srgbByte(0.8 / std::sqrt(2.0))), 10);
    expectNoGlErrors(*v);
}

TEST(Render, BadLightsAndMaterialsNeverReachPixels) {
    auto v = orthoTopViewer(kSize, kHalf);
    auto m = Material::create();
    m->diffuse = {0.5f, 0.5f, 0.5f, 1};
    auto root = Group::create();
    auto good = Light::create();
    auto nanLight = Light::create();
    nanLight->direction = {std::nanf(""), 0, -1};
    auto zeroDir = Light::create();
    zeroDir->direction = glm::vec3(0.0f);
    auto negative = Light::create(LightType::Ambient);
    negative->color = glm::vec3(-1.0f);
    for (auto& l : {good, nanLight, zeroDir, negative})
        root->addChild(l);
    root->addChild(quadAt(4, 4, {0, 0, 0}, m));
    v->setSceneData(root);
    v->frame();
    expectPixel(v->capture(), 32, 32, {0.5, 0.5, 0.5}); // only the good light counts
    // A NaN material colour is refused with a message naming what is wrong.
    m->diffuse.r = std::nanf("");
    try {
        v->frame();
        FAIL() << "NaN material drawn";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("Material colours"), std::string::npos) << e.what();
    }
    m->diffuse.r = 0.5f;
    EXPECT_NO_THROW(v->frame());
}

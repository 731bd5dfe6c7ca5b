// Image-based light (EnvironmentLightNode): the CPU prefilter against closed forms and an
// independent quadrature, then rendered spheres. The white furnace: under a uniform environment
// of radiance 1 a sphere returns the directional albedo of its BRDF, computed here by a
// midpoint rule over the hemisphere that shares nothing with the library's importance sampling.
// A mirror-smooth sphere reflects the cube texel its mirror direction hits.
#include "TestUtil.h"

#include <sgfx/nodes/ao/AmbientOcclusionNode.h>
#include <sgfx/nodes/environment/EnvironmentLightNode.h>
#include <sgfx/nodes/sky/SkyNode.h>

#include <sgfx/Geometry.h>
#include <sgfx/Material.h>
#include <sgfx/ModelLoader.h>
#include <sgfx/NodeVisitor.h>
#include <sgfx/Queries.h>
#include <sgfx/Shapes.h>
#include <sgfx/Texture.h>

#include <stb_image_write.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <set>

using namespace sgfx;

namespace {

constexpr double kPi = 3.14159265358979323846;

// The glTF lobe written out from the glTF 2.0 spec, appendix B.3 (GGX D, height-correlated
// Smith V, Schlick F), with the shader's clamp of perceptual roughness at 0.045.
double specularBrdf(double NdotL, double NdotV, double NdotH, double VdotH, double f0, double roughness) {
    const double r = std::max(roughness, 0.045);
    const double a2 = r * r * r * r;
    const double d = NdotH * NdotH * (a2 - 1.0) + 1.0;
    const double D = a2 / (kPi * d * d);
    const double vis = 0.5 / (NdotL * std::sqrt(NdotV * NdotV * (1.0 - a2) + a2) +
                              NdotV * std::sqrt(NdotL * NdotL * (1.0 - a2) + a2));
    const double F = f0 + (1.0 - f0) * std::pow(1.0 - VdotH, 5.0);
    return F * D * vis;
}

// ∫ f(L, V) cosθ_L dω over the hemisphere by the midpoint rule in (θ, φ): the directional albedo
// of the lobe for normal incidence cosine NdotV.
double directionalAlbedo(double NdotV, double f0, double roughness, int nTheta = 1200, int nPhi = 240) {
    const glm::dvec3 v(std::sqrt(1.0 - NdotV * NdotV), 0.0, NdotV);
    double sum = 0.0;
    for (int i = 0; i < nTheta; ++i) {
        const double theta = (i + 0.5) * (kPi / 2) / nTheta;
        for (int j = 0; j < nPhi; ++j) {
            const double phi = (j + 0.5) * 2 * kPi / nPhi;
            const glm::dvec3 l(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                               std::cos(theta));
            const glm::dvec3 h = glm::normalize(l + v);
            sum += specularBrdf(l.z, NdotV, h.z, glm::dot(v, h), f0, roughness) * l.z * std::sin(theta);
        }
    }
    return sum * (kPi / 2 / nTheta) * (2 * kPi / nPhi);
}

constexpr int kSize = 96;
constexpr float kHalf = 1.2f;   // ortho half extent
constexpr float kRadius = 1.0f; // sphere radius

// How the frame is lit besides the environment: per-pixel or per-vertex, and with the light list
// (a black directional light beyond maxUnrolledLights = 0) or not.
struct Paths {
    RendererOptions::Lighting lighting = RendererOptions::Lighting::PerPixel;
    bool lightList = false;
};

// Renders a unit sphere with `material` under `node` (its only light) from +Z, orthographic.
FloatImage renderSphere(const std::shared_ptr<Material>& material, std::shared_ptr<EffectNode> node,
                        Paths paths = {}, std::shared_ptr<Node> extra = nullptr) {
    auto v = test::orthoTopViewer(kSize, kHalf);
    v->renderer().options().lighting = paths.lighting;
    if (paths.lightList) {
        v->renderer().options().maxUnrolledLights = 0;
        auto black = Light::create(LightType::Directional);
        black->color = glm::vec3(0.0f);
        node->addChild(black);
    }
    if (extra) node->addChild(extra);
    // The shader's V points at the eye: far away, it is +Z everywhere to 0.05°, as the
    // expectations below assume.
    v->camera()->setLookAt({0, 0, 1000}, {0, 0, 0}, {0, 1, 0});
    v->camera()->projectionMatrix = glm::ortho(-kHalf, kHalf, -kHalf, kHalf, 900.0f, 1100.0f);
    v->renderer().options().colorTarget = RendererOptions::ColorTarget::Rgba32F;
    auto ball = shapes::sphere(kRadius, 96, 48);
    ball->getOrCreateStateSet().material.set(material);
    node->addChild(ball);
    v->setSceneData(node);
    v->frame();
    test::expectNoGlErrors(*v);
    return v->renderer().readPixelsLinear();
}

glm::vec3 pixel(const FloatImage& img, int x, int y) {
    const float* p = &img.rgba[(std::size_t(y) * img.width + x) * 4];
    return {p[0], p[1], p[2]};
}

// The pixel whose sphere normal has the given N·V (V = +Z) along +X from the centre, and that N.
std::pair<int, glm::dvec3> pixelAtNdotV(double NdotV) {
    const double sinT = std::sqrt(1.0 - NdotV * NdotV);
    const int x = int(std::floor((sinT * kRadius + kHalf) / (2.0 * kHalf) * kSize));
    const double worldX = (x + 0.5) / kSize * 2.0 * kHalf - kHalf;
    const double nx = worldX / kRadius;
    return {x, glm::dvec3(nx, 0.0, std::sqrt(1.0 - nx * nx))};
}

std::shared_ptr<Material> pbr(glm::vec3 base, float metallic, float roughness) {
    return test::metallicRoughness(base, metallic, roughness);
}

} // namespace

TEST(EnvironmentMath, CubeAddressingRoundTripsAndSolidAnglesCoverTheSphere) {
    for (int f = 0; f < 6; ++f)
        for (glm::vec2 st : {glm::vec2(0.1f, 0.2f), glm::vec2(0.5f), glm::vec2(0.93f, 0.71f)}) {
            const env::CubeCoord c = env::cubeCoord(env::cubeDirection(f, st));
            EXPECT_EQ(c.face, f);
            EXPECT_NEAR(c.st.x, st.x, 1e-6f);
            EXPECT_NEAR(c.st.y, st.y, 1e-6f);
        }
    // OpenGL's table 8.19: +X's s runs along -Z and its t along -Y.
    EXPECT_EQ(env::cubeCoord({1, 0, 0}).face, 0);
    EXPECT_NEAR(env::cubeCoord({1, 0, -0.5f}).st.x, 0.75f, 1e-6f);
    EXPECT_NEAR(env::cubeCoord({1, -0.5f, 0}).st.y, 0.75f, 1e-6f);
    EXPECT_EQ(env::cubeCoord({0, 0, -2}).face, 5);
    double total = 0.0;
    for (int t = 0; t < 16; ++t)
        for (int s = 0; s < 16; ++s)
            total += env::texelSolidAngle(16, s, t);
    EXPECT_NEAR(6.0 * total, 4.0 * kPi, 1e-4);
}

TEST(EnvironmentMath, IrradianceOfALinearSkyIsItsClosedForm) {
    // L(d) = 1 + d.z lies in bands 0 and 1, where order-2 SH is exact: the cosine convolution
    // over π gives E(N)/π = 1 + (2/3) N.z (Ramamoorthi and Hanrahan 2001, Â1 = 2π/3).
    env::CubeImage c = env::CubeImage::filled(32, glm::vec3(0.0f));
    for (int f = 0; f < 6; ++f)
        for (int t = 0; t < 32; ++t)
            for (int s = 0; s < 32; ++s) {
                const glm::vec3 d =
                    glm::normalize(env::cubeDirection(f, glm::vec2((s + 0.5f) / 32.0f, (t + 0.5f) / 32.0f)));
                c.texel(f, s, t) = glm::vec3(1.0f + d.z, 2.0f, 1.0f);
            }
    const env::Sh9 sh = env::irradianceSh(c);
    for (glm::vec3 n :
         {glm::vec3(0, 0, 1), glm::vec3(0, 0, -1), glm::vec3(1, 0, 0), glm::normalize(glm::vec3(1, 2, 3))}) {
        const glm::vec3 e = env::evalSh(sh, n);
        EXPECT_NEAR(e.r, 1.0f + 2.0f / 3.0f * n.z, 2e-3f) << n.x << " " << n.y << " " << n.z;
        EXPECT_NEAR(e.g, 2.0f, 2e-3f);
        EXPECT_NEAR(e.b, 1.0f, 2e-3f);
    }
}

TEST(EnvironmentMath, SplitSumTableMatchesTheQuadratureAlbedo) {
    // A + B is the lobe's albedo for F0 = 1, B for F0 = 0: both against the midpoint rule.
    for (double roughness : {0.3, 0.6, 1.0})
        for (double NdotV : {0.2, 0.6, 0.95}) {
            const glm::vec2 ab = env::brdfScaleBias(float(NdotV), float(roughness), 4096);
            EXPECT_NEAR(ab.x + ab.y, directionalAlbedo(NdotV, 1.0, roughness), 0.01)
                << "roughness " << roughness << " N.V " << NdotV;
            EXPECT_NEAR(ab.y, directionalAlbedo(NdotV, 0.0, roughness), 0.005)
                << "roughness " << roughness << " N.V " << NdotV;
        }
}

TEST(EnvironmentMath, UniformRadianceStaysUniformAtEveryLevel) {
    const auto e = Environment::uniform(glm::vec3(0.25f, 0.5f, 2.0f), 16);
    ASSERT_EQ(e->specular().size(), 3u); // 16, 8, 4
    for (const env::CubeImage& level : e->specular())
        for (const auto& face : level.faces)
            for (const glm::vec3& t : face) {
                EXPECT_NEAR(t.r, 0.25f, 1e-5f);
                EXPECT_NEAR(t.b, 2.0f, 1e-4f);
            }
    EXPECT_NEAR(env::evalSh(e->irradiance(), glm::vec3(0.3f, -0.2f, 0.9f)).g, 0.5f, 1e-3f);
}

TEST(Environment, WhiteFurnaceReturnsTheAnalyticAlbedo) {
    const auto white = Environment::uniform(glm::vec3(1.0f));
    struct Case {
        const char* what;
        glm::vec3 base;
        float metallic, roughness;
    };
    for (const Case& c : {Case{"smooth dielectric", glm::vec3(1.0f), 0.0f, 0.2f},
                          Case{"rough dielectric", glm::vec3(1.0f), 0.0f, 0.9f},
                          // Not white: the total depends on the table's E (white cancels it).
                          Case{"grey dielectric", glm::vec3(0.3f, 0.5f, 0.0f), 0.0f, 0.5f},
                          Case{"smooth metal", glm::vec3(0.5f, 0.7f, 0.9f), 1.0f, 0.2f},
                          Case{"rough metal", glm::vec3(0.5f, 0.7f, 0.9f), 1.0f, 0.9f}}) {
        const FloatImage img =
            renderSphere(pbr(c.base, c.metallic, c.roughness), EnvironmentLightNode::create(white));
        for (double NdotV : {0.98, 0.7, 0.4}) {
            const auto [x, n] = pixelAtNdotV(NdotV);
            const double nv = n.z;
            // Schlick's F is linear in F0, so the albedo is F0·(a1 − a0) + a0. Fine in φ: the
            // lobe of roughness 0.2 seen at N·V = 0.4 is a few degrees wide.
            const double a0 = directionalAlbedo(nv, 0.0, c.roughness, 1200, 1200);
            const double a1 = directionalAlbedo(nv, 1.0, c.roughness, 1200, 1200);
            for (int ch = 0; ch < 3; ++ch) {
                // Metal: F0 = base, no diffuse. Dielectric: F0 = 0.04 and a white diffuse layer
                // that gets what the lobe does not reflect, so the total is exactly 1.
                const double f0 = c.metallic > 0.5f ? c.base[ch] : 0.04;
                const double spec = f0 * (a1 - a0) + a0;
                const double expected = c.metallic > 0.5f ? spec : spec + (1.0 - spec) * c.base[ch];
                EXPECT_NEAR(pixel(img, x, kSize / 2)[ch], expected, 0.02 * expected + 0.005)
                    << c.what << " at N.V " << nv << " channel " << ch;
            }
        }
    }
}

// The shared EnvironmentTest model (rows of white metal, white dielectric and black dielectric
// spheres, metallic and roughness from a texture) in a uniform white environment. Each sampled
// pixel is picked (scene query): its sphere row, its normal and its texture coordinates, which give
// the texel's roughness and metallic. A white dielectric returns 1 whatever its roughness and angle
// (the diffuse layer gets what the lobe does not reflect); a white metal returns the lobe's
// directional albedo from the quadrature at that roughness and N·V.
TEST(Environment, SharedEnvironmentTestModelInTheWhiteFurnace) {
    const auto file = std::filesystem::path(SGFX_SOURCE_DIR) / ".." / "shared" / "assets" / "gltf" /
                      "EnvironmentTest" / "glTF" / "EnvironmentTest.gltf";
    if (!test::optionalPrerequisite(std::filesystem::exists(file), "shared glTF set A2")) return;
    auto model = loadModel(file);
    struct Hide : NodeVisitor {
        Hide()
            : NodeVisitor(Mode::AllChildren) {}
        void apply(Node& n) override {
            if (n.name == "ground_plane_n3d") n.nodeMask = 0; // the spheres alone
            traverse(n);
        }
    } hide;
    model->accept(hide);
    auto env = EnvironmentLightNode::create(Environment::uniform(glm::vec3(1.0f)));
    env->addChild(model);
    constexpr int w = 200, h = 120;
    auto v = Viewer::createHeadless(w, h);
    v->renderer().options().colorTarget = RendererOptions::ColorTarget::Rgba32F;
    v->camera()->clearColor = glm::vec4(0.0f);
    const BoundingSphere b = model->bound();
    const glm::vec3 eye = b.center + glm::vec3(0.0f, -2.0f, 0.2f) * b.radius;
    v->camera()->setPerspective(35.0f, 0.05f * b.radius, 10.0f * b.radius);
    v->camera()->setLookAt(eye, b.center, {0, 0, 1});
    v->camera()->computeNearFar = false;
    v->setSceneData(env);
    v->frame();
    test::expectNoGlErrors(*v);
    const FloatImage img = v->renderer().readPixelsLinear();
    std::map<std::pair<int, int>, double> albedo; // (N·V, roughness) in hundredths
    int dielectric = 0, metal = 0;
    double metalMin = 1e9, metalMax = -1e9;
    for (int y = 1; y < h; y += 3)
        for (int x = 1; x < w; x += 3) {
            const float* p = &img.rgba[(std::size_t(y) * w + x) * 4];
            if (p[3] < 0.5f) continue; // background
            const auto hit = pick(*v, x + 0.5, y + 0.5);
            if (!hit || !hit->hit.texcoord) continue; // a silhouette pixel the ray misses
            std::string row;
            for (const Node* n : hit->hit.nodePath)
                if (n->name == "Metallic0" || n->name == "Dielectric0") row = n->name;
            if (row.empty()) continue; // the black row
            const Material& m = **hit->hit.geometry->stateSet()->material.value;
            const Image& map = *m.metallicRoughnessTexture->image;
            const glm::dvec2 uv = glm::fract(*hit->hit.texcoord);
            const std::uint8_t* t = map.pixel(std::min(int(uv.x * map.width), map.width - 1),
                                              std::min(int(uv.y * map.height), map.height - 1));
            const double metallic = t[2] / 255.0, roughness = t[1] / 255.0;
            if (metallic > 0.05 && metallic < 0.95) continue; // the test's cases are the two ends
            const double nv = glm::dot(hit->hit.normal, glm::normalize(glm::dvec3(eye) - hit->hit.point));
            if (nv < 0.15) continue; // grazing: the interpolated normal and the pixel's differ most
            double expected = 1.0;
            if (metallic >= 0.95 && roughness < 0.25) {
                // A near-mirror lobe is too narrow for the midpoint rule; its albedo is near 1.
                for (int c = 0; c < 3; ++c) {
                    EXPECT_GE(p[c], 0.85) << row << " pixel " << x << "," << y << " roughness " << roughness;
                    EXPECT_LE(p[c], 1.02) << row << " pixel " << x << "," << y << " roughness " << roughness;
                }
                ++metal;
                continue;
            }
            if (metallic >= 0.95) {
                const std::pair<int, int> key{int(std::lround(nv * 50)), int(std::lround(roughness * 50))};
                if (!albedo.count(key))
                    albedo[key] = directionalAlbedo(key.first / 50.0, 1.0, key.second / 50.0, 1200, 600);
                expected = albedo[key];
            }
            for (int c = 0; c < 3; ++c)
                EXPECT_NEAR(p[c], expected, 0.03 + 0.03 * expected)
                    << row << " pixel " << x << "," << y << " N.V " << nv << " roughness " << roughness
                    << " metallic " << metallic;
            if (metallic < 0.05) {
                ++dielectric;
            } else {
                ++metal;
                metalMin = std::min(metalMin, expected);
                metalMax = std::max(metalMax, expected);
            }
        }
    std::printf("EnvironmentTest: %d white dielectric and %d white metal samples; metal albedo %.3f..%.3f\n",
                dielectric, metal, metalMin, metalMax);
    EXPECT_GT(dielectric, 30);
    EXPECT_GT(metal, 30);
    EXPECT_GT(metalMax - metalMin, 0.05) << "the samples cover several roughnesses";
}

TEST(Environment, BlinnPhongDiffuseInAUniformEnvironmentIsItsColour) {
    auto m = Material::create();
    m->diffuse = {0.3f, 0.5f, 0.7f, 1.0f};
    m->specular = glm::vec3(0.0f);
    // Every lighting path: per pixel, per vertex (the environment is still per pixel), the list.
    for (const Paths paths : {Paths{}, Paths{RendererOptions::Lighting::PerVertex, false},
                              Paths{RendererOptions::Lighting::PerPixel, true},
                              Paths{RendererOptions::Lighting::PerVertex, true}}) {
        const FloatImage img =
            renderSphere(m, EnvironmentLightNode::create(Environment::uniform(glm::vec3(2.0f)), 0.5f), paths);
        for (double NdotV : {0.95, 0.5}) {
            const auto [x, n] = pixelAtNdotV(NdotV);
            const glm::vec3 p = pixel(img, x, kSize / 2);
            EXPECT_NEAR(p.r, 0.3f, 0.005f)
                << "per vertex " << int(paths.lighting) << " list " << paths.lightList;
            EXPECT_NEAR(p.g, 0.5f, 0.005f);
            EXPECT_NEAR(p.b, 0.7f, 0.005f);
        }
    }
}

TEST(Environment, AmbientOcclusionDarkensTheEnvironmentNearContacts) {
    // A grey sphere resting on a grey ground, lit by a uniform environment alone, seen from above:
    // without occlusion every ground pixel is 0.6 (irradiance/π = 1 everywhere); ambient occlusion
    // (through sgfx_indirect) darkens the ground beside the sphere and not the ground far from it.
    constexpr float kView = 3.0f;
    auto frame = [&](bool ao) {
        auto v = test::orthoTopViewer(kSize, kView);
        v->camera()->setLookAt({0, 0, 1000}, {0, 0, 0}, {0, 1, 0});
        v->camera()->projectionMatrix = glm::ortho(-kView, kView, -kView, kView, 900.0f, 1100.0f);
        v->renderer().options().colorTarget = RendererOptions::ColorTarget::Rgba32F;
        auto grey = Material::create();
        grey->diffuse = {0.6f, 0.6f, 0.6f, 1.0f};
        auto ball = shapes::sphere(kRadius, 96, 48);
        ball->getOrCreateStateSet().material.set(grey);
        auto ground = shapes::quad(2.0f * kView, 2.0f * kView);
        ground->getOrCreateStateSet().material.set(grey);
        auto place = Transform::create(glm::translate(glm::mat4(1.0f), {0.0f, 0.0f, -kRadius}));
        place->addChild(ground);
        auto env = EnvironmentLightNode::create(Environment::uniform(glm::vec3(1.0f)));
        env->addChild(ball);
        env->addChild(place);
        NodePtr root = env;
        if (ao) {
            AmbientOcclusionParameters p;
            p.radius = 1.0f;
            p.bias = 0.01f;
            auto occlusion = AmbientOcclusionNode::create(p);
            occlusion->addChild(env);
            root = occlusion;
        }
        v->setSceneData(root);
        v->frame();
        test::expectNoGlErrors(*v);
        return v->renderer().readPixelsLinear();
    };
    const FloatImage plain = frame(false), occluded = frame(true);
    auto at = [&](float worldX) { return int((worldX + kView) / (2.0f * kView) * kSize); };
    const int near = at(1.1f), far = at(2.8f), y = kSize / 2;
    EXPECT_NEAR(pixel(plain, near, y).g, 0.6f, 0.005f);
    EXPECT_NEAR(pixel(plain, far, y).g, 0.6f, 0.005f);
    EXPECT_LT(pixel(occluded, near, y).g, 0.57f) << "ambient occlusion did not reach the environment light";
    EXPECT_NEAR(pixel(occluded, far, y).g, 0.6f, 0.01f);
}

TEST(Environment, MirrorSphereReflectsTheCubeTexelItsMirrorDirectionHits) {
    // Each texel holds its own (s, t) and its face: a smooth metal of base 1 reflects the texel
    // that R = reflect(-V, N) hits by GL's own cube sampling, so env::cubeCoord (which names the
    // expected texel) is checked against the driver's reading of OpenGL's table 8.19, a flipped
    // s or t on any face included.
    env::CubeImage cube = env::CubeImage::filled(32, glm::vec3(0.0f));
    for (int f = 0; f < 6; ++f)
        for (int t = 0; t < 32; ++t)
            for (int s = 0; s < 32; ++s)
                cube.texel(f, s, t) = glm::vec3((s + 0.5f) / 32.0f, (t + 0.5f) / 32.0f, (f + 1.0f) / 6.0f);
    const FloatImage img = renderSphere(pbr(glm::vec3(1.0f), 1.0f, 0.0f),
                                        EnvironmentLightNode::create(Environment::fromCube(cube)));
    int checked = 0;
    std::set<int> faces;
    for (int y = 4; y < kSize; y += 7)
        for (int x = 4; x < kSize; x += 7) {
            const double wx = (x + 0.5) / kSize * 2.0 * kHalf - kHalf;
            const double wy = kHalf - (y + 0.5) / kSize * 2.0 * kHalf; // rows run top to bottom
            const double r2 = wx * wx + wy * wy;
            if (r2 > 0.85 * 0.85) continue; // the rim: tessellation bends the normal most
            const glm::dvec3 n(wx, wy, std::sqrt(1.0 - r2));
            const glm::dvec3 r = 2.0 * n.z * n - glm::dvec3(0, 0, 1);
            const env::CubeCoord c = env::cubeCoord(glm::vec3(r));
            if (std::min({c.st.x, c.st.y, 1.0f - c.st.x, 1.0f - c.st.y}) < 0.15f) continue; // near an edge
            // F0 = 1 makes F = 1, and at roughness 0.045 (the clamp) Smith's masking is 1 to 1e-3
            // away from the rim: the albedo is 1 (a midpoint rule cannot resolve so narrow a lobe).
            const double albedo = 1.0;
            const glm::vec3 p = pixel(img, x, y);
            const glm::vec3 texel(c.st.x, c.st.y, (c.face + 1.0f) / 6.0f);
            for (int ch = 0; ch < 3; ++ch)
                EXPECT_NEAR(p[ch], texel[ch] * albedo, 0.04)
                    << "pixel " << x << "," << y << " reflects face " << c.face << " channel " << ch;
            faces.insert(c.face);
            ++checked;
        }
    EXPECT_GT(checked, 40);
    EXPECT_GE(faces.size(), 4u) << "the mirror directions must reach most faces";
}

TEST(Environment, OcclusionMapsAndIntensityScaleTheEnvironment) {
    auto m = Material::create();
    m->diffuse = {0.8f, 0.8f, 0.8f, 1.0f};
    auto occ = Image::create(1, 1, 3);
    occ->pixels = {102, 102, 102}; // 0.4
    m->occlusionTexture = Texture::create(occ, false);
    m->occlusionStrength = 1.0f;
    auto ball = shapes::sphere(kRadius, 96, 48);
    ASSERT_FALSE(ball->texcoords.empty());
    const FloatImage img =
        renderSphere(m, EnvironmentLightNode::create(Environment::uniform(glm::vec3(1.0f)), 1.5f));
    const glm::vec3 p = pixel(img, kSize / 2, kSize / 2);
    EXPECT_NEAR(p.r, 0.8 * 1.5 * (102.0 / 255.0), 0.005);
}

TEST(Environment, FilesLoadAndBadOnesNameTheFileAndTheReason) {
    const std::filesystem::path dir = std::filesystem::temp_directory_path() / "sgfx_environment_test";
    std::filesystem::create_directories(dir);
    // A 2:1 Radiance file of uniform radiance 0.75.
    std::vector<float> hdr(16 * 8 * 3, 0.75f);
    ASSERT_TRUE(stbi_write_hdr((dir / "uniform.hdr").c_str(), 16, 8, 3, hdr.data()));
    const auto e = Environment::load(dir / "uniform.hdr", 16);
    EXPECT_NEAR(env::evalSh(e->irradiance(), glm::vec3(0, 0, 1)).r, 0.75f, 0.01f);
    EXPECT_NEAR(e->radiance().texel(3, 5, 5).g, 0.75f, 0.01f);
    // A square image is neither a panorama nor a strip.
    ASSERT_TRUE(stbi_write_hdr((dir / "square.hdr").c_str(), 8, 8, 3, hdr.data()));
    try {
        (void)Environment::load(dir / "square.hdr");
        ADD_FAILURE() << "a square image loaded";
    } catch (const std::runtime_error& err) {
        EXPECT_NE(std::string(err.what()).find("square.hdr"), std::string::npos) << err.what();
        EXPECT_NE(std::string(err.what()).find("2:1"), std::string::npos) << err.what();
    }
    try {
        (void)Environment::load(dir / "missing.hdr");
        ADD_FAILURE() << "a missing file loaded";
    } catch (const std::runtime_error& err) {
        EXPECT_NE(std::string(err.what()).find("missing.hdr"), std::string::npos) << err.what();
    }
    // Negative radiance is refused naming the face and texel.
    env::CubeImage bad = env::CubeImage::filled(8, glm::vec3(1.0f));
    bad.texel(4, 2, 3) = glm::vec3(-1.0f);
    try {
        (void)Environment::fromCube(bad);
        ADD_FAILURE() << "negative radiance accepted";
    } catch (const std::invalid_argument& err) {
        EXPECT_NE(std::string(err.what()).find("face 4 texel (2, 3)"), std::string::npos) << err.what();
    }
    EXPECT_THROW(EnvironmentLightNode::create(std::shared_ptr<const Environment>()), std::invalid_argument);
    EXPECT_THROW(EnvironmentLightNode::create(std::shared_ptr<const SkyNode>()), std::invalid_argument);
    auto node = EnvironmentLightNode::create(Environment::uniform(glm::vec3(1.0f)), 2.0f);
    EXPECT_THROW(node->setIntensity(-1.0f), std::invalid_argument);
    EXPECT_EQ(node->intensity(), 2.0f);
    std::filesystem::remove_all(dir);
}

TEST(Environment, SkyEnvironmentMatchesSkyMathInEveryFaceDirectionAndFollowsTheSun) {
    SkyParameters p = SkyParameters::atTime(16.0f);
    auto sky = SkyNode::create(p);
    auto node = EnvironmentLightNode::create(sky);
    node->addChild(shapes::sphere(1.0f));
    auto v = test::orthoTopViewer(16, 2.0f);
    v->setSceneData(node);
    auto check = [&](const SkyParameters& now, const char* when) {
        v->frame();
        test::expectNoGlErrors(*v);
        const auto e = node->environment();
        ASSERT_TRUE(e) << when;
        const env::CubeImage& c = e->radiance();
        ASSERT_EQ(c.size, 32);
        int checked = 0;
        for (int f = 0; f < 6; ++f)
            for (int t = 2; t < 32; t += 9)
                for (int s = 2; s < 32; s += 9) {
                    const glm::vec3 d = glm::normalize(
                        env::cubeDirection(f, glm::vec2((s + 0.5f) / 32.0f, (t + 0.5f) / 32.0f)));
                    const glm::vec3 expected =
                        sky::skyRadiance(now.atmosphere, d, now.sunDirection, now.sunIntensity, now.altitude,
                                         now.steps, now.lightSteps);
                    for (int ch = 0; ch < 3; ++ch)
                        EXPECT_NEAR(c.texel(f, s, t)[ch], expected[ch], 0.01f * expected[ch] + 1e-4f)
                            << when << ": face " << f << " texel " << s << "," << t << " channel " << ch;
                    ++checked;
                }
        EXPECT_EQ(checked, 96);
    };
    check(p, "afternoon");
    const auto before = node->environment();
    p.sunDirection = sky::sunDirection(9.0f, 45.0f, 172);
    sky->setParameters(p);
    check(sky->parameters(), "morning");
    EXPECT_NE(node->environment(), before) << "the sun moved but the environment was not rendered again";
    v->frame();
    const auto same = node->environment();
    v->frame();
    EXPECT_EQ(node->environment(), same) << "the sun stood still but the environment was rendered again";
}

TEST(Environment, ClearcoatDarkensTheBaseAndMirrorsTheEnvironment) {
    // Under a uniform environment of radiance 1 a coat of factor 1 (F0 = 0.04, Schlick at the
    // coat's N.V) takes its Fresnel share of the base's light and reflects that share of the
    // environment through its own lobe, whose albedo without Fresnel is a1(N.V, coat roughness):
    // total = (1 − Fc)·E_base + Fc·a1. A smooth coat has a1 = 1 (F = 1, no masking).
    const auto white = Environment::uniform(glm::vec3(1.0f));
    for (float coatRoughness : {0.0f, 0.7f}) {
        auto m = pbr(glm::vec3(0.0f), 0.0f, 0.5f); // black dielectric: E_base is the lobe's albedo
        m->clearcoat = 1.0f;
        m->clearcoatRoughness = coatRoughness;
        const FloatImage coated = renderSphere(m, EnvironmentLightNode::create(white));
        for (double NdotV : {0.98, 0.6}) {
            const auto [x, n] = pixelAtNdotV(NdotV);
            const double nv = n.z;
            const double fc = 0.04 + 0.96 * std::pow(1.0 - nv, 5.0);
            const double base = directionalAlbedo(nv, 0.04, 0.5, 1200, 1200);
            const double a1 =
                coatRoughness > 0.0f ? directionalAlbedo(nv, 1.0, coatRoughness, 1200, 1200) : 1.0;
            const double expected = (1.0 - fc) * base + fc * a1;
            EXPECT_NEAR(pixel(coated, x, kSize / 2).g, expected, 0.02 * expected + 0.003)
                << "coat roughness " << coatRoughness << " N.V " << nv;
            // Without the coat's own reflection the pixel would be (1 − Fc)·E_base: the test sees it.
            EXPECT_GT(std::abs(expected - (1.0 - fc) * base), 0.02);
        }
    }
}

TEST(Environment, ForeignShadersCallTheEnvironment) {
    // An application's shader declares the environment's functions and calls them under
    // SGFX_ENVIRONMENT (docs/effects/environment.md): a uniform radiance of 2 gives irradiance/π = 2.
    static const char* const frag = R"(#version 450 core
layout(location = 0) out vec4 fragOut;
#ifdef SGFX_ENVIRONMENT
vec3 sgfx_environmentDiffuse(vec3 N);
vec3 sgfx_environmentRadiance(vec3 R, float roughness);
#endif
void main() {
#ifdef SGFX_ENVIRONMENT
    fragOut = vec4(0.25 * sgfx_environmentDiffuse(vec3(0.0, 0.0, 1.0)).rg,
                   0.125 * sgfx_environmentRadiance(vec3(1.0, 0.0, 0.0), 0.5).g, 1.0);
#else
    fragOut = vec4(1.0, 0.0, 1.0, 1.0);
#endif
}
)";
    auto v = test::orthoTopViewer(16, 1.0f);
    v->renderer().options().colorTarget = RendererOptions::ColorTarget::Rgba32F;
    auto q = shapes::quad(2.0f, 2.0f);
    q->getOrCreateStateSet().program.set(ShaderProgram::create("app_env", test::kForeignVert, frag));
    auto env = EnvironmentLightNode::create(Environment::uniform(glm::vec3(2.0f)));
    env->addChild(q);
    v->setSceneData(env);
    v->frame();
    test::expectNoGlErrors(*v);
    const glm::vec3 p = pixel(v->renderer().readPixelsLinear(), 8, 8);
    EXPECT_NEAR(p.r, 0.5f, 0.005f);
    EXPECT_NEAR(p.g, 0.5f, 0.005f);
    EXPECT_NEAR(p.b, 0.25f, 0.005f);
}

// Transparent stage and TransparencyBin: queue order without GL, then OSMesa renders (≤ 96×96)
// against the over operator, the weighted blended formula (McGuire & Bavoil 2013, eq. 6) and
// the blend equations, computed here from the same inputs.
#include "TestUtil.h"

#include <sgfx/CullVisitor.h>
#include <sgfx/Geometry.h>
#include <sgfx/Group.h>
#include <sgfx/ShaderComposer.h>
#include <sgfx/Shapes.h>
#include <sgfx/TriangleSort.h>
#include <sgfx/nodes/transparency/OitMath.h>
#include <sgfx/nodes/transparency/TransparencyBin.h>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <numeric>

using namespace sgfx;
using namespace sgfx::test;

namespace {

constexpr int kSize = 64;
constexpr float kHalf = 2.0f;
const glm::dvec3 kBackground(0.2, 0.2, 0.2);

// A w×w pane at `pos`, facing +Z, emissive colour, blended (double-sided unless told otherwise).
std::shared_ptr<Transform> pane(glm::vec3 pos, glm::vec3 color, float alpha, float w = 2.0f,
                                BlendMode blend = BlendMode::Alpha, CullFace cull = CullFace::None) {
    auto t = Transform::create(glm::translate(glm::mat4(1.0f), pos));
    auto q = shapes::quad(w, w);
    q->name = "pane";
    auto& ss = q->getOrCreateStateSet();
    ss.material.set(flatMaterial(color, alpha));
    ss.blend.set(blend);
    ss.cullFace.set(cull);
    t->addChild(q);
    return t;
}

const Geometry* geometryOf(const Node& n) {
    return dynamic_cast<const Geometry*>(static_cast<const Group&>(n).children()[0].get());
}

std::unique_ptr<Viewer> topViewer(bool fromBelow = false) {
    auto v = orthoTopViewer(kSize, kHalf);
    v->camera()->clearColor = glm::vec4(glm::vec3(kBackground), 1.0f);
    if (fromBelow) v->camera()->setLookAt({0, 0, -10}, {0, 0, 0}, {0, 1, 0});
    return v;
}

Image render(Viewer& v, std::shared_ptr<Node> scene) {
    v.setSceneData(std::move(scene));
    v.frame();
    for (const auto& e : v.renderer().takeGlErrors())
        ADD_FAILURE() << "GL: " << e;
    return v.capture();
}

glm::dvec3 over(glm::dvec3 src, double alpha, glm::dvec3 dst) {
    return src * alpha + dst * (1.0 - alpha);
}

int channelError(const Image& img, int x, int y, glm::dvec3 expected) {
    const glm::ivec4 p = pixelAt(img, x, y);
    int e = 0;
    for (int c = 0; c < 3; ++c)
        e = std::max(e, std::abs(p[c] - srgbByte(expected[c])));
    return e;
}

// The queue a camera builds for a scene, sorted.
RenderQueue cullAndSort(Camera& cam, const std::shared_ptr<Node>& scene) {
    cam.removeChildren();
    cam.addChild(scene);
    RenderQueue q;
    CullVisitor cv(cam, q);
    cv.run(cam);
    q.sort();
    cam.removeChildren();
    return q;
}

std::shared_ptr<Camera> lookingDown(glm::vec3 eye = {0, 0, 10}) {
    auto cam = Camera::create();
    cam->setViewport(0, 0, 64, 64);
    cam->setPerspective(60.0f, 0.1f, 100.0f);
    cam->setLookAt(eye, {0, 0, 0}, {0, 1, 0});
    return cam;
}

// Three panes at heights 1, 2, 3 (red, green, blue) overlapping at the centre.
struct ThreePanes {
    std::array<glm::vec3, 3> pos{glm::vec3(-0.4f, 0, 1), glm::vec3(0, 0, 2), glm::vec3(0.4f, 0, 3)};
    std::array<glm::vec3, 3> color{glm::vec3(0.9f, 0.1f, 0.1f), glm::vec3(0.1f, 0.8f, 0.2f),
                                   glm::vec3(0.1f, 0.2f, 0.9f)};
    std::array<float, 3> alpha{0.5f, 0.4f, 0.6f};
    std::shared_ptr<Transform> make(int i) const { return pane(pos[i], color[i], alpha[i]); }
};

} // namespace

// ------------------------------------------------------------------------------------ queue order

TEST(TransparentOrder, BackToFrontAndFlipsWithTheCamera) {
    auto root = Group::create();
    for (float z : {2.0f, -3.0f, 5.0f, 0.0f})
        root->addChild(pane({0, 0, z}, glm::vec3(1), 0.5f, 1.0f, BlendMode::Alpha, CullFace::Back));
    auto heightOf = [](const RenderItem& it) { return it.model[3][2]; };
    {
        auto cam = lookingDown({0, 0, 20});
        const RenderQueue q = cullAndSort(*cam, root);
        ASSERT_EQ(q.transparent.size(), 4u);
        EXPECT_TRUE(q.opaque.empty());
        std::vector<float> h;
        for (const RenderItem& it : q.transparent)
            h.push_back(heightOf(it));
        EXPECT_EQ(h, (std::vector<float>{-3, 0, 2, 5})) << "far (low) first when looking down";
    }
    {
        auto cam = lookingDown({0, 0, -20});
        const RenderQueue q = cullAndSort(*cam, root);
        std::vector<float> h;
        for (const RenderItem& it : q.transparent)
            h.push_back(heightOf(it));
        EXPECT_EQ(h, (std::vector<float>{5, 2, 0, -3})) << "the other side: the order flips";
    }
}

TEST(TransparentOrder, TiesKeepCullOrderEveryFrame) {
    auto root = Group::create();
    std::vector<const Geometry*> added;
    for (int i = 0; i < 6; ++i) {
        auto p = pane({float(i % 3) - 1.0f, float(i / 3), 0}, glm::vec3(1), 0.5f, 0.5f, BlendMode::Alpha,
                      CullFace::Back);
        root->addChild(p);
        added.push_back(geometryOf(*p));
    }
    // An orthographic camera: every pane has the same view depth.
    auto cam = lookingDown();
    cam->projectionMatrix = glm::ortho(-5.f, 5.f, -5.f, 5.f, 0.1f, 100.f);
    for (int frame = 0; frame < 3; ++frame) {
        const RenderQueue q = cullAndSort(*cam, root);
        ASSERT_EQ(q.transparent.size(), added.size());
        for (std::size_t i = 0; i < added.size(); ++i)
            EXPECT_EQ(q.transparent[i].geometry, added[i]) << "frame " << frame << " item " << i;
    }
}

TEST(TransparentOrder, ExplicitOrderAndDepthBiasWin) {
    auto root = Group::create();
    auto nearPane = pane({0, 0, 5}, glm::vec3(1), 0.5f, 1.0f, BlendMode::Alpha, CullFace::Back);
    auto farPane = pane({0, 0, 0}, glm::vec3(1), 0.5f, 1.0f, BlendMode::Alpha, CullFace::Back);
    root->addChild(nearPane);
    root->addChild(farPane);
    auto cam = lookingDown({0, 0, 20});
    EXPECT_EQ(cullAndSort(*cam, root).transparent[0].geometry, geometryOf(*farPane));

    // A bias of +6 m makes the near pane sort as if 1 m beyond the far one.
    TransparencyDetails bias;
    bias.depthBias = 6.0f;
    nearPane->getOrCreateStateSet().transparency.set(bias);
    EXPECT_EQ(cullAndSort(*cam, root).transparent[0].geometry, geometryOf(*nearPane));
    bias.depthBias = 4.0f; // not enough
    nearPane->getOrCreateStateSet().transparency.set(bias);
    EXPECT_EQ(cullAndSort(*cam, root).transparent[0].geometry, geometryOf(*farPane));

    // An explicit order beats any depth: the far pane with order 1 is drawn last.
    nearPane->getOrCreateStateSet().transparency.clear();
    TransparencyDetails late;
    late.order = 1;
    farPane->getOrCreateStateSet().transparency.set(late);
    const RenderQueue q = cullAndSort(*cam, root);
    EXPECT_EQ(q.transparent[0].geometry, geometryOf(*nearPane));
    EXPECT_EQ(q.transparent[1].geometry, geometryOf(*farPane));
}

TEST(TransparentOrder, DoubleSidedItemsAreQueuedBackFacesFirst) {
    auto root = Group::create();
    root->addChild(pane({0, 0, 0}, glm::vec3(1), 0.5f)); // CullFace::None
    auto cam = lookingDown();
    RenderQueue q = cullAndSort(*cam, root);
    ASSERT_EQ(q.transparent.size(), 2u);
    EXPECT_EQ(q.transparent[0].faces, RenderItem::Faces::Back);
    EXPECT_EQ(q.transparent[1].faces, RenderItem::Faces::Front);

    TransparencyDetails one;
    one.twoPass = false;
    root->getOrCreateStateSet().transparency.set(one);
    q = cullAndSort(*cam, root);
    ASSERT_EQ(q.transparent.size(), 1u);
    EXPECT_EQ(q.transparent[0].faces, RenderItem::Faces::AsState);
}

TEST(TransparentOrder, WeightedBlendedBinClaimsAlphaItemsOnly) {
    auto bin = TransparencyBin::create(TransparencyMode::WeightedBlended);
    bin->addChild(pane({0, 0, 0}, glm::vec3(1), 0.5f));
    bin->addChild(pane({0, 0, 1}, glm::vec3(1), 0.5f, 1.0f, BlendMode::Premultiplied));
    bin->addChild(pane({0, 0, 2}, glm::vec3(1), 0.5f, 1.0f, BlendMode::Additive, CullFace::Back));
    auto plain = Transform::create();
    plain->addChild(shapes::quad(1, 1)); // no blend, but under the bin: in it (straight alpha)
    bin->addChild(plain);
    auto cam = lookingDown();
    RenderQueue q = cullAndSort(*cam, bin);
    EXPECT_EQ(q.claimed.size(), 3u);
    ASSERT_EQ(q.transparent.size(), 1u) << "additive blending commutes: it stays sorted";
    EXPECT_TRUE(q.opaque.empty());

    bin->setMode(TransparencyMode::Sorted);
    q = cullAndSort(*cam, bin);
    EXPECT_TRUE(q.claimed.empty());
    EXPECT_EQ(q.transparent.size(), 6u); // two double-sided panes twice, two single-sided
}

TEST(TransparentOrder, BadDetailsAndParametersAreRefused) {
    auto root = Group::create();
    auto p = pane({0, 0, 0}, glm::vec3(1), 0.5f);
    root->addChild(p);
    TransparencyDetails d;
    d.depthBias = std::numeric_limits<float>::quiet_NaN();
    p->getOrCreateStateSet().transparency.set(d);
    auto cam = lookingDown();
    try {
        cullAndSort(*cam, root);
        ADD_FAILURE() << "a NaN depth bias must be refused";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("depthBias"), std::string::npos) << e.what();
    }
    d = {};
    d.resortAngle = 200.0f;
    EXPECT_THROW(d.validate(), std::invalid_argument);
    auto bin = TransparencyBin::create();
    EXPECT_THROW(bin->setDetails(d), std::invalid_argument);
    EXPECT_THROW(bin->setMode(TransparencyMode(7)), std::invalid_argument);
    OitParameters o;
    o.depthScale = 0.0f;
    EXPECT_THROW(bin->setOitParameters(o), std::invalid_argument);
    o = {};
    o.weight = OitWeight(9);
    EXPECT_THROW(bin->setOitParameters(o), std::invalid_argument);
    EXPECT_EQ(bin->oitParameters().weight, OitWeight::Depth7) << "a refused value keeps the old one";
}

// --------------------------------------------------------------------------------- triangle sort

TEST(TriangleSort, MatchesABruteForceSortAndResortsOnlyPastTheThreshold) {
    auto g = shapes::sphere(1.0f, 24, 12);
    TriangleDepthSort sort(*g);
    ASSERT_EQ(sort.triangleCount(), g->triangleCount());
    const glm::mat4 view = glm::lookAt(glm::vec3(3, -2, 4), glm::vec3(0), glm::vec3(0, 0, 1));
    EXPECT_TRUE(sort.update(view, 5.0f));
    const auto idx = sort.indices();
    ASSERT_EQ(idx.size(), g->indices.size());
    float last = -1e30f;
    for (std::size_t t = 0; t < idx.size(); t += 3) {
        const glm::vec3 c =
            (g->positions[idx[t]] + g->positions[idx[t + 1]] + g->positions[idx[t + 2]]) / 3.0f;
        const float z = (view * glm::vec4(c, 1.0f)).z;
        EXPECT_GE(z, last - 1e-5f) << "triangle " << t / 3 << " is nearer than the one after it";
        last = z;
    }
    // Same triangles, each once.
    std::vector<std::uint32_t> a(idx.begin(), idx.end()), b = g->indices;
    std::sort(a.begin(), a.end());
    std::sort(b.begin(), b.end());
    EXPECT_EQ(a, b);

    const glm::mat4 turned3 = view * glm::rotate(glm::mat4(1.0f), glm::radians(3.0f), glm::vec3(0, 0, 1));
    EXPECT_FALSE(sort.update(turned3, 5.0f)) << "3 degrees is under the threshold";
    const glm::mat4 turned8 = view * glm::rotate(glm::mat4(1.0f), glm::radians(8.0f), glm::vec3(0, 0, 1));
    EXPECT_TRUE(sort.update(turned8, 5.0f));
    EXPECT_TRUE(sort.update(turned8 * glm::translate(glm::mat4(1.0f), glm::vec3(0.01f)), 0.0f))
        << "threshold 0: every call re-sorts";
    EXPECT_EQ(sort.sorts(), 3u);
}

TEST(TriangleSort, StripsAndFansAreUnrolled) {
    auto strip = Geometry::create();
    strip->mode = PrimitiveMode::TriangleStrip;
    for (int i = 0; i < 6; ++i)
        strip->positions.push_back({float(i / 2), float(i % 2), float(i)});
    TriangleDepthSort s(*strip);
    EXPECT_EQ(s.triangleCount(), 4u);
    auto fan = Geometry::create();
    fan->mode = PrimitiveMode::TriangleFan;
    fan->positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {-1, 1, 0}};
    EXPECT_EQ(TriangleDepthSort(*fan).triangleCount(), 3u);
    auto lines = Geometry::create();
    lines->mode = PrimitiveMode::Lines;
    lines->positions = {{0, 0, 0}, {1, 0, 0}};
    TriangleDepthSort l(*lines);
    EXPECT_EQ(l.triangleCount(), 0u);
    EXPECT_FALSE(l.update(glm::mat4(1.0f), 5.0f));
}

// ----------------------------------------------------------------------------------- render: sorted

TEST(TransparentRender, ThreePanesEqualTheOverOperatorFromBothSides) {
    const ThreePanes panes;
    for (bool fromBelow : {false, true}) {
        auto root = Group::create();
        for (int i = 0; i < 3; ++i)
            root->addChild(panes.make(i));
        auto v = topViewer(fromBelow);
        const Image img = render(*v, root);
        glm::dvec3 expected = kBackground;
        for (int k = 0; k < 3; ++k) {
            const int i = fromBelow ? 2 - k : k; // far to near
            expected = over(glm::dvec3(panes.color[i]), panes.alpha[i], expected);
        }
        const int e = channelError(img, kSize / 2, kSize / 2, expected);
        EXPECT_LE(e, 2) << (fromBelow ? "from below" : "from above");
        std::printf("three panes from %s: error %d/255\n", fromBelow ? "below" : "above", e);
    }
}

TEST(TransparentRender, EveryInsertionOrderGivesTheSameImage) {
    const ThreePanes panes;
    std::array<int, 3> perm{0, 1, 2};
    Image first;
    int n = 0;
    do {
        auto root = Group::create();
        for (int i : perm)
            root->addChild(panes.make(i));
        auto v = topViewer();
        const Image img = render(*v, root);
        if (n++ == 0)
            first = img;
        else
            EXPECT_EQ(channelsDiffering(first, img, 0), 0) << "permutation " << perm[0] << perm[1] << perm[2];
    } while (std::next_permutation(perm.begin(), perm.end()));
    EXPECT_EQ(n, 6);
}

TEST(TransparentRender, BlendModesFollowTheirEquations) {
    // Lit by a directional light straight down the view: at the centre N = L = V = H.
    const glm::dvec3 diffuse(0.4, 0.3, 0.2), specular(0.3, 0.3, 0.3), emissive(0.05, 0.0, 0.0);
    const double a = 0.5;
    const glm::dvec3 bg(0.3, 0.4, 0.5);
    const glm::dvec3 scattered = diffuse, added = emissive + specular;
    for (BlendMode mode :
         {BlendMode::Alpha, BlendMode::Premultiplied, BlendMode::Additive, BlendMode::Multiply}) {
        auto root = Group::create();
        auto light = Light::create(LightType::Directional);
        light->direction = {0, 0, -1};
        root->addChild(light);
        auto q = shapes::quad(3, 3);
        auto m = Material::create();
        m->ambient = glm::vec3(0);
        m->diffuse = glm::vec4(glm::vec3(diffuse), float(a));
        m->specular = glm::vec3(specular);
        m->shininess = 10.0f;
        m->emissive = glm::vec3(emissive);
        q->getOrCreateStateSet().material.set(m);
        q->getOrCreateStateSet().blend.set(mode);
        root->addChild(q);
        auto v = topViewer();
        v->camera()->clearColor = glm::vec4(glm::vec3(bg), 1.0f);
        const Image img = render(*v, root);
        const glm::dvec3 straight = scattered + added;
        glm::dvec3 expected;
        switch (mode) {
        case BlendMode::Alpha:
            expected = straight * a + bg * (1 - a);
            break;
        case BlendMode::Premultiplied: // highlights and emission are not scaled by coverage
            expected = scattered * a + added + bg * (1 - a);
            break;
        case BlendMode::Additive:
            expected = bg + straight * a;
            break;
        default:
            expected = bg * straight;
            break;
        }
        const int e = channelError(img, kSize / 2, kSize / 2, expected);
        EXPECT_LE(e, 2) << "blend mode " << int(mode);
    }
}

TEST(TransparentRender, ClosedDoubleSidedObjectBlendsItsFarSideFirst) {
    // One mesh: a red top (facing up) listed before a green bottom (facing down), both α = 0.5.
    auto g = Geometry::create();
    g->positions = {{-1, -1, 1}, {1, -1, 1}, {1, 1, 1}, {-1, 1, 1},
                    {-1, -1, 0}, {-1, 1, 0}, {1, 1, 0}, {1, -1, 0}};
    g->indices = {0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7};
    g->colors.assign(4, glm::vec4(0.9f, 0.1f, 0.1f, 0.5f));
    g->colors.resize(8, glm::vec4(0.1f, 0.8f, 0.2f, 0.5f));
    auto m = Material::create();
    m->ambient = glm::vec3(1);
    m->diffuse = glm::vec4(0, 0, 0, 1);
    auto& ss = g->getOrCreateStateSet();
    ss.material.set(m);
    ss.blend.set(BlendMode::Alpha);
    ss.cullFace.set(CullFace::None);
    const glm::dvec3 red(0.9, 0.1, 0.1), green(0.1, 0.8, 0.2);
    const glm::dvec3 right = over(red, 0.5, over(green, 0.5, kBackground));
    for (bool twoPass : {true, false}) {
        TransparencyDetails d;
        d.twoPass = twoPass;
        ss.transparency.set(d);
        auto root = Group::create();
        auto ambient = Light::create(LightType::Ambient);
        root->addChild(ambient);
        root->addChild(g);
        auto v = topViewer();
        const Image img = render(*v, root);
        const int e = channelError(img, kSize / 2, kSize / 2, right);
        if (twoPass)
            EXPECT_LE(e, 2) << "back faces first, then front faces";
        else
            EXPECT_GT(e, 20) << "in index order the near face is blended first";
    }
}

TEST(TransparentRender, DepthWritingGlassHidesWhatIsDrawnAfterIt) {
    for (bool writeDepth : {false, true}) {
        auto root = Group::create();
        auto nearPane = pane({0, 0, 3}, {0.1f, 0.2f, 0.9f}, 0.5f);
        TransparencyDetails d;
        d.order = -1; // drawn first although nearer
        d.writeDepth = writeDepth;
        nearPane->getOrCreateStateSet().transparency.set(d);
        root->addChild(nearPane);
        root->addChild(pane({0, 0, 1}, {0.9f, 0.1f, 0.1f}, 0.5f));
        auto v = topViewer();
        const Image img = render(*v, root);
        const glm::dvec3 nearOverBg = over({0.1, 0.2, 0.9}, 0.5, kBackground);
        const glm::dvec3 expected = writeDepth ? nearOverBg : over({0.9, 0.1, 0.1}, 0.5, nearOverBg);
        EXPECT_LE(channelError(img, kSize / 2, kSize / 2, expected), 2) << "writeDepth " << writeDepth;
    }
}

TEST(TransparentRender, AlphaModesBuiltInCode) {
    // glTF's three alpha modes as a loader maps them: BLEND into the bin, MASK opaque with a
    // cutoff, OPAQUE opaque whatever the alpha.
    auto root = Group::create();
    auto blend = pane({-1.2f, 1.0f, 0}, {0.9f, 0.1f, 0.1f}, 0.5f, 1.4f);

    auto alphaImage = Image::create(2, 1, 1);
    alphaImage->pixels = {64, 192}; // 0.25 | 0.75
    auto alphaTex = Texture::create(alphaImage, false);
    alphaTex->minFilter = alphaTex->magFilter = Filter::Nearest;
    auto maskMat = flatMaterial({0.1f, 0.8f, 0.2f}, 1.0f);
    maskMat->alphaTexture = alphaTex;
    maskMat->alphaCutoff = 0.5f;
    auto mask = Transform::create(glm::translate(glm::mat4(1.0f), {1.0f, 1.0f, 0}));
    auto maskQuad = shapes::quad(1.6f, 1.4f);
    maskQuad->getOrCreateStateSet().material.set(maskMat);
    mask->addChild(maskQuad);

    auto opaque = Transform::create(glm::translate(glm::mat4(1.0f), {0, -1.0f, 0}));
    auto opaqueQuad = shapes::quad(1.4f, 1.4f);
    opaqueQuad->getOrCreateStateSet().material.set(flatMaterial({0.1f, 0.2f, 0.9f}, 0.3f));
    opaque->addChild(opaqueQuad);
    for (auto n : {std::static_pointer_cast<Node>(blend), std::static_pointer_cast<Node>(mask),
                   std::static_pointer_cast<Node>(opaque)})
        root->addChild(n);

    auto cam = lookingDown();
    const RenderQueue q = cullAndSort(*cam, root);
    EXPECT_EQ(q.transparent.size(), 2u); // the blended pane, twice (double-sided)
    EXPECT_EQ(q.opaque.size(), 2u);

    auto v = topViewer();
    const Image img = render(*v, root);
    auto px = [](float x, float y) {
        return glm::ivec2(int((x + kHalf) / (2 * kHalf) * kSize), int((kHalf - y) / (2 * kHalf) * kSize));
    };
    glm::ivec2 p = px(-1.2f, 1.0f);
    EXPECT_LE(channelError(img, p.x, p.y, over({0.9, 0.1, 0.1}, 0.5, kBackground)), 2) << "BLEND";
    p = px(0.6f, 1.0f); // alpha 0.25 < cutoff: cut away
    EXPECT_LE(channelError(img, p.x, p.y, kBackground), 1) << "MASK below its cutoff";
    p = px(1.4f, 1.0f); // alpha 0.75: opaque
    EXPECT_LE(channelError(img, p.x, p.y, {0.1, 0.8, 0.2}), 1) << "MASK above its cutoff";
    p = px(0.0f, -1.0f);
    EXPECT_LE(channelError(img, p.x, p.y, {0.1, 0.2, 0.9}), 1) << "OPAQUE ignores alpha";
}

namespace {
// Four overlapping horizontal quads at heights 0, 1, 2, 3, each with its own vertex colour
// and α = 0.5; listed top first. As one mesh, or as four items.
std::shared_ptr<Node> stackedQuads(bool oneMesh, bool sortTriangles) {
    const glm::vec4 colors[4] = {{0.9f, 0.1f, 0.1f, 0.5f},
                                 {0.1f, 0.8f, 0.2f, 0.5f},
                                 {0.1f, 0.2f, 0.9f, 0.5f},
                                 {0.9f, 0.8f, 0.1f, 0.5f}};
    auto m = Material::create();
    m->ambient = glm::vec3(1);
    m->diffuse = glm::vec4(0, 0, 0, 1);
    auto root = Group::create();
    root->addChild(Light::create(LightType::Ambient));
    auto state = StateSet::create();
    state->material.set(m);
    state->blend.set(BlendMode::Alpha);
    state->cullFace.set(CullFace::None);
    TransparencyDetails d;
    d.sortTriangles = sortTriangles;
    state->transparency.set(d);
    std::shared_ptr<Geometry> mesh;
    for (int level = 3; level >= 0; --level) {
        if (!mesh || !oneMesh) {
            mesh = Geometry::create();
            mesh->setStateSet(state);
            root->addChild(mesh);
        }
        const float z = float(level), x = 0.3f * float(level) - 0.45f;
        const auto base = std::uint32_t(mesh->positions.size());
        for (glm::vec2 c : {glm::vec2(-1, -1), glm::vec2(1, -1), glm::vec2(1, 1), glm::vec2(-1, 1)}) {
            mesh->positions.push_back({x + 0.8f * c.x, 0.8f * c.y, z});
            mesh->colors.push_back(colors[level]);
        }
        for (std::uint32_t i : {0u, 1u, 2u, 0u, 2u, 3u})
            mesh->indices.push_back(base + i);
    }
    return root;
}

std::unique_ptr<Viewer> obliqueViewer(float eyeZ) {
    auto v = Viewer::createHeadless(96, 96);
    v->camera()->setPerspective(50.0f, 0.1f, 100.0f);
    v->camera()->setLookAt({2.5f, -4.0f, eyeZ}, {0, 0, 1.5f}, {0, 0, 1});
    v->camera()->clearColor = glm::vec4(glm::vec3(kBackground), 1.0f);
    return v;
}
} // namespace

TEST(TransparentRender, PerTriangleSortEqualsSeparatelySortedItems) {
    for (float eyeZ : {7.0f, -5.0f}) {
        auto split = obliqueViewer(eyeZ);
        const Image reference = render(*split, stackedQuads(false, false));
        auto sorted = obliqueViewer(eyeZ);
        const Image img = render(*sorted, stackedQuads(true, true));
        EXPECT_EQ(sorted->renderer().stats().triangleSorts, 1u);
        EXPECT_LE(channelsDiffering(reference, img, 1), 0) << "eye height " << eyeZ;
        auto unsorted = obliqueViewer(eyeZ);
        const Image wrong = render(*unsorted, stackedQuads(true, false));
        if (eyeZ > 0) { // listed top first: from above that is near to far
            EXPECT_GT(channelsDiffering(reference, wrong, 8), 100)
                << "without sorting the mesh blends wrongly";
        }
    }
}

TEST(TransparentRender, TrianglesAreResortedWhenTheViewTurns) {
    auto v = obliqueViewer(7.0f);
    v->setSceneData(stackedQuads(true, true));
    v->frame();
    EXPECT_EQ(v->renderer().stats().triangleSorts, 1u);
    v->frame();
    EXPECT_EQ(v->renderer().stats().triangleSorts, 0u) << "same view: the order is kept";
    v->camera()->setLookAt({2.5f, -4.0f, -5.0f}, {0, 0, 1.5f}, {0, 0, 1});
    v->frame();
    EXPECT_EQ(v->renderer().stats().triangleSorts, 1u);
    const Image img = v->capture();
    auto split = obliqueViewer(-5.0f);
    EXPECT_LE(channelsDiffering(render(*split, stackedQuads(false, false)), img, 1), 0);
}

// ------------------------------------------------------------------------- render: weighted blended

namespace {
// Expected eq. 6 pixel for layers at view depths `z` (metres), straight colours.
glm::dvec3 weightedBlended(std::span<const glm::vec3> colors, std::span<const float> alphas,
                           std::span<const double> z, glm::dvec3 bg, int equation = 7) {
    std::vector<oit::Layer> layers;
    for (std::size_t i = 0; i < colors.size(); ++i)
        layers.push_back({colors[i].r, colors[i].g, colors[i].b, alphas[i],
                          oit::weight<double>(equation, alphas[i], z[i], 0.0)});
    const double b[3] = {bg.r, bg.g, bg.b};
    double out[3];
    oit::composite(layers, b, out);
    return {out[0], out[1], out[2]};
}
} // namespace

TEST(WeightedBlendedRender, ThreePanesEqualEquationSixInAnyOrder) {
    const ThreePanes panes;
    const std::array<double, 3> z{9, 8, 7}; // eye at height 10
    const glm::dvec3 expected = weightedBlended(panes.color, panes.alpha, z, kBackground);
    std::array<int, 3> perm{0, 1, 2};
    Image first;
    int n = 0;
    do {
        auto bin = TransparencyBin::create(TransparencyMode::WeightedBlended);
        for (int i : perm)
            bin->addChild(panes.make(i));
        auto v = topViewer();
        const Image img = render(*v, bin);
        const int e = channelError(img, kSize / 2, kSize / 2, expected);
        EXPECT_LE(e, 2) << "permutation " << perm[0] << perm[1] << perm[2];
        if (n++ == 0) {
            first = img;
            std::printf("weighted blended three panes: error %d/255\n", e);
        } else {
            EXPECT_LE(channelsDiffering(first, img, 1), 0);
        }
    } while (std::next_permutation(perm.begin(), perm.end()));
}

TEST(WeightedBlendedRender, InterpenetratingQuadsShowNoSeam) {
    // Two quads crossing along x = 0 (tilted ±20° about Y), seen from above: left of the line
    // one is in front, right of it the other. Sorting whole items gets one side wrong.
    const glm::vec3 red(0.9f, 0.1f, 0.1f), green(0.1f, 0.8f, 0.2f);
    const float a = 0.6f, tilt = glm::radians(20.0f);
    auto make = [&](std::shared_ptr<Group> parent) {
        for (int s : {1, -1}) {
            auto t = Transform::create(glm::rotate(glm::mat4(1.0f), float(s) * tilt, glm::vec3(0, 1, 0)));
            auto q = shapes::quad(3, 3);
            auto& ss = q->getOrCreateStateSet();
            ss.material.set(flatMaterial(s > 0 ? red : green, a));
            ss.blend.set(BlendMode::Alpha);
            ss.cullFace.set(CullFace::None);
            t->addChild(q);
            parent->addChild(t);
        }
    };
    auto sortedRoot = Group::create();
    make(sortedRoot);
    auto bin = TransparencyBin::create(TransparencyMode::WeightedBlended);
    make(bin);
    auto vs = topViewer();
    const Image sorted = render(*vs, sortedRoot);
    auto vo = topViewer();
    const Image oitImg = render(*vo, bin);

    const int row = kSize / 2;
    int worstOit = 0, worstSortedLeft = 0, worstSortedRight = 0, worstJump = 0;
    for (int x = 12; x < kSize - 12; ++x) {
        const double wx = -kHalf + (x + 0.5) * 2 * kHalf / kSize;
        // Heights of the red (+tilt: z = −x·tan) and green (z = +x·tan) quads at this pixel.
        const double zr = -wx * std::tan(double(tilt)), zg = wx * std::tan(double(tilt));
        const std::array<glm::vec3, 2> colors{red, green};
        const std::array<float, 2> alphas{a, a};
        const std::array<double, 2> depth{10 - zr, 10 - zg};
        worstOit = std::max(
            worstOit, channelError(oitImg, x, row, weightedBlended(colors, alphas, depth, kBackground)));
        const glm::dvec3 exact = zr > zg ? over(glm::dvec3(red), a, over(glm::dvec3(green), a, kBackground))
                                         : over(glm::dvec3(green), a, over(glm::dvec3(red), a, kBackground));
        (wx < 0 ? worstSortedLeft : worstSortedRight) =
            std::max(wx < 0 ? worstSortedLeft : worstSortedRight, channelError(sorted, x, row, exact));
        if (x > 12)
            for (int c = 0; c < 3; ++c)
                worstJump = std::max(worstJump,
                                     std::abs(pixelAt(oitImg, x, row)[c] - pixelAt(oitImg, x - 1, row)[c]));
    }
    std::printf("interpenetrating: OIT vs eq. 6 %d/255, largest step between neighbours %d/255; "
                "sorted vs exact left %d, right %d\n",
                worstOit, worstJump, worstSortedLeft, worstSortedRight);
    EXPECT_LE(worstOit, 2);
    EXPECT_LE(worstJump, 3) << "no seam where the quads cross";
    EXPECT_GT(std::max(worstSortedLeft, worstSortedRight), 20) << "sorted items are wrong on one side";
    EXPECT_LE(std::min(worstSortedLeft, worstSortedRight), 2);
}

TEST(WeightedBlendedRender, NearlyOpaqueLayersAreWhereItIsApproximate) {
    // The documented weakness: α near 1 in front should hide what is behind; eq. 6 averages.
    const std::array<glm::vec3, 2> colors{glm::vec3(0.9f, 0.1f, 0.1f), glm::vec3(0.1f, 0.8f, 0.2f)};
    const std::array<float, 2> alphas{0.95f, 0.95f};
    const std::array<double, 2> z{9, 8};
    auto sortedRoot = Group::create();
    auto bin = TransparencyBin::create(TransparencyMode::WeightedBlended);
    for (int i = 0; i < 2; ++i) {
        sortedRoot->addChild(pane({0, 0, 1.0f + float(i)}, colors[i], alphas[i]));
        bin->addChild(pane({0, 0, 1.0f + float(i)}, colors[i], alphas[i]));
    }
    const glm::dvec3 exact =
        over(glm::dvec3(colors[1]), alphas[1], over(glm::dvec3(colors[0]), alphas[0], kBackground));
    auto vs = topViewer();
    auto vo = topViewer();
    const Image s = render(*vs, sortedRoot), o = render(*vo, bin);
    EXPECT_LE(channelError(s, kSize / 2, kSize / 2, exact), 2);
    EXPECT_LE(channelError(o, kSize / 2, kSize / 2, weightedBlended(colors, alphas, z, kBackground)), 2);
    const int oitError = channelError(o, kSize / 2, kSize / 2, exact);
    std::printf("alpha 0.95 over 0.95: weighted blended is %d/255 from the exact composite\n", oitError);
    EXPECT_GT(oitError, 20);
}

TEST(WeightedBlendedRender, EveryWeightFunctionMatchesItsEquation) {
    const ThreePanes panes;
    const std::array<double, 3> z{9, 8, 7};
    for (auto [w, eq] : {std::pair{OitWeight::Constant, 0}, std::pair{OitWeight::Depth7, 7},
                         std::pair{OitWeight::Depth8, 8}, std::pair{OitWeight::Depth9, 9}}) {
        auto bin = TransparencyBin::create(TransparencyMode::WeightedBlended);
        OitParameters p;
        p.weight = w;
        p.depthScale = 0.5f; // z in units of 0.5 m
        bin->setOitParameters(p);
        for (int i = 0; i < 3; ++i)
            bin->addChild(panes.make(i));
        auto v = topViewer();
        const Image img = render(*v, bin);
        const std::array<double, 3> zs{z[0] / 0.5, z[1] / 0.5, z[2] / 0.5};
        EXPECT_LE(channelError(img, kSize / 2, kSize / 2,
                               weightedBlended(panes.color, panes.alpha, zs, kBackground, eq)),
                  2)
            << "equation " << eq;
    }
}

TEST(WeightedBlendedRender, OpaqueGeometryInFrontHidesTheLayers) {
    // The accumulation is depth-tested against the opaque scene: a wall above the panes hides them.
    const ThreePanes panes;
    auto root = Group::create();
    auto bin = TransparencyBin::create(TransparencyMode::WeightedBlended);
    for (int i = 0; i < 3; ++i)
        bin->addChild(panes.make(i));
    root->addChild(bin);
    auto wall = Transform::create(glm::translate(glm::mat4(1.0f), {1.0f, 0, 5}));
    auto wq = shapes::quad(2, 4);
    wq->getOrCreateStateSet().material.set(flatMaterial({0.5f, 0.5f, 0.1f}, 1.0f));
    wall->addChild(wq);
    root->addChild(wall);
    auto v = topViewer();
    const Image img = render(*v, root);
    const int wallX = kSize / 2 + kSize / 8; // x = 0.5, inside the wall, over the panes
    EXPECT_LE(channelError(img, wallX, kSize / 2, {0.5, 0.5, 0.1}), 1);
    const int openX = kSize / 2 - kSize / 8; // x = -0.5: panes 1 and 2 (and 3 reaches -0.6)
    const glm::dvec3 exp =
        weightedBlended(panes.color, panes.alpha, std::array<double, 3>{9, 8, 7}, kBackground);
    EXPECT_LE(channelError(img, openX, kSize / 2, exp), 2);
}

TEST(WeightedBlendedRender, SingleLayersEqualTheOverOperatorInPerspective) {
    // One layer per pixel: eq. 6 reduces to the over operator, so OIT and sorting must agree on
    // every pixel, including a pane that leaves the frame and one far away (the passes are
    // scissored to the layers' screen bounds).
    auto make = [](std::shared_ptr<Group> parent) {
        parent->addChild(pane({-3.0f, 2.0f, 0.0f}, {0.9f, 0.1f, 0.1f}, 0.5f, 6.0f));
        parent->addChild(pane({1.5f, 8.0f, 0.5f}, {0.1f, 0.8f, 0.2f}, 0.7f, 1.0f));
    };
    auto sortedRoot = Group::create();
    make(sortedRoot);
    auto bin = TransparencyBin::create(TransparencyMode::WeightedBlended);
    make(bin);
    auto vs = obliqueViewer(3.0f);
    const Image s = render(*vs, sortedRoot);
    auto vo = obliqueViewer(3.0f);
    const Image o = render(*vo, bin);
    EXPECT_LE(channelsDiffering(s, o, 2), 0);
    auto ve = obliqueViewer(3.0f);
    EXPECT_GT(channelsDiffering(s, render(*ve, Group::create()), 8), 1000) << "the panes are in view";
}

TEST(WeightedBlendedRender, ForeignShadersAccumulateThroughTheWrap) {
    // The application's own program, blended in a weighted blended bin: the composer's wrap adds
    // the second output. One layer, so the result is the over operator.
    static const char* frag = R"(#version 450 core
uniform vec4 appColor;
out vec4 fragOut;
void main() { fragOut = appColor; }
)";
    auto program = ShaderProgram::create("app_glass", kForeignVert, frag);
    auto bin = TransparencyBin::create(TransparencyMode::WeightedBlended);
    auto q = shapes::quad(2, 2);
    auto& ss = q->getOrCreateStateSet();
    ss.program.set(program);
    ss.setUniform("appColor", glm::vec4(0.9f, 0.6f, 0.1f, 0.4f));
    bin->addChild(q);
    auto v = topViewer();
    const Image img = render(*v, bin);
    EXPECT_LE(channelError(img, kSize / 2, kSize / 2, over({0.9, 0.6, 0.1}, 0.4, kBackground)), 2);
    EXPECT_LE(channelError(img, 2, 2, kBackground), 1);
}

TEST(WeightedBlendedRender, WeightsFollowThePapersEquationsNearAndFar) {
    // Two panes 0.5 m and 9 m from the eye: their weights differ by two orders of magnitude under
    // equation 7, so the composite leans to the near (red) pane by how much the equation says.
    // The expected pixel is computed here from McGuire & Bavoil 2013, equations 6–9, written out
    // (not through OitMath.h), with the paper's clamp to [1e-2, 3e3].
    auto paperWeight = [](int eq, double alpha, double z) {
        z = std::abs(z);
        double w = 1.0;
        if (eq == 7) w = 10.0 / (1e-5 + (z / 5) * (z / 5) + std::pow(z / 200, 6.0));
        if (eq == 8) w = 10.0 / (1e-5 + (z / 10) * (z / 10) * (z / 10) + std::pow(z / 200, 6.0));
        if (eq == 9) w = 0.03 / (1e-5 + std::pow(z / 200, 4.0));
        return eq == 0 ? alpha : alpha * std::clamp(w, 1e-2, 3e3);
    };
    const glm::dvec3 near(0.9, 0.1, 0.1), far(0.1, 0.2, 0.9);
    const double alpha = 0.5, zNear = 0.5, zFar = 9.0;
    for (auto [w, eq] : {std::pair{OitWeight::Constant, 0}, std::pair{OitWeight::Depth7, 7},
                         std::pair{OitWeight::Depth8, 8}, std::pair{OitWeight::Depth9, 9}}) {
        auto bin = TransparencyBin::create(TransparencyMode::WeightedBlended);
        OitParameters p;
        p.weight = w;
        bin->setOitParameters(p);
        bin->addChild(pane({0, 0, float(10.0 - zFar)}, glm::vec3(far), float(alpha)));
        bin->addChild(pane({0, 0, float(10.0 - zNear)}, glm::vec3(near), float(alpha)));
        auto v = topViewer();
        const Image img = render(*v, bin);
        const double wn = paperWeight(eq, alpha, zNear), wf = paperWeight(eq, alpha, zFar);
        const double reveal = (1 - alpha) * (1 - alpha);
        const glm::dvec3 expected =
            (near * alpha * wn + far * alpha * wf) / (alpha * wn + alpha * wf) * (1 - reveal) +
            kBackground * reveal;
        EXPECT_LE(channelError(img, kSize / 2, kSize / 2, expected), 2)
            << "equation " << eq << ": near weight " << wn << ", far weight " << wf;
    }
}

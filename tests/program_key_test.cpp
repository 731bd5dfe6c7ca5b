// ProgramKey: named fields that never overlap, interned ids, and the composer compiling one
// program per distinct key.
#include "TestUtil.h"

#include <sgfx/CullVisitor.h>
#include <sgfx/Effect.h>
#include <sgfx/GraphicsContext.h>
#include <sgfx/ProgramKey.h>
#include <sgfx/Renderer.h>
#include <sgfx/ShaderComposer.h>
#include <sgfx/Shapes.h>
#include <sgfx/gl/Objects.h>

#include <gtest/gtest.h>

#include <chrono>
#include <iostream>
#include <map>
#include <random>
#include <set>
#include <span>
#include <stdexcept>
#include <tuple>

using namespace sgfx;
using namespace sgfx::test;

namespace {

// What decides an item's program: source (0 built-in, 1-2 drawable bases, 3-4 foreign programs),
// snippet set, material features and draw mode.
struct Combo {
    int source;
    int snippets;
    FeatureMask features;
    DrawMode mode;
    auto tie() const { return std::tuple(source, snippets, features, std::uint8_t(mode)); }
    bool operator<(const Combo& o) const { return tie() < o.tie(); }
};

constexpr int kSnippetSets = 40;
constexpr int kSnippets = 6;

// Six snippets; set i holds snippet k where bit k of i is set (set 0 = no snippet).
struct Fixture {
    Fixture() {
        drawableA.name = "drawable_a";
        drawableB.name = "drawable_b";
        for (int k = 0; k < kSnippets; ++k) {
            snippets[k].name = "snip" + std::to_string(k);
            snippets[k].colorCode = "sgfx_color.rgb *= 0.9" + std::to_string(k) + ";";
        }
    }
    BaseShader drawableA = ShaderComposer::blinnPhong(), drawableB = ShaderComposer::blinnPhong();
    std::shared_ptr<ShaderProgram> foreignA = ShaderProgram::create("app_a", kForeignVert, kForeignFrag);
    std::shared_ptr<ShaderProgram> foreignB =
        ShaderProgram::create("app_b", kForeignVert, std::string(kForeignFrag) + "// b\n");
    ShaderSnippet snippets[kSnippets];

    std::vector<const ShaderSnippet*> set(int i) const {
        std::vector<const ShaderSnippet*> out;
        for (int k = 0; k < kSnippets; ++k)
            if (i & (1 << k)) out.push_back(&snippets[k]);
        return out;
    }
    // As RenderQueue::internEffectSet spells a signature.
    std::string signature(int i) const {
        std::string sig;
        for (const ShaderSnippet* s : set(i))
            sig += s->name + '\n';
        return sig;
    }
    const void* base(int source) const {
        const void* bases[] = {nullptr, &drawableA, &drawableB, foreignA.get(), foreignB.get()};
        return bases[source];
    }
    static ProgramSource kind(int source) {
        return source == 0  ? ProgramSource::Builtin
               : source < 3 ? ProgramSource::Drawable
                            : ProgramSource::Foreign;
    }
    // What CullVisitor and drawItems build for the combination.
    ProgramKey key(ProgramKeyTable& table, const Combo& c) const {
        return ProgramKey::make(kind(c.source), table.base(base(c.source)),
                                table.effects(signature(c.snippets)), c.features, c.mode);
    }
    // The main pass's program for the combination, as drawItems asks the composer for it.
    gl::Program& program(ShaderComposer& composer, const Combo& c) const {
        const auto list = set(c.snippets);
        if (c.source == 1 || c.source == 2)
            return composer.program(c.source == 1 ? drawableA : drawableB, list, c.features);
        return composer.program(static_cast<const ShaderProgram*>(base(c.source)), list, c.features);
    }
};

// Valid built-in variants whose bits overlap the signature ids in the old packing (light count
// 12-15 and world position / point lights 16-17 against signature bits 0-5), with a few others.
FeatureMask randomFeatures(std::mt19937& rng) {
    FeatureMask f = FeatureMask(rng() % 9) << FeatureLightCountShift;
    for (FeatureMask bit : {FeatureWorldPosition, FeaturePointLights, FeatureNormals, FeatureTexCoords})
        if (rng() & 1u) f |= bit;
    return f;
}

// `n` distinct combinations. Features as drawItems completes them (world position where
// lighting or snippets read it), so each is a program that compiles.
std::vector<Combo> randomCombos(std::mt19937& rng, std::size_t n, std::span<const DrawMode> modes) {
    std::set<Combo> seen;
    std::vector<Combo> out;
    while (out.size() < n) {
        const int source = int(rng() % 5), set = int(rng() % kSnippetSets);
        const FeatureMask features = ShaderComposer::withWorldPosition(randomFeatures(rng), set != 0);
        const Combo c{source, set, features, modes[rng() % modes.size()]};
        if (seen.insert(c).second) out.push_back(c);
    }
    return out;
}

// The packing before ProgramKey: program source at 8, features at 32, signature at 44, mode at 60.
std::uint64_t oldPacking(std::uint64_t program, std::uint32_t signature, FeatureMask features,
                         DrawMode mode) {
    return (program << 8) ^ (std::uint64_t(signature) << 44) ^ (std::uint64_t(features) << 32) ^
           (std::uint64_t(mode) << 60);
}

class SnippetEffect : public EffectNode {
public:
    explicit SnippetEffect(std::string snippetName) { snippet_.name = std::move(snippetName); }
    std::string_view kind() const override { return snippet_.name; }
    const ShaderSnippet& snippet() const override { return snippet_; }

private:
    ShaderSnippet snippet_;
};

} // namespace

TEST(ProgramKey, FieldsAreNamedDisjointAndReadBack) {
    static_assert(ProgramKey::fieldsDisjoint());
    std::uint64_t covered = 0;
    for (const ProgramKeyField& f : ProgramKey::kFields) {
        EXPECT_EQ(covered & f.mask(), 0u) << f.name;
        covered |= f.mask();
    }
    EXPECT_TRUE(ProgramKey::Features.fits(kAllMaterialFeatures));
    const ProgramKey k =
        ProgramKey::make(ProgramSource::Foreign, 5, 77, FeatureBatched | FeatureBaseMap, DrawMode::GBuffer);
    EXPECT_EQ(k.source(), ProgramSource::Foreign);
    EXPECT_EQ(k.base(), 5u);
    EXPECT_EQ(k.effects(), 77u);
    EXPECT_EQ(k.features(), FeatureMask(FeatureBatched | FeatureBaseMap));
    EXPECT_EQ(k.mode(), DrawMode::GBuffer);
    EXPECT_EQ(k.with(ProgramKey::Mode, std::uint64_t(DrawMode::Main)).mode(), DrawMode::Main);
    EXPECT_EQ(k.with(ProgramKey::Mode, std::uint64_t(DrawMode::Main)).base(), 5u);
    EXPECT_NE(ProgramKey::none(),
              ProgramKey::make(ProgramSource::Foreign, std::uint32_t(ProgramKey::Base.max()),
                               std::uint32_t(ProgramKey::Effects.max()),
                               ProgramKey::Features.max(), DrawMode::GBuffer));
}

TEST(ProgramKey, FiveHundredRandomCombosAreFiveHundredPrograms) {
    const Fixture fx;
    std::mt19937 rng(20240522);
    const DrawMode modes[] = {DrawMode::Main, DrawMode::DepthOnly, DrawMode::GBuffer};
    const std::vector<Combo> combos = randomCombos(rng, 500, modes);
    ProgramKeyTable table;
    std::map<ProgramKey, std::size_t> owner;
    for (std::size_t i = 0; i < combos.size(); ++i) {
        const ProgramKey k = fx.key(table, combos[i]);
        const auto [it, added] = owner.emplace(k, i);
        EXPECT_TRUE(added) << "combos " << it->second << " and " << i << " share the key " << k;
    }
    EXPECT_EQ(owner.size(), 500u);
    EXPECT_EQ(table.bases(), 4u);
    EXPECT_LE(table.signatures(), std::size_t(kSnippetSets - 1));
    // Equal combinations give equal keys (asked again, in the other order).
    for (std::size_t i = combos.size(); i-- > 0;)
        EXPECT_EQ(owner.at(fx.key(table, combos[i])), i);

    // The composer agrees: 500 distinct main-pass combinations are 500 keys and 500 programs,
    // each compiled once (about 3 s on llvmpipe). Depth and G-buffer passes drop the effects
    // (drawItems), so there keys are finer than programs: those are left out here.
    std::unique_ptr<GraphicsContext> context;
    try {
        context = createHeadlessContext();
    } catch (const std::exception& e) {
        if (underCi()) FAIL() << e.what();
        GTEST_SKIP() << "no OpenGL 4.5 context: " << e.what();
    }
    ShaderComposer composer; // after the context: its programs go first
    const DrawMode mainPass[] = {DrawMode::Main};
    const std::vector<Combo> main = randomCombos(rng, 500, mainPass);
    ProgramKeyTable mainTable;
    std::map<ProgramKey, const gl::Program*> programOf;
    std::set<const gl::Program*> programs;
    std::vector<const gl::Program*> first;
    const auto t0 = std::chrono::steady_clock::now();
    for (const Combo& c : main) {
        first.push_back(&fx.program(composer, c));
        programs.insert(first.back());
        programOf.emplace(fx.key(mainTable, c), first.back());
    }
    std::cout << main.size() << " programs composed in "
              << std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() << " s\n";
    EXPECT_EQ(programOf.size(), 500u);
    EXPECT_EQ(programs.size(), 500u);
    EXPECT_EQ(composer.misses(), 500u);
    EXPECT_EQ(composer.hits(), 0u);
    for (std::size_t i = 0; i < main.size(); ++i) {
        EXPECT_EQ(&fx.program(composer, main[i]), first[i]);
        EXPECT_EQ(programOf.at(fx.key(mainTable, main[i])), first[i]);
    }
    EXPECT_EQ(composer.misses(), 500u);
    EXPECT_EQ(composer.hits(), 500u);
}

TEST(ProgramKey, OldCollisionIsGone) {
    // Feature bit j landed on signature bit j-12: FeatureWorldPosition (16) with no snippet was
    // the key of the plain variant under signature id 16, and FeatureBlendPremultiplied (18) that
    // of signature id 64.
    ProgramKeyTable table;
    std::uint32_t ids[65];
    for (int i = 0; i < 65; ++i)
        ids[i] = table.effects(i == 0 ? std::string() : "set" + std::to_string(i) + "\n");
    ASSERT_EQ(ids[16], 16u);
    ASSERT_EQ(ids[64], 64u);
    const FeatureMask plain = FeatureNormals | (2u << FeatureLightCountShift);
    for (const auto& [bit, sig] : {std::pair{FeatureMask(FeatureWorldPosition), 16},
                                   std::pair{FeatureMask(FeatureBlendPremultiplied), 64}}) {
        // The old packing gives both one key: the test looks at a real collision.
        ASSERT_EQ(oldPacking(0, ids[0], plain | bit, DrawMode::Main),
                  oldPacking(0, ids[sig], plain, DrawMode::Main));
        const ProgramKey withBit = ProgramKey::make(ProgramSource::Builtin, 0, ids[0], plain | bit);
        const ProgramKey withSignature = ProgramKey::make(ProgramSource::Builtin, 0, ids[sig], plain);
        EXPECT_NE(withBit, withSignature) << withBit << " vs " << withSignature;
    }
    // A drawable's base and a foreign program with the same id are told apart by the source.
    EXPECT_NE(ProgramKey::make(ProgramSource::Drawable, 1, 0, 0),
              ProgramKey::make(ProgramSource::Foreign, 1, 0, 0));
    // Depth and G-buffer variants of one item: distinct from each other and from the main one.
    const ProgramKey mainKey = ProgramKey::make(ProgramSource::Drawable, 1, 3, plain);
    EXPECT_NE(mainKey, mainKey.with(ProgramKey::Mode, std::uint64_t(DrawMode::DepthOnly)));
    EXPECT_NE(mainKey.with(ProgramKey::Mode, std::uint64_t(DrawMode::GBuffer)),
              mainKey.with(ProgramKey::Mode, std::uint64_t(DrawMode::DepthOnly)));
}

TEST(ProgramKey, FieldOverflowThrows) {
    auto expectThrowNaming = [](const auto& f, const std::string& field) {
        try {
            f();
            ADD_FAILURE() << field << ": no exception";
        } catch (const std::length_error& e) {
            EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
        }
    };
    expectThrowNaming([] { (void)ProgramKey::make(ProgramSource::Builtin, 0, 0, ProgramKey::Features.max() + 1); }, "Features");
    expectThrowNaming([] { (void)ProgramKey::make(ProgramSource::Builtin, 0, 0, 0, DrawMode(4)); }, "Mode");
    expectThrowNaming([] { (void)ProgramKey::make(ProgramSource::Builtin, 0, std::uint32_t(ProgramKey::Effects.max() + 1), 0); }, "Effects");
    expectThrowNaming([] { (void)ProgramKey::make(ProgramSource::Foreign, std::uint32_t(ProgramKey::Base.max() + 1), 0, 0); }, "Base");
    expectThrowNaming([] { (void)ProgramKey::make(ProgramSource(4), 0, 0, 0); }, "Source");
    expectThrowNaming([] { (void)ProgramKey().with(ProgramKey::Effects, ProgramKey::Effects.max() + 1); },
                      "Effects");
    // The largest values fit.
    EXPECT_NO_THROW((void)ProgramKey().with(ProgramKey::Effects, ProgramKey::Effects.max()));

    // A table fails loudly when its ids outgrow their field, naming it; ids already given stay.
    ProgramKeyTable table;
    std::vector<char> objects(ProgramKey::Base.max() + 1);
    for (std::size_t i = 0; i < ProgramKey::Base.max(); ++i)
        ASSERT_EQ(table.base(&objects[i]), i + 1);
    expectThrowNaming([&] { (void)table.base(&objects.back()); }, "Base");
    EXPECT_EQ(table.base(&objects[0]), 1u);
    for (std::size_t i = 1; i <= ProgramKey::Effects.max(); ++i)
        ASSERT_EQ(table.effects(std::to_string(i)), i);
    expectThrowNaming([&] { (void)table.effects("one too many"); }, "Effects");
    table.clear();
    EXPECT_EQ(table.base(&objects.back()), 1u);
}

TEST(ProgramKey, IdsAreDensePerFrameAndDoNotGrow) {
    // Each frame twenty new snippet sets and a new foreign program, culled into one queue: every
    // frame the same small ids (they grew over a session before).
    auto scene = [](int frame) {
        auto cam = Camera::create();
        cam->setViewport(0, 0, 100, 100);
        cam->setPerspective(90.0f, 1.0f, 100.0f);
        cam->viewMatrix = glm::mat4(1.0f);
        auto foreign = ShaderProgram::create("app" + std::to_string(frame), kForeignVert, kForeignFrag);
        for (int i = 0; i < 20; ++i) {
            auto e =
                std::make_shared<SnippetEffect>("effect" + std::to_string(frame) + "_" + std::to_string(i));
            auto box = shapes::box({1, 1, 1});
            if (i % 2) box->getOrCreateStateSet().program.set(foreign);
            auto t = Transform::create(glm::translate(glm::mat4(1.0f), {float(i % 5) - 2.0f, 0.0f, -10.0f}));
            t->addChild(box);
            e->addChild(t);
            cam->addChild(e);
        }
        return cam;
    };
    RenderQueue q;
    std::vector<ProgramKey> firstFrame;
    for (int frame = 0; frame < 3; ++frame) {
        const auto cam = scene(frame);
        q.clear();
        CullVisitor cv(*cam, q);
        cv.run(*cam);
        ASSERT_EQ(q.opaque.size(), 20u);
        std::vector<ProgramKey> keys;
        for (const RenderItem& it : q.opaque) {
            keys.push_back(it.programKey);
            EXPECT_GE(it.programKey.effects(), 1u);
            EXPECT_LE(it.programKey.effects(), 20u);
            EXPECT_EQ(it.programKey.base(), it.program() ? 1u : 0u);
            EXPECT_EQ(it.programKey.source(), it.program() ? ProgramSource::Foreign : ProgramSource::Builtin);
        }
        EXPECT_EQ(std::set<ProgramKey>(keys.begin(), keys.end()).size(), 20u);
        EXPECT_EQ(q.programKeys.signatures(), 20u);
        EXPECT_EQ(q.programKeys.bases(), 1u);
        if (frame == 0) firstFrame = keys;
        EXPECT_EQ(keys, firstFrame) << "frame " << frame;
    }
}

// The frame graph's compile and execute without GL: culling, lifetimes, the sharing of textures,
// size rules, and the errors a wrong declaration gets.
#include "sgfx/FrameGraph.h"

#include <gtest/gtest.h>
#include <sgfx_glad/gl.h>

#include <map>
#include <regex>

using namespace sgfx;
using Builder = FrameGraph::Builder;

namespace {

// Hands out texture names, reusing released ones of an equal description, and records the calls.
struct FakeAllocator : ResourceAllocator {
    std::multimap<ResolvedDesc, unsigned> free;
    unsigned next = 100;
    int made = 0, acquired = 0, released = 0;
    std::vector<std::string> names;
    unsigned acquire(const ResolvedDesc& d, std::string_view name) override {
        ++acquired;
        names.emplace_back(name);
        if (auto it = free.find(d); it != free.end()) {
            const unsigned t = it->second;
            free.erase(it);
            return t;
        }
        ++made;
        return next++;
    }
    void release(unsigned t, const ResolvedDesc& d) override {
        ++released;
        free.emplace(d, t);
    }
};

const TextureDesc kDepth{GL_DEPTH_COMPONENT32F};
const TextureDesc kColour{GL_RGBA16F};
const TextureDesc kHalf{GL_RG32F, SizeRule::half(SizeRule::Round::Up)};

std::vector<std::string> run(FrameGraph& g, FakeAllocator& a) {
    std::vector<std::string> order;
    g.execute(a, [&](std::string_view name, const FrameGraph::Execute&) { order.emplace_back(name); });
    return order;
}

// The view's target, written by a final pass that is kept because it writes an imported resource.
ResourceId target(FrameGraph& g) {
    return g.import("view.colour", {GL_SRGB8_ALPHA8}, 7);
}

} // namespace

TEST(FrameGraph, CullsPassesWhoseOutputsNobodyReads) {
    FrameGraph g;
    const ResourceId view = target(g);
    ResourceId a, b, c;
    g.addPass("A", [&](Builder& x) { a = x.colour(x.create("a", kColour)); }, {});
    g.addPass("B",
              [&](Builder& x) {
                  x.sample(a);
                  b = x.colour(x.create("b", kColour));
              },
              {});
    g.addPass("C",
              [&](Builder& x) {
                  x.sample(b);
                  c = x.colour(x.create("c", kColour));
              },
              {}); // c: unread
    g.addPass("D",
              [&](Builder& x) {
                  x.sample(a);
                  x.colour(view);
              },
              {});
    g.compile({64, 32}, {64, 32});
    EXPECT_FALSE(g.culled("A"));
    EXPECT_TRUE(g.culled("B")) << "B's only output is read by C, which is culled";
    EXPECT_TRUE(g.culled("C"));
    EXPECT_FALSE(g.culled("D"));
    FakeAllocator alloc;
    EXPECT_EQ(run(g, alloc), (std::vector<std::string>{"A", "D"}));
    EXPECT_EQ(alloc.names, std::vector<std::string>{"a"}) << "culled passes' resources are never made";
}

TEST(FrameGraph, SideEffectsImportedWritesAndPresentedResourcesSurvive) {
    FrameGraph g;
    const ResourceId view = target(g);
    ResourceId shown;
    g.addPass("simulate", [](Builder& x) { x.sideEffect(); }, {});
    g.addPass("write view", [&](Builder& x) { x.colour(view); }, {});
    g.addPass("made", [&](Builder& x) { shown = x.colour(x.create("shown", kColour)); }, {});
    g.addPass("unused", [&](Builder& x) { x.colour(x.create("nobody", kColour)); }, {});
    g.present(shown);
    g.compile({8, 8}, {8, 8});
    EXPECT_EQ(g.livePasses(), (std::vector<std::string>{"simulate", "write view", "made"}));
}

TEST(FrameGraph, LivePassesRunInDeclarationOrderAndKeepReadsPreviousContent) {
    FrameGraph g;
    ResourceId view = target(g);
    ResourceId depth;
    g.addPass("depth pre-pass", [&](Builder& x) { depth = x.depth(x.create("scene.depth", kDepth)); }, {});
    g.addPass("main", [&](Builder& x) { view = x.colour(view, 0, false); }, {});
    g.addPass("fog",
              [&](Builder& x) {
                  x.sample(depth);
                  view = x.colour(view);
              },
              {});
    g.addPass("aa", [&](Builder& x) { view = x.colour(view); }, {});
    g.compile({8, 8}, {8, 8});
    FakeAllocator alloc;
    EXPECT_EQ(run(g, alloc), (std::vector<std::string>{"depth pre-pass", "main", "fog", "aa"}));
    EXPECT_EQ(g.writers("view.colour"), (std::vector<std::string>{"main", "fog", "aa"}));
    EXPECT_EQ(g.writers("scene.depth"), std::vector<std::string>{"depth pre-pass"});
}

TEST(FrameGraph, ReadingWhatNoPassWroteThrowsNamingBoth) {
    FrameGraph g;
    try {
        g.addPass("ao occlusion", [&](Builder& x) { x.sample(x.create("scene.normals", kColour)); }, {});
        FAIL() << "no error";
    } catch (const std::logic_error& e) {
        EXPECT_NE(std::string(e.what()).find("'ao occlusion' reads 'scene.normals'"), std::string::npos)
            << e.what();
    }
}

TEST(FrameGraph, UsingAReplacedVersionThrows) {
    FrameGraph g;
    ResourceId v0, v1;
    g.addPass("first", [&](Builder& x) { v0 = x.colour(x.create("r", kColour)); }, {});
    g.addPass("second", [&](Builder& x) { v1 = x.colour(v0); }, {});
    EXPECT_NE(v0, v1);
    EXPECT_THROW(g.addPass("third", [&](Builder& x) { x.sample(v0); }, {}), std::logic_error);
    EXPECT_THROW(g.addPass("fourth", [&](Builder& x) { x.sample(ResourceId{}); }, {}), std::invalid_argument);
}

TEST(FrameGraph, SizeRulesRoundAsTheirUsersNeed) {
    // Half of 641: ambient occlusion rounds up (321), the volume's half resolution down (320).
    EXPECT_EQ(SizeRule::half(SizeRule::Round::Up).resolve({641, 361}, {641, 361}), glm::ivec2(321, 181));
    EXPECT_EQ(SizeRule::half(SizeRule::Round::Down).resolve({641, 361}, {641, 361}), glm::ivec2(320, 180));
    // Supersampling ×2: the draw target is twice the view.
    EXPECT_EQ(SizeRule::draw().resolve({1282, 722}, {641, 361}), glm::ivec2(1282, 722));
    EXPECT_EQ(SizeRule::view().resolve({1282, 722}, {641, 361}), glm::ivec2(641, 361));
    EXPECT_EQ(SizeRule::fixedSize(256, 128).resolve({1, 1}, {1, 1}), glm::ivec2(256, 128));
    EXPECT_EQ(SizeRule::half(SizeRule::Round::Down).resolve({1, 1}, {1, 1}), glm::ivec2(1, 1))
        << "at least 1";
}

TEST(FrameGraph, EqualDescriptionsWithDisjointLivesShareATextureOverlappingOnesNever) {
    FrameGraph g;
    ResourceId view = target(g);
    ResourceId raw, blurX, blurY;
    // AO's chain: raw → blur x → blur y; raw is dead once blur x ran, so blur y takes its texture.
    g.addPass("occlusion", [&](Builder& x) { raw = x.colour(x.create("ao.raw", kHalf)); }, {});
    g.addPass("blur x",
              [&](Builder& x) {
                  x.sample(raw);
                  blurX = x.colour(x.create("ao.x", kHalf));
              },
              {});
    g.addPass("blur y",
              [&](Builder& x) {
                  x.sample(blurX);
                  blurY = x.colour(x.create("ao.map", kHalf));
              },
              {});
    g.addPass("main",
              [&](Builder& x) {
                  x.sample(blurY);
                  view = x.colour(view);
              },
              {});
    g.compile({641, 361}, {641, 361});
    EXPECT_EQ(g.textureSlots(), 2u) << "ao.map reuses ao.raw's texture; ao.x overlaps both";
    EXPECT_EQ(g.transientBytes(), 2u * 321 * 181 * 8);
    FakeAllocator alloc;
    unsigned rawTex = 0, mapTex = 0, xTex = 0;
    g.execute(alloc, [&](std::string_view name, const FrameGraph::Execute&) {
        if (name == "occlusion") rawTex = g.texture(raw);
        if (name == "blur x") xTex = g.texture(blurX);
        if (name == "blur y") mapTex = g.texture(blurY);
    });
    EXPECT_EQ(alloc.made, 2);
    EXPECT_EQ(rawTex, mapTex);
    EXPECT_NE(rawTex, xTex);
    EXPECT_EQ(alloc.acquired, alloc.released) << "every transient texture is given back";
    EXPECT_EQ(g.texture(blurY), 0u) << "no texture outside the resource's life";
}

TEST(FrameGraph, DifferentDescriptionsNeverShare) {
    FrameGraph g;
    ResourceId view = target(g);
    ResourceId a, b;
    g.addPass("A", [&](Builder& x) { a = x.colour(x.create("a", kColour)); }, {});
    g.addPass("B",
              [&](Builder& x) {
                  x.sample(a);
                  b = x.colour(x.create("b", kHalf));
              },
              {});
    g.addPass("C",
              [&](Builder& x) {
                  x.sample(b);
                  x.colour(x.create("c", kHalf));
                  x.colour(view);
              },
              {});
    g.compile({64, 64}, {64, 64});
    EXPECT_EQ(g.textureSlots(), 3u);
}

TEST(FrameGraph, DotNamesPassesResourcesEdgesAndTimes) {
    FrameGraph g;
    ResourceId view = target(g);
    ResourceId d;
    g.addPass("scene depth", [&](Builder& x) { d = x.depth(x.create("scene.depth", kDepth)); }, {});
    g.addPass("fog \"post\"",
              [&](Builder& x) {
                  x.sample(d, "SGFX_FOG_DEPTH");
                  view = x.colour(view);
              },
              {});
    g.addPass("orphan", [&](Builder& x) { x.colour(x.create("nobody", kColour)); }, {});
    g.compile({320, 180}, {320, 180});
    const std::string dot = g.dotCluster("main view", {{"scene depth", 0.25}});
    EXPECT_NE(dot.find("scene depth\\n0.250 ms"), std::string::npos) << dot;
    EXPECT_NE(dot.find("fog \\\"post\\\"\\n-"), std::string::npos) << dot;
    EXPECT_NE(dot.find("scene.depth\\nD32F 320x180 [slot 0]"), std::string::npos) << dot;
    EXPECT_NE(dot.find("label=\"SGFX_FOG_DEPTH\""), std::string::npos) << dot;
    EXPECT_TRUE(std::regex_search(dot, std::regex("orphan[^\\]]*style=dashed"))) << dot;
    EXPECT_EQ(std::count(dot.begin(), dot.end(), '{'), std::count(dot.begin(), dot.end(), '}'));
}

TEST(FrameGraph, BlackboardNamesWhatIsMissing) {
    Blackboard b;
    b.put("scene.depth", {3, 1});
    EXPECT_EQ(b.get("scene.depth"), (ResourceId{3, 1}));
    try {
        b.get("scene.normals");
        FAIL();
    } catch (const std::out_of_range& e) {
        EXPECT_NE(std::string(e.what()).find("'scene.normals'"), std::string::npos);
    }
}

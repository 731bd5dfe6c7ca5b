// Traversal and logic tests: no GL context needed.
#include <sgfx/Camera.h>
#include <sgfx/CullVisitor.h>
#include <sgfx/Effect.h>
#include <sgfx/Geometry.h>
#include <sgfx/Group.h>
#include <sgfx/Material.h>
#include <sgfx/Renderer.h>
#include <sgfx/ShaderComposer.h>
#include <sgfx/Shapes.h>
#include <sgfx/StateSet.h>
#include <sgfx/Visitors.h>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include <bit>

#include <cmath>
#include <deque>
#include <string>

using namespace sgfx;

namespace {

class NameRecorder : public NodeVisitor {
public:
    NameRecorder()
        : NodeVisitor(Mode::ActiveChildren) {}
    void apply(Node& n) override {
        order += n.name + " ";
        traverse(n);
    }
    std::string order;
};

std::shared_ptr<Group> named(const std::string& n) {
    auto g = Group::create();
    g->name = n;
    return g;
}

std::shared_ptr<Geometry> unitBox(const std::string& name = "box") {
    auto g = shapes::box({1, 1, 1});
    g->name = name;
    return g;
}

class TestEffect : public EffectNode {
public:
    TestEffect(std::string k, std::string n, int o = 0)
        : kind_(std::move(k))
        , order_(o) {
        snippet_.name = std::move(n);
    }
    std::string_view kind() const override { return kind_; }
    int order() const override { return order_; }
    const ShaderSnippet& snippet() const override { return snippet_; }

private:
    std::string kind_;
    int order_;
    ShaderSnippet snippet_;
};

// Camera at the origin looking down -Y... simpler: default view looks down -Z.
std::shared_ptr<Camera> perspectiveCamera() {
    auto c = Camera::create();
    c->setViewport(0, 0, 100, 100);
    c->setPerspective(90.0f, 1.0f, 100.0f);
    c->viewMatrix = glm::mat4(1.0f);
    return c;
}

} // namespace

TEST(Traversal, VisitOrderIsDepthFirstPreOrder) {
    auto root = named("root");
    auto a = named("a"), b = named("b"), a1 = named("a1"), a2 = named("a2");
    root->addChild(a);
    root->addChild(b);
    a->addChild(a1);
    a->addChild(a2);
    NameRecorder r;
    root->accept(r);
    EXPECT_EQ(r.order, "root a a1 a2 b ");
}

TEST(Traversal, NodeMaskSkipsSubtree) {
    auto root = named("root");
    auto a = named("a"), b = named("b"), a1 = named("a1");
    root->addChild(a);
    root->addChild(b);
    a->addChild(a1);
    a->nodeMask = 0x2;
    NameRecorder r;
    r.traversalMask = 0x1;
    root->accept(r);
    EXPECT_EQ(r.order, "root b ");
    r.order.clear();
    r.traversalMask = 0x3;
    root->accept(r);
    EXPECT_EQ(r.order, "root a a1 b ");
}

TEST(Traversal, SharedSubgraphVisitedOncePerParentPath) {
    auto root = named("root");
    auto p1 = named("p1"), p2 = named("p2"), shared = named("s");
    root->addChild(p1);
    root->addChild(p2);
    p1->addChild(shared);
    p2->addChild(shared);
    shared->addChild(unitBox("leaf"));
    NameRecorder r;
    root->accept(r);
    EXPECT_EQ(r.order, "root p1 s leaf p2 s leaf ");
    EXPECT_EQ(shared->parents().size(), 2u);
    StatsVisitor stats;
    root->accept(stats);
    EXPECT_EQ(stats.drawables, 2u);
    EXPECT_EQ(stats.triangles, 24u);
}

TEST(Traversal, CycleIsRefusedWithAnError) {
    auto a = named("a"), b = named("b"), c = named("c");
    a->addChild(b);
    b->addChild(c);
    try {
        c->addChild(a);
        FAIL() << "cycle accepted";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("cycle"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("'a'"), std::string::npos) << e.what();
    }
    EXPECT_THROW(a->addChild(a), std::invalid_argument);
    EXPECT_THROW(a->addChild(nullptr), std::invalid_argument);
    EXPECT_EQ(c->numChildren(), 0u); // unchanged after the refusal
    // A diamond (shared child) is not a cycle.
    auto d = named("d");
    b->addChild(d);
    c->addChild(d);
    EXPECT_EQ(d->parents().size(), 2u);
}

TEST(Traversal, RemovingAChildClearsItsParentLink) {
    auto a = named("a");
    auto child = unitBox();
    a->addChild(child);
    EXPECT_TRUE(a->removeChild(child.get()));
    EXPECT_TRUE(child->parents().empty());
    EXPECT_FALSE(a->removeChild(child.get()));
    {
        auto g = named("g");
        g->addChild(child);
    }
    EXPECT_TRUE(child->parents().empty()); // the dead group let go of it
}

TEST(Bounds, DirtyPropagatesWhenAChildMoves) {
    auto root = named("root");
    auto t = Transform::create();
    t->addChild(unitBox());
    root->addChild(t);
    const float r0 = root->bound().radius;
    EXPECT_NEAR(root->bound().center.x, 0.0f, 1e-6f);
    EXPECT_NEAR(r0, std::sqrt(3.0f) / 2.0f, 1e-5f);
    t->setMatrix(glm::translate(glm::mat4(1.0f), {10, 0, 0}));
    EXPECT_NEAR(root->bound().center.x, 10.0f, 1e-5f);
    // Editing geometry and calling dirty() also reaches the root.
    auto g = std::static_pointer_cast<Geometry>(t->child(0));
    for (auto& p : g->positions)
        p *= 2.0f;
    g->dirty();
    EXPECT_NEAR(root->bound().radius, std::sqrt(3.0f), 1e-5f);
    EXPECT_THROW(t->setMatrix(glm::mat4(std::nanf(""))), std::invalid_argument);
}

TEST(Bounds, GroupSphereEnclosesChildren) {
    auto g = Group::create();
    auto a = Transform::create(glm::translate(glm::mat4(1.0f), {-5, 0, 0}));
    auto b = Transform::create(glm::translate(glm::mat4(1.0f), {5, 2, 1}));
    a->addChild(unitBox());
    b->addChild(shapes::sphere(3.0f));
    g->addChild(a);
    g->addChild(b);
    const BoundingSphere s = g->bound();
    for (const auto& c : g->children()) {
        const BoundingSphere cs = c->bound();
        EXPECT_LE(glm::length(cs.center - s.center) + cs.radius, s.radius + 1e-4f);
    }
    ComputeBoundsVisitor cb;
    g->accept(cb);
    EXPECT_NEAR(cb.min.x, -5.5f, 1e-5f);
    EXPECT_NEAR(cb.max.x, 8.0f, 1e-4f);
}

TEST(Culling, FrustumClassifiesExactCases) {
    // Symmetric 90° frustum looking down -Z, near 1, far 100: the side planes are x = ±(-z).
    const Frustum f = Frustum::fromMatrix(glm::perspective(glm::radians(90.0f), 1.0f, 1.0f, 100.0f));
    EXPECT_EQ(f.classify({{0, 0, -50}, 1.0f}), Containment::Inside);
    EXPECT_EQ(f.classify({{0, 0, 10}, 1.0f}), Containment::Outside);      // behind the eye
    EXPECT_EQ(f.classify({{0, 0, -200}, 1.0f}), Containment::Outside);    // beyond far
    EXPECT_EQ(f.classify({{0, 0, -100}, 1.0f}), Containment::Intersects); // straddles far
    // Distance from (x, 0, -10) to the plane x = 10 (normal (-1,0,1)/√2 inside): (10 - x)/√2.
    const float s2 = std::sqrt(2.0f);
    EXPECT_EQ(f.classify({{10.0f + 1.01f * s2, 0, -10}, 1.0f}), Containment::Outside);
    EXPECT_EQ(f.classify({{10.0f + 0.99f * s2, 0, -10}, 1.0f}), Containment::Intersects);
    EXPECT_EQ(f.classify({{10.0f - 1.01f * s2, 0, -10}, 1.0f}), Containment::Inside);
}

TEST(Culling, CullVisitorDropsOutsideKeepsInsideAndStraddling) {
    auto cam = perspectiveCamera(); // 90° fov, near 1, far 100, looking down -Z
    auto place = [&](glm::vec3 p, const std::string& n) {
        auto t = Transform::create(glm::translate(glm::mat4(1.0f), p));
        t->name = n;
        t->addChild(unitBox(n));
        cam->addChild(t);
    };
    place({0, 0, -20}, "inside");
    place({0, 0, 20}, "behind");
    place({200, 0, -20}, "right");
    place({20.0f, 0, -20}, "straddle"); // centre on the right plane
    place({0, 0, -300}, "far");
    RenderQueue q;
    CullVisitor cv(*cam, q);
    cv.run(*cam);
    std::string names;
    for (auto& it : q.opaque)
        names += it.geometry->name + " ";
    EXPECT_EQ(q.opaque.size(), 2u) << names;
    EXPECT_NE(names.find("inside"), std::string::npos);
    EXPECT_NE(names.find("straddle"), std::string::npos);
    EXPECT_EQ(cv.culledNodes, 3u);
    // Near/far from what was kept: nearest is the inside box at 20 - r.
    EXPECT_NEAR(cv.computedNear, 20.0f - std::sqrt(3.0f) / 2, 1e-3f);
    // With culling off everything is queued.
    cam->cullingEnabled = false;
    RenderQueue all;
    CullVisitor cv2(*cam, all);
    cv2.run(*cam);
    EXPECT_EQ(all.opaque.size(), 5u);
}

// The cull traversal multiplies the radius scale down chains of rotations and uniform scales
// instead of measuring every modelView matrix; it must give the radius BoundingSphere::transformed
// gives for the whole matrix, with or without a non-uniform scale (the measured path) in the chain.
TEST(Culling, RadiusScaleMatchesTheWholeMatrixDownSimilarAndShearedChains) {
    for (bool stretched : {false, true}) {
        auto cam = Camera::create();
        cam->setViewport(0, 0, 100, 100);
        cam->setPerspective(60.0f, 0.1f, 1000.0f);
        cam->setLookAt({30, -40, 20}, {0, 0, 0});
        const glm::mat4 a = glm::scale(glm::rotate(glm::mat4(1.0f), 0.7f, glm::normalize(glm::vec3(1, 2, 3))),
                                       glm::vec3(2.0f));
        const glm::mat4 b =
            stretched ? glm::scale(glm::mat4(1.0f), {1.0f, 3.0f, 1.0f})
                      : glm::scale(glm::rotate(glm::mat4(1.0f), -1.1f, glm::vec3(0, 0, 1)), glm::vec3(0.5f));
        const glm::mat4 c = glm::translate(glm::rotate(glm::mat4(1.0f), 0.3f, glm::vec3(1, 0, 0)), {1, 2, 0});
        auto ta = Transform::create(a), tb = Transform::create(b), tc = Transform::create(c);
        EXPECT_TRUE(ta->similarity());
        EXPECT_EQ(tb->similarity(), !stretched);
        auto box = shapes::box({1, 2, 3});
        tc->addChild(box);
        tb->addChild(tc);
        ta->addChild(tb);
        cam->addChild(ta);
        RenderQueue q;
        CullVisitor cv(*cam, q);
        cv.run(*cam);
        ASSERT_EQ(q.opaque.size(), 1u);
        const BoundingSphere expected = box->bound().transformed(cam->viewMatrix * a * b * c);
        EXPECT_NEAR(cv.computedNear, -expected.center.z - expected.radius, 1e-4f * expected.radius);
        EXPECT_NEAR(cv.computedFar, -expected.center.z + expected.radius, 1e-4f * expected.radius);
    }
}

// Instanced leaves (one Geometry with its own StateSet under many Transforms) share the
// ResolvedState the cull merges for them, per inherited state: under an Override material each
// item still resolves to that parent's material, and the blend above one group changes its items'
// features and bin but not the other group's.
TEST(Culling, SharedLeafStateResolvesPerParentState) {
    auto cam = perspectiveCamera();
    auto leaf = unitBox("leaf");
    auto own = Material::create();
    leaf->getOrCreateStateSet().material.set(own);
    auto red = Material::create(), blue = Material::create();
    auto a = Group::create(), b = Group::create(), c = Group::create();
    a->getOrCreateStateSet().material.set(red, Override);
    b->getOrCreateStateSet().material.set(blue, Override);
    c->getOrCreateStateSet().blend.set(BlendMode::Alpha);
    for (int i = 0; i < 40; ++i)
        for (const auto& g : {a, b, c}) {
            auto t =
                Transform::create(glm::translate(glm::mat4(1.0f), {float(i % 5) - 2, 0, -20.0f - float(i)}));
            t->addChild(leaf);
            g->addChild(t);
        }
    cam->addChild(a);
    cam->addChild(b);
    cam->addChild(c);
    RenderQueue q;
    CullVisitor cv(*cam, q);
    cv.run(*cam);
    ASSERT_EQ(q.opaque.size(), 80u);
    ASSERT_EQ(q.transparent.size(), 40u);
    std::size_t reds = 0, blues = 0;
    const ResolvedState* redState = nullptr;
    for (const RenderItem& it : q.opaque) {
        const Material* m = it.state->material.value->get();
        reds += m == red.get();
        blues += m == blue.get();
        if (m == red.get()) {
            if (!redState) redState = it.state;
            EXPECT_EQ(it.state, redState) << "instanced leaves under one state share its merge";
        }
        EXPECT_EQ(it.features & FeatureBlend, 0u);
    }
    EXPECT_EQ(reds, 40u);
    EXPECT_EQ(blues, 40u);
    for (const RenderItem& it : q.transparent) {
        EXPECT_EQ(it.state->material.value->get(), own.get());
        EXPECT_NE(it.features & FeatureBlend, 0u);
    }
    // A few states for 120 items, not one per item.
    EXPECT_LE(q.states.size(), 8u);
}

// A node with culling switched off is visited (its effect planned) even when everything is out of
// view, and so are its ancestors; its children are still culled on their own.
TEST(Culling, CullingInactiveNodeAndItsAncestorsAreAlwaysVisited) {
    struct Planner : EffectNode {
        std::string_view kind() const override { return "planner"; }
        const ShaderSnippet& snippet() const override {
            static const ShaderSnippet s{};
            return s;
        }
    };
    auto cam = perspectiveCamera();
    auto outside = Transform::create(glm::translate(glm::mat4(1.0f), {0, 0, 50})); // behind the camera
    auto group = Group::create();
    auto effect = std::make_shared<Planner>();
    effect->addChild(unitBox("hidden"));
    group->addChild(effect);
    outside->addChild(group);
    cam->addChild(outside);
    FramePlan plan;
    {
        RenderQueue q;
        CullVisitor cv(*cam, q, &plan);
        cv.run(*cam);
        EXPECT_EQ(std::count(plan.effects.begin(), plan.effects.end(), effect.get()),
                  0); // culled with its parents
    }
    effect->setCullingActive(false);
    EXPECT_TRUE(outside->cullingDisabledInSubtree()); // propagated to the ancestors
    {
        RenderQueue q;
        CullVisitor cv(*cam, q, &plan);
        cv.run(*cam);
        EXPECT_EQ(std::count(plan.effects.begin(), plan.effects.end(), effect.get()), 1);
        EXPECT_EQ(q.size(), 0u); // the box below is still culled
    }
    effect->setCullingActive(true);
    EXPECT_FALSE(outside->cullingDisabledInSubtree());
    group->removeChild(effect.get());
    effect->setCullingActive(false);
    EXPECT_FALSE(outside->cullingDisabledInSubtree()); // no longer a descendant
}

TEST(Culling, NodeMaskHidesFromCull) {
    auto cam = perspectiveCamera();
    auto t = Transform::create(glm::translate(glm::mat4(1.0f), {0, 0, -10}));
    t->addChild(unitBox());
    cam->addChild(t);
    t->nodeMask = 0;
    RenderQueue q;
    CullVisitor cv(*cam, q);
    cv.run(*cam);
    EXPECT_EQ(q.size(), 0u);
}

TEST(State, InheritanceOverrideAndProtect) {
    auto red = Material::create();
    red->diffuse = {1, 0, 0, 1};
    auto blue = Material::create();
    blue->diffuse = {0, 0, 1, 1};
    auto green = Material::create();

    StateSet parent, child, protectedChild;
    parent.material.set(red);
    parent.cullFace.set(CullFace::None);
    child.material.set(blue);
    ResolvedState base = ResolvedState::defaults();
    // Plain: the child's value wins.
    EXPECT_EQ(base.merged(parent).merged(child).material.value->get(), blue.get());
    // Inherited where the child says nothing.
    EXPECT_EQ(*base.merged(parent).merged(child).cullFace.value, CullFace::None);
    // Parent Override beats the child's plain value...
    parent.material.set(red, Override);
    EXPECT_EQ(base.merged(parent).merged(child).material.value->get(), red.get());
    // ...but not a Protected one.
    protectedChild.material.set(green, Protected);
    EXPECT_EQ(base.merged(parent).merged(protectedChild).material.value->get(), green.get());
    // Uniforms follow the same rules by name.
    parent.setUniform("u", 1.0f, Override);
    child.setUniform("u", 2.0f);
    child.setUniform("v", 3.0f);
    const ResolvedState r = base.merged(parent).merged(child);
    EXPECT_EQ(std::get<float>(*r.uniforms.at("u").value), 1.0f);
    EXPECT_EQ(std::get<float>(*r.uniforms.at("v").value), 3.0f);
}

TEST(State, CullRecordsInheritedStatePerItem) {
    auto cam = perspectiveCamera();
    auto g = Group::create();
    auto mat = Material::create();
    g->getOrCreateStateSet().material.set(mat);
    auto t = Transform::create(glm::translate(glm::mat4(1.0f), {0, 0, -10}));
    t->addChild(unitBox());
    g->addChild(t);
    cam->addChild(g);
    RenderQueue q;
    CullVisitor cv(*cam, q);
    cv.run(*cam);
    ASSERT_EQ(q.opaque.size(), 1u);
    EXPECT_EQ(q.opaque[0].state->material.value->get(), mat.get());
    EXPECT_NEAR(q.opaque[0].model[3].z, -10.0f, 1e-6f);
}

TEST(Queue, OpaqueSortedByDistanceOctaveProgramMaterialThenFrontToBack) {
    auto cam = perspectiveCamera();
    auto m1 = Material::create(), m2 = Material::create();
    auto foreign =
        ShaderProgram::create("app", "#version 450 core\nvoid main(){}", "#version 450 core\nvoid main(){}");
    struct Spec {
        float z;
        std::shared_ptr<Material> m;
        bool foreign;
        std::string name;
    };
    // All but the last lie in one octave of distance [16, 32).
    const Spec specs[] = {{-30, m1, false, "m1far"},  {-17, m2, false, "m2near"},
                          {-25, m1, false, "m1mid"},  {-16.5f, m1, true, "fnear"},
                          {-20, m1, false, "m1near"}, {-80, m1, false, "m1veryfar"}};
    for (const auto& s : specs) {
        auto t = Transform::create(glm::translate(glm::mat4(1.0f), {0, 0, s.z}));
        auto b = unitBox(s.name);
        b->getOrCreateStateSet().material.set(s.m);
        if (s.foreign) b->getOrCreateStateSet().program.set(foreign);
        t->addChild(b);
        cam->addChild(t);
    }
    RenderQueue q;
    CullVisitor cv(*cam, q);
    cv.run(*cam);
    q.sort();
    ASSERT_EQ(q.opaque.size(), 6u);
    EXPECT_EQ(q.opaque.back().geometry->name, "m1veryfar"); // a farther octave comes after
    // Within an octave: items of one program are contiguous, items of one material within it are
    // contiguous, and each run is front to back.
    for (std::size_t i = 1; i + 1 < q.opaque.size(); ++i) {
        const auto& a = q.opaque[i - 1];
        const auto& b = q.opaque[i];
        ASSERT_EQ(a.depthBucket, b.depthBucket);
        ASSERT_LE(a.programKey, b.programKey);
        if (a.programKey == b.programKey &&
            a.state->material.value->get() == b.state->material.value->get()) {
            EXPECT_LT(a.depth, b.depth) << a.geometry->name << " before " << b.geometry->name;
        }
    }
    std::string m1run;
    for (auto& it : q.opaque)
        if (it.state->material.value->get() == m1.get() && !it.program()) m1run += it.geometry->name + " ";
    EXPECT_EQ(m1run, "m1near m1mid m1far m1veryfar ");
}

TEST(Queue, PackedOpaqueSortEqualsTheComparisonOrder) {
    // The radix sort on packed (octave, program rank, material rank, mesh rank, depth) keys
    // gives exactly the order of the item comparison, also past 4096 distinct materials (its
    // fallback), with ties (equal depths, -0 and +0) in cull order.
    auto depthKey = [](float depth) {
        std::uint32_t d = std::bit_cast<std::uint32_t>(depth + 0.0f);
        d ^= (d & 0x80000000u) ? 0xffffffffu : 0x80000000u;
        return d >> 12;
    };
    std::vector<std::shared_ptr<Geometry>> meshes;
    for (int i = 0; i < 9; ++i)
        meshes.push_back(Geometry::create());
    for (const int materials : {7, 5000}) {
        SCOPED_TRACE(materials);
        std::vector<std::shared_ptr<Material>> mats;
        std::deque<ResolvedState> states;
        for (int i = 0; i < materials; ++i) {
            mats.push_back(Material::create());
            states.push_back(ResolvedState::defaults());
            states.back().material.set(mats.back());
        }
        RenderQueue q;
        std::uint32_t seed = 12345;
        auto next = [&seed] { return seed = seed * 1664525u + 1013904223u; };
        for (std::uint32_t i = 0; i < 20000; ++i) {
            RenderItem it;
            it.state = &states[next() % std::uint32_t(materials)];
            it.geometry = meshes[next() % 9].get();
            // Five keys whose fields spread over the whole 64 bits.
            const std::uint32_t p = next() % 5;
            it.programKey = ProgramKey::make(ProgramSource(p % 3), p, p * 409, p * 0x01234567u);
            const float depths[] = {0.5f, 1.0f, -0.0f, 0.0f, 3.0f, 3.0f, 1000.0f};
            it.depth = next() % 4 == 0 ? depths[next() % 7] : float(next() % 100000) * 0.01f;
            it.depthBucket = it.depth > 1.0f ? std::int8_t(std::ilogb(it.depth)) : 0;
            it.sequence = i;
            q.opaque.push_back(it);
        }
        std::vector<RenderItem> expected = q.opaque;
        std::stable_sort(expected.begin(), expected.end(), [&](const RenderItem& a, const RenderItem& b) {
            if (a.depthBucket != b.depthBucket) return a.depthBucket < b.depthBucket;
            if (a.programKey != b.programKey) return a.programKey < b.programKey;
            const Material* ma = a.state->material.value->get();
            const Material* mb = b.state->material.value->get();
            if (ma != mb) return ma < mb;
            if (a.geometry != b.geometry) return a.geometry < b.geometry;
            return depthKey(a.depth) < depthKey(b.depth); // depth's top 20 bits
        });
        q.sort();
        ASSERT_EQ(q.opaque.size(), expected.size());
        for (std::size_t i = 0; i < expected.size(); ++i)
            ASSERT_EQ(q.opaque[i].sequence, expected[i].sequence) << i;
    }
}

TEST(Queue, TransparentBackToFrontAndStable) {
    auto cam = perspectiveCamera();
    const float zs[] = {-10, -40, -20, -40, -30};
    for (int i = 0; i < 5; ++i) {
        auto t = Transform::create(glm::translate(glm::mat4(1.0f), {0, 0, zs[i]}));
        auto b = unitBox("t" + std::to_string(i));
        b->getOrCreateStateSet().blend.set(BlendMode::Alpha);
        t->addChild(b);
        cam->addChild(t);
    }
    RenderQueue q;
    CullVisitor cv(*cam, q);
    cv.run(*cam);
    q.sort();
    std::string order;
    for (auto& it : q.transparent)
        order += it.geometry->name + " ";
    EXPECT_EQ(order, "t1 t3 t4 t2 t0 "); // ties (t1, t3 at 40 m) keep cull order
    EXPECT_TRUE(q.opaque.empty());
    // From the other side the order flips.
    cam->viewMatrix = glm::lookAt(glm::vec3(0, 0, -50), glm::vec3(0, 0, 0), glm::vec3(0, 1, 0));
    RenderQueue q2;
    CullVisitor cv2(*cam, q2);
    cv2.run(*cam);
    q2.sort();
    order.clear();
    for (auto& it : q2.transparent)
        order += it.geometry->name + " ";
    EXPECT_EQ(order, "t0 t2 t4 t1 t3 ");
}

TEST(Effects, ItemsRecordEffectsAboveThemInnerWins) {
    auto cam = perspectiveCamera();
    auto outer = std::make_shared<TestEffect>("tint", "tint_outer", 5);
    auto fog = std::make_shared<TestEffect>("fog", "fog_a", 1);
    auto inner = std::make_shared<TestEffect>("tint", "tint_inner", 5);
    auto t = Transform::create(glm::translate(glm::mat4(1.0f), {0, 0, -10}));
    auto plain = unitBox("plain"), deep = unitBox("deep"), mid = unitBox("mid");
    cam->addChild(t);
    t->addChild(plain);
    t->addChild(outer);
    outer->addChild(mid);
    outer->addChild(fog);
    fog->addChild(inner);
    inner->addChild(deep);
    RenderQueue q;
    CullVisitor cv(*cam, q);
    cv.run(*cam);
    auto effectsOf = [&](const std::string& name) {
        std::string s;
        for (auto& it : q.opaque)
            if (it.geometry->name == name)
                for (auto* e : q.effectSets[it.effectSet].effects)
                    s += e->snippet().name + " ";
        return s;
    };
    EXPECT_EQ(effectsOf("plain"), "");
    EXPECT_EQ(effectsOf("mid"), "tint_outer ");
    EXPECT_EQ(effectsOf("deep"), "fog_a tint_inner "); // inner tint replaced outer; sorted by order
    inner->enabled = false;
    RenderQueue q2;
    CullVisitor cv2(*cam, q2);
    cv2.run(*cam);
    for (auto& it : q2.opaque)
        if (it.geometry->name == "deep") {
            EXPECT_EQ(q2.effectSets[it.effectSet].effects.size(), 2u);
        }
}

TEST(Camera, BadParametersAreRefused) {
    auto c = Camera::create();
    EXPECT_THROW(c->setPerspective(0.0f, 1.0f, 10.0f), std::invalid_argument);
    EXPECT_THROW(c->setPerspective(45.0f, -1.0f, 10.0f), std::invalid_argument);
    EXPECT_THROW(c->setPerspective(45.0f, 1.0f, 0.5f), std::invalid_argument);
    EXPECT_THROW(c->setPerspective(std::nanf(""), 1.0f, 10.0f), std::invalid_argument);
    EXPECT_THROW(c->setViewport(0, 0, 0, 10), std::invalid_argument);
    EXPECT_THROW(c->setLookAt({0, 0, 0}, {0, 0, 0}), std::invalid_argument);
    c->setPerspective(45.0f, 1.0f, 10.0f);
    EXPECT_FLOAT_EQ(c->zFar(), 10.0f);
}

TEST(Geometry, ValidateNamesTheProblem) {
    auto g = unitBox("crate");
    g->indices.push_back(999);
    try {
        g->validate();
        FAIL();
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("'crate' index"), std::string::npos) << e.what();
    }
    auto h = unitBox("mesh");
    h->normals.pop_back();
    EXPECT_THROW(h->validate(), std::invalid_argument);
}

TEST(Update, CallbacksRunOncePerVisitWithTheClock) {
    auto root = named("root");
    auto child = named("child");
    root->addChild(child);
    int calls = 0;
    double seen = 0.0;
    child->updateCallback = [&](Node& n, UpdateVisitor& uv) {
        ++calls;
        seen = uv.simulationTime;
        EXPECT_EQ(n.name, "child");
        EXPECT_EQ(uv.nodePath.back(), &n); // the path ends at the node being updated
    };
    UpdateVisitor uv;
    uv.simulationTime = 2.5;
    root->accept(uv);
    EXPECT_EQ(calls, 1);
    EXPECT_DOUBLE_EQ(seen, 2.5);
    child->nodeMask = 0; // masked subtrees are not updated
    uv.traversalMask = 1;
    root->accept(uv);
    EXPECT_EQ(calls, 1);
}

TEST(Camera, ViewportRefreshesOnlyTheProjectionSetPerspectiveMade) {
    auto c = Camera::create();
    c->setViewport(0, 0, 100, 100);
    c->setPerspective(60.0f, 1.0f, 100.0f);
    c->setViewport(0, 0, 200, 100); // aspect 2: the perspective follows
    EXPECT_TRUE(c->perspective());
    EXPECT_NEAR(c->projectionMatrix[1][1] / c->projectionMatrix[0][0], 2.0f, 1e-5f);
    const glm::mat4 ortho = glm::ortho(-1.0f, 1.0f, -1.0f, 1.0f, 0.1f, 10.0f);
    c->projectionMatrix = ortho; // an application's own projection survives resizes
    EXPECT_FALSE(c->perspective());
    c->setViewport(0, 0, 64, 48);
    EXPECT_EQ(c->projectionMatrix, ortho);
}

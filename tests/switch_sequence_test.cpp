// Switch, Sequence and LOD in distance mode: which children the cull, update and intersection
// visitors reach, Sequence timing against hand-computed frames, and setters that refuse bad values.
#include <sgfx/Camera.h>
#include <sgfx/CullVisitor.h>
#include <sgfx/Geometry.h>
#include <sgfx/Group.h>
#include <sgfx/LOD.h>
#include <sgfx/Queries.h>
#include <sgfx/Sequence.h>
#include <sgfx/Shapes.h>
#include <sgfx/Switch.h>
#include <sgfx/Visitors.h>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

using namespace sgfx;

namespace {

// A box of edge `size` centred at the origin (its top at size / 2), counting its updates.
std::shared_ptr<Geometry> box(const std::string& name, float size = 1.0f, int* updates = nullptr) {
    auto g = shapes::box(glm::vec3(size));
    g->name = name;
    if (updates) g->updateCallback = [updates](Node&, UpdateVisitor&) { ++*updates; };
    return g;
}

std::shared_ptr<Camera> camera90() {
    auto c = Camera::create();
    c->setViewport(0, 0, 100, 100);
    c->setPerspective(90.0f, 0.1f, 1000.0f);
    return c;
}

std::string queued(Camera& cam) {
    RenderQueue q;
    CullVisitor cv(cam, q);
    cv.run(cam);
    std::string names;
    for (const auto& it : q.opaque)
        names += it.geometry->name + " ";
    return names;
}

// Names of the geometries an AllChildren visitor reaches.
struct AllNames : NodeVisitor {
    AllNames()
        : NodeVisitor(Mode::AllChildren) {}
    void apply(Geometry& g) override { names += g.name + " "; }
    std::string names;
};

template <class F> void expectRefused(F&& f, const std::string& node, const std::string& part) {
    try {
        f();
        ADD_FAILURE() << "no exception for " << part;
    } catch (const std::logic_error& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find(node), std::string::npos) << what;
        EXPECT_NE(what.find(part), std::string::npos) << what;
    }
}

} // namespace

TEST(Switch, CullUpdateAndQueriesVisitOnlyChildrenThatAreOn) {
    int updates[3] = {0, 0, 0};
    auto sw = Switch::create();
    sw->addChild(box("small", 1.0f, &updates[0]));
    sw->addChild(box("middle", 2.0f, &updates[1]));
    sw->addChild(box("large", 4.0f, &updates[2]), false);
    auto cam = camera90();
    auto root = Group::create();
    root->addChild(sw);
    cam->addChild(root);
    cam->setLookAt({0, -20, 0}, {0, 0, 0});
    EXPECT_EQ(queued(*cam), "small middle ");
    UpdateVisitor uv;
    cam->accept(uv);
    EXPECT_EQ(updates[0], 1);
    EXPECT_EQ(updates[1], 1);
    EXPECT_EQ(updates[2], 0);
    // Queries walk the children that are on, through the root's index and from the switch itself.
    EXPECT_NEAR(heightOfTerrain(*root, 0.1, 0.1).value_or(-1.0), 1.0, 1e-6);
    sw->setSingleChildOn(2);
    EXPECT_EQ(queued(*cam), "large ");
    EXPECT_NEAR(heightOfTerrain(*root, 0.1, 0.1).value_or(-1.0), 2.0, 1e-6);
    EXPECT_NEAR(heightOfTerrain(*sw, 0.1, 0.1).value_or(-1.0), 2.0, 1e-6);
    sw->setAllChildrenOff();
    EXPECT_EQ(queued(*cam), "");
    EXPECT_FALSE(heightOfTerrain(*root, 0.1, 0.1).has_value());
    sw->setAllChildrenOn();
    EXPECT_EQ(queued(*cam), "small middle large ");
    AllNames all;
    sw->setValue(0, false);
    sw->accept(all);
    EXPECT_EQ(all.names, "small middle large "); // AllChildren visitors see every child
}

TEST(Switch, BoundCoversChildrenThatAreOnAndValuesFollowChildren) {
    auto sw = Switch::create();
    sw->name = "switch";
    auto small = box("small", 2.0f), large = box("large", 8.0f);
    sw->addChild(small);
    sw->addChild(large);
    EXPECT_NEAR(sw->bound().radius, large->bound().radius, 1e-5f);
    sw->setValue(1, false); // dirties the bound, as OSG's does
    EXPECT_NEAR(sw->bound().radius, small->bound().radius, 1e-5f);
    sw->setNewChildDefault(false);
    sw->insertChild(0, box("new"));
    ASSERT_EQ(sw->values().size(), 3u);
    EXPECT_FALSE(sw->value(0));
    EXPECT_TRUE(sw->value(1));
    EXPECT_FALSE(sw->value(2));
    EXPECT_TRUE(sw->removeChild(small.get()));
    EXPECT_EQ(sw->values(), (std::vector<bool>{false, false}));
    expectRefused([&] { sw->setValue(2, true); }, "'switch'", "no child 2");
    expectRefused([&] { sw->setSingleChildOn(7); }, "'switch'", "no child 7");
    EXPECT_EQ(sw->values(), (std::vector<bool>{false, false})); // unchanged
}

namespace {
// Advances `s` to simulation time t with an update visitor and returns the shown child.
int at(Sequence& s, double t) {
    UpdateVisitor uv;
    uv.simulationTime = t;
    s.accept(uv);
    return s.value();
}

std::shared_ptr<Sequence> sequence(std::initializer_list<double> times) {
    auto s = Sequence::create();
    s->name = "flipbook";
    int i = 0;
    for (double t : times)
        s->addChild(box("f" + std::to_string(i++)), t);
    return s;
}
} // namespace

TEST(Sequence, LoopTimingAcrossCycles) {
    auto s = sequence({1.0, 2.0, 3.0}); // one cycle: f0 [0,1) f1 [1,3) f2 [3,6)
    EXPECT_EQ(at(*s, 5.0), -1) << "stopped until started, as in OSG";
    s->setMode(Sequence::Mode::Start);
    const double t0 = 10.0; // the clock starts at the first update after Start
    for (auto [t, expected] : {std::pair{0.0, 0},
                               {0.75, 0},
                               {1.0, 1},
                               {2.75, 1},
                               {3.0, 2},
                               {5.75, 2},
                               {6.0, 0},
                               {7.5, 1},
                               {12.25, 0},
                               {15.5, 2}})
        EXPECT_EQ(at(*s, t0 + t), expected) << "t = " << t;
    // Speed 2 from here on: 0.25 s more is 0.5 s of the sequence (15.5 + 0.5 = 16 = 6·2 + 4: f2).
    s->setDuration(2.0);
    EXPECT_EQ(at(*s, t0 + 15.75), 2);
    EXPECT_EQ(at(*s, t0 + 16.75), 0); // 18: a cycle boundary
}

TEST(Sequence, SwingRepeatsReverseAndPause) {
    auto s = sequence({1.0, 1.0, 1.0, 1.0});
    s->setInterval(Sequence::LoopMode::Swing, 0, -1); // 0 1 2 3 2 1 | 0 1 ...
    s->setDuration(1.0, 2);                           // two swings, then home at f0
    s->setMode(Sequence::Mode::Start);
    // The clock starts at the first update after Start (t = 0.5).
    for (auto [t, expected] :
         {std::pair{0.5, 0}, {3.5, 3}, {4.5, 2}, {5.5, 1}, {6.5, 0}, {9.5, 3}, {11.5, 1}})
        EXPECT_EQ(at(*s, t), expected) << "t = " << t;
    EXPECT_EQ(s->mode(), Sequence::Mode::Start);
    EXPECT_EQ(at(*s, 12.0), 1); // the clock started at the first update, 0.5
    EXPECT_EQ(at(*s, 12.5), 0); // 2 cycles of 6 s done
    EXPECT_EQ(s->mode(), Sequence::Mode::Stop);
    EXPECT_EQ(at(*s, 13.5), 0);
    // Backwards loop 3..1, paused for 100 s in the middle.
    s->setInterval(Sequence::LoopMode::Loop, 3, 1);
    s->setDuration(1.0, -1);
    s->setMode(Sequence::Mode::Start);
    EXPECT_EQ(at(*s, 20.0), 3);
    EXPECT_EQ(at(*s, 21.5), 2);
    s->setMode(Sequence::Mode::Pause);
    EXPECT_EQ(at(*s, 50.0), 2);
    s->setMode(Sequence::Mode::Resume);
    EXPECT_EQ(at(*s, 121.5), 2); // the clock restarts here: still 1.5 s played
    EXPECT_EQ(at(*s, 122.0), 1);
    EXPECT_EQ(at(*s, 123.0), 3);
    EXPECT_NEAR(s->elapsed(), 3.0, 1e-12);
}

TEST(Sequence, VisitorsReachOnlyTheShownChild) {
    int updates[2] = {0, 0};
    auto s = Sequence::create();
    s->addChild(box("low", 1.0f, &updates[0]), 1.0);
    s->addChild(box("high", 4.0f, &updates[1]), 1.0);
    auto root = Group::create();
    root->addChild(s);
    auto cam = camera90();
    cam->addChild(root);
    cam->setLookAt({0, -20, 0}, {0, 0, 0});
    EXPECT_EQ(queued(*cam), "");
    s->setMode(Sequence::Mode::Start);
    UpdateVisitor uv;
    uv.simulationTime = 0.5;
    cam->accept(uv);
    EXPECT_EQ(updates[0], 1);
    EXPECT_EQ(updates[1], 0);
    EXPECT_EQ(queued(*cam), "low ");
    EXPECT_NEAR(heightOfTerrain(*root, 0.1, 0.1).value_or(-1.0), 0.5, 1e-6);
    uv.simulationTime = 1.5;
    cam->accept(uv);
    EXPECT_EQ(updates[0], 1);
    EXPECT_EQ(updates[1], 1);
    EXPECT_EQ(queued(*cam), "high ");
    EXPECT_NEAR(heightOfTerrain(*root, 0.1, 0.1).value_or(-1.0), 2.0, 1e-6);
    AllNames all;
    s->accept(all);
    EXPECT_EQ(all.names, "low high ");
}

TEST(Sequence, BadSettersAreRefusedAndKeepTheOldState) {
    auto s = sequence({1.0, 2.0});
    s->setInterval(Sequence::LoopMode::Swing, 1, 0);
    s->setDuration(3.0, 4);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    expectRefused([&] { s->setTime(0, -1.0); }, "'flipbook'", "time");
    expectRefused([&] { s->setTime(1, nan); }, "'flipbook'", "finite");
    expectRefused([&] { s->setTime(2, 1.0); }, "'flipbook'", "no child 2");
    expectRefused([&] { s->addChild(box("x"), std::numeric_limits<double>::infinity()); }, "'flipbook'",
                  "finite");
    expectRefused([&] { s->setDefaultTime(-0.5); }, "'flipbook'", "default time");
    expectRefused([&] { s->setInterval(Sequence::LoopMode::Loop, 0, 2); }, "'flipbook'", "interval");
    expectRefused([&] { s->setInterval(Sequence::LoopMode::Loop, -2, 0); }, "'flipbook'", "interval");
    expectRefused([&] { s->setInterval(Sequence::LoopMode(7), 0, 1); }, "'flipbook'", "loop mode");
    expectRefused([&] { s->setDuration(0.0, 1); }, "'flipbook'", "speed");
    expectRefused([&] { s->setDuration(1.0, -2); }, "'flipbook'", "repeats");
    expectRefused([&] { s->setMode(Sequence::Mode(9)); }, "'flipbook'", "mode 9");
    EXPECT_EQ(s->numChildren(), 2u);
    EXPECT_EQ(s->time(0), 1.0);
    EXPECT_EQ(s->time(1), 2.0);
    EXPECT_EQ(s->defaultTime(), 1.0);
    EXPECT_EQ(s->loopMode(), Sequence::LoopMode::Swing);
    EXPECT_EQ(s->begin(), 1);
    EXPECT_EQ(s->end(), 0);
    EXPECT_EQ(s->speed(), 3.0);
    EXPECT_EQ(s->repeats(), 4);
    EXPECT_EQ(s->mode(), Sequence::Mode::Stop);
}

// ---------------------------------------------------------------- LOD by distance
namespace {
// "near" within 10 of the user sphere's centre (LOD frame), "far" beyond.
std::shared_ptr<LOD> distanceLod(const glm::vec3& centre = glm::vec3(0.0f)) {
    auto lod = LOD::create();
    lod->name = "lod";
    lod->setRangeMode(LOD::RangeMode::DistanceFromEye);
    lod->addChild(box("near"), 0.0f, 10.0f);
    lod->addChild(box("far"), 10.0f, std::numeric_limits<float>::infinity());
    lod->setUserSphere(centre, 1.0f);
    return lod;
}
} // namespace

TEST(LodDistance, ChildByDistanceFromTheEyeEvenUnderAScaledTransform) {
    auto cam = camera90();
    auto t = Transform::create();
    t->addChild(distanceLod());
    cam->addChild(t);
    // Distance, not size: the projection does not matter, and turning the camera does not either.
    for (auto [eye, expected] : {std::pair{glm::vec3(0, -9.9f, 0), "near "},
                                 {glm::vec3(0, -10.1f, 0), "far "},
                                 {glm::vec3(6, -7.9f, 0), "near "},
                                 {glm::vec3(6, -8.1f, 0), "far "}}) {
        cam->setLookAt(eye, {0, 0, 0});
        EXPECT_EQ(queued(*cam), expected) << eye.x << " " << eye.y;
    }
    // Translated by 5 and scaled by 2: the centre is at x = 5 and the ranges, in the LOD's frame
    // as in OSG, reach 20 m in the world.
    t->setMatrix(glm::scale(glm::translate(glm::mat4(1.0f), {5, 0, 0}), glm::vec3(2.0f)));
    cam->setLookAt({5, -19.9f, 0}, {5, 0, 0});
    EXPECT_EQ(queued(*cam), "near ");
    cam->setLookAt({5, -20.1f, 0}, {5, 0, 0});
    EXPECT_EQ(queued(*cam), "far ");
    cam->setLookAt({-14.9f, 0, 0}, {5, 0, 0}); // along x: 19.9 from the centre
    EXPECT_EQ(queued(*cam), "near ");
}

TEST(LodDistance, BoundCentreByDefaultAndReferenceViewInTheShadowCull) {
    auto lod = LOD::create();
    lod->setRangeMode(LOD::RangeMode::DistanceFromEye);
    auto offset = Transform::create(glm::translate(glm::mat4(1.0f), {30, 0, 0}));
    offset->addChild(box("fine"));
    auto coarse = Transform::create(glm::translate(glm::mat4(1.0f), {30, 0, 0}));
    coarse->addChild(box("coarse", 3.0f)); // its top at 1.5, the fine one's at 0.5
    lod->addChild(offset, 0.0f, 10.0f);
    lod->addChild(coarse, 10.0f, 1e9f);
    auto cam = camera90();
    cam->addChild(lod);
    cam->setLookAt({30, -9.9f, 0}, {30, 0, 0}); // the bound's centre is at x = 30
    EXPECT_EQ(queued(*cam), "fine ");
    cam->setLookAt({0, -9.9f, 0}, {30, 0, 0});
    EXPECT_EQ(queued(*cam), "coarse ");
    // A light 100 m away measures from the reference (camera) view: the camera's level.
    const glm::mat4 lightView = glm::lookAt(glm::vec3(30, 0, 100), glm::vec3(30, 0, 0), glm::vec3(0, 1, 0));
    const glm::mat4 lightProj = glm::ortho(-50.0f, 50.0f, -50.0f, 50.0f, 1.0f, 300.0f);
    auto shadowCull = [&](bool reference) {
        RenderQueue q;
        CullVisitor cv(CullView{lightView, lightProj, 100, true}, q);
        if (reference)
            cv.setReferenceView(glm::lookAt(glm::vec3(30, -5, 0), glm::vec3(30, 0, 0), glm::vec3(0, 0, 1)),
                                cam->projectionMatrix, 100);
        auto holder = Group::create(); // runFrom visits the node's children
        holder->addChild(lod);
        cv.runFrom(*holder, glm::mat4(1.0f), q.states.front());
        std::string names;
        for (const auto& it : q.opaque)
            names += it.geometry->name + " ";
        return names;
    };
    EXPECT_EQ(shadowCull(false), "coarse ");
    EXPECT_EQ(shadowCull(true), "fine ");
    // The finest level for queries is the nearest one in distance mode.
    EXPECT_EQ(lod->fineness(0), -0.0f);
    EXPECT_NEAR(heightOfTerrain(*lod, 30.1, 0.1).value_or(-1.0), 0.5, 1e-6);
    expectRefused([&] { lod->setRangeMode(LOD::RangeMode(5)); }, "LOD", "range mode");
    EXPECT_EQ(lod->rangeMode(), LOD::RangeMode::DistanceFromEye);
}

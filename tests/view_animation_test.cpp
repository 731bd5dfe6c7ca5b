// sgfx-view's animation controls (demos/view/AnimationControls.cpp), without a window: --time and
// --animation's choice and pose, the listing, and the panel's timeline as player calls. No GL.
#include "AnimationControls.h"

#include <sgfx/Animation.h>
#include <sgfx/Group.h>
#include <sgfx/Visitors.h>

#include <gtest/gtest.h>

#include <string>
#include <vector>

using namespace sgfx;

namespace {

// An AnimatedGroup whose animations move one child along x: "walk" to 2 over 2 s, then "run" to 8
// over 4 s. The loader starts animation 0, as it does here.
struct Model {
    std::shared_ptr<Group> root = Group::create(); // the viewer's wrapping group
    std::shared_ptr<AnimatedGroup> animated = AnimatedGroup::create();
    std::shared_ptr<Transform> node = Transform::create();
    Model() {
        root->addChild(animated);
        animated->addChild(node);
        AnimationPlayer& p = animated->player();
        AnimationTarget target;
        target.transform = node;
        p.targets.push_back(target);
        const std::pair<const char*, float> moves[] = {{"walk", 2.0f}, {"run", 8.0f}};
        for (auto [name, x] : moves) {
            Animation a;
            a.name = name;
            AnimationSampler s;
            s.times = {0.0f, x == 2.0f ? 2.0f : 4.0f};
            s.values = {0, 0, 0, x, 0, 0};
            a.samplers.push_back(s);
            a.channels.push_back({0, 0, AnimationPath::Translation});
            p.animations.push_back(a);
        }
        p.play(0);
    }
    AnimationPlayer& player() { return animated->player(); }
    // One update traversal at simulation time `sim`, as Viewer::update runs it.
    float xAt(double sim) {
        UpdateVisitor v;
        v.simulationTime = sim;
        root->accept(v);
        return node->matrix()[3].x;
    }
};

TEST(ViewAnimation, FindsPlayersUnderWrappingGroups) {
    Model a, b;
    auto top = Group::create();
    top->addChild(a.root);
    top->addChild(b.root);
    const auto players = view::findPlayers(*top);
    ASSERT_EQ(players.size(), 2u);
    EXPECT_EQ(players[0], &a.player());
    EXPECT_EQ(players[1], &b.player());
    EXPECT_TRUE(view::findPlayers(*Group::create()).empty());
}

TEST(ViewAnimation, ListsIndexNameDurationChannels) {
    Model m;
    const std::string list = view::listAnimations(view::findPlayers(*m.root));
    EXPECT_EQ(list, "  0  'walk'  2.000 s, 1 channels\n  1  'run'  4.000 s, 1 channels\n");
}

TEST(ViewAnimation, TimeHoldsThePoseOverLaterFrames) {
    Model m;
    const std::string what = view::chooseAnimation(view::findPlayers(*m.root), std::nullopt, 0.5);
    EXPECT_EQ(what, "animation 0 'walk' (2.000 s) at 0.5 s");
    // Headless frames (TAA settles over 30) advance the simulation clock; the pose stays.
    for (int f = 1; f <= 30; ++f)
        EXPECT_NEAR(m.xAt(f / 60.0), 0.5f, 1e-6f) << "frame " << f;
    EXPECT_FALSE(m.player().playing());
}

TEST(ViewAnimation, AnimationByNameOrIndex) {
    Model m;
    const auto players = view::findPlayers(*m.root);
    EXPECT_EQ(view::chooseAnimation(players, std::string("run"), 1.0), "animation 1 'run' (4.000 s) at 1 s");
    EXPECT_NEAR(m.xAt(0.1), 2.0f, 1e-6f);
    EXPECT_EQ(view::chooseAnimation(players, std::string("0"), 3.0),
              "animation 0 'walk' (2.000 s) at 3 s (1 s into the loop)");
    EXPECT_NEAR(m.xAt(0.2), 1.0f, 1e-6f);
    // Without a time it plays the animation from its start.
    EXPECT_EQ(view::chooseAnimation(players, std::string("1"), std::nullopt), "animation 1 'run' (4.000 s)");
    EXPECT_TRUE(m.player().playing());
    EXPECT_EQ(m.player().current(), 1);
    EXPECT_EQ(view::chooseAnimation(players, std::nullopt, std::nullopt), "");
}

TEST(ViewAnimation, UnknownAnimationListsThem) {
    Model m;
    const auto players = view::findPlayers(*m.root);
    for (const char* bad : {"nosuch", "2", "-1"}) {
        try {
            view::chooseAnimation(players, std::string(bad), 0.5);
            ADD_FAILURE() << bad << " accepted";
        } catch (const view::AnimationChoiceError& e) {
            const std::string msg = e.what();
            EXPECT_NE(msg.find(std::string("--animation: no animation '") + bad + "'"), std::string::npos)
                << msg;
            EXPECT_NE(msg.find("  0  'walk'  2.000 s"), std::string::npos) << msg;
            EXPECT_NE(msg.find("  1  'run'  4.000 s"), std::string::npos) << msg;
        }
    }
    EXPECT_THROW(view::chooseAnimation({}, std::nullopt, 0.5), view::AnimationChoiceError);
}

TEST(ViewAnimation, ControlsPlayPauseScrub) {
    Model m;
    view::AnimationControls c;
    c.attach(*m.root);
    ASSERT_EQ(c.entries().size(), 2u);
    EXPECT_EQ(c.entries()[1].label, "run");
    EXPECT_EQ(c.entries()[1].duration, 4.0);
    EXPECT_EQ(c.selected(), 0);
    EXPECT_NEAR(m.xAt(0.5), 0.5f, 1e-6f);
    EXPECT_TRUE(c.playing());
    c.togglePlay();
    EXPECT_FALSE(c.playing());
    EXPECT_NEAR(m.xAt(1.0), 0.5f, 1e-6f);
    c.togglePlay();
    EXPECT_NEAR(m.xAt(1.25), 0.75f, 1e-6f);

    // Dragging the slider pauses and seeks; releasing resumes what played.
    c.beginScrub();
    EXPECT_FALSE(c.playing());
    c.scrub(1.5);
    EXPECT_NEAR(m.xAt(2.0), 1.5f, 1e-6f);
    EXPECT_DOUBLE_EQ(c.time(), 1.5);
    c.scrub(0.25);
    EXPECT_NEAR(m.xAt(3.0), 0.25f, 1e-6f);
    c.endScrub();
    EXPECT_TRUE(c.playing());
    EXPECT_NEAR(m.xAt(3.5), 0.75f, 1e-6f);
    // A paused player stays paused after a scrub.
    c.togglePlay();
    c.scrub(1.0);
    c.endScrub();
    EXPECT_FALSE(c.playing());
    EXPECT_NEAR(m.xAt(4.0), 1.0f, 1e-6f);
}

TEST(ViewAnimation, ControlsSelectSpeedLoop) {
    Model m;
    view::AnimationControls c;
    c.attach(*m.root);
    c.next();
    EXPECT_EQ(c.selected(), 1);
    EXPECT_EQ(m.player().current(), 1);
    EXPECT_DOUBLE_EQ(c.duration(), 4.0);
    EXPECT_NEAR(m.xAt(1.0), 2.0f, 1e-6f); // run: 2 m/s from 0 at the last update (0)
    c.setSpeed(0.5);
    EXPECT_DOUBLE_EQ(c.speed(), 0.5);
    EXPECT_NEAR(m.xAt(2.0), 3.0f, 1e-6f);
    // Clamp from 1.5 s into the run: holds the end instead of wrapping.
    c.setLoop(false);
    EXPECT_FALSE(c.loop());
    EXPECT_NEAR(m.xAt(10.0), 8.0f, 1e-6f);
    c.setLoop(true);
    EXPECT_TRUE(c.loop());
    c.next(); // wraps to the first, keeps playing
    EXPECT_EQ(c.selected(), 0);
    EXPECT_TRUE(c.playing());
    // Paused, a new choice stays paused at its start.
    c.togglePlay();
    c.select(1);
    EXPECT_FALSE(c.playing());
    EXPECT_NEAR(m.xAt(20.0), 0.0f, 1e-6f);
}

TEST(ViewAnimation, ControlsWithoutAnimationsDoNothing) {
    view::AnimationControls c;
    c.attach(*Group::create());
    EXPECT_TRUE(c.empty());
    c.togglePlay();
    c.next();
    c.scrub(1.0);
    c.endScrub();
    c.setSpeed(2.0);
    c.setLoop(false);
    EXPECT_FALSE(c.playing());
    EXPECT_EQ(c.time(), 0.0);
    EXPECT_EQ(c.selected(), -1);
}

} // namespace

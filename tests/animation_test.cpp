// Keyframe animation: samplers against an independent reference (a linear scan through the glTF 2.0
// Appendix C formulas in double precision, slerp from the sine formula), validation messages, the
// player's clock (wrap, speed, seek, pause, determinism), cross-fades and mixing. No GL context.
#include <sgfx/Animation.h>
#include <sgfx/Group.h>
#include <sgfx/Visitors.h>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

using namespace sgfx;

namespace {

// ---------------------------------------------------------------- the reference
struct Ref {
    const AnimationSampler& s;
    std::size_t stride() const {
        return s.interpolation == Interpolation::CubicSpline ? 3 * s.components : s.components;
    }
    // Part 0: in-tangent, 1: value, 2: out-tangent (CubicSpline); plain samplers have values only.
    double at(std::size_t key, std::size_t part, std::size_t i) const {
        const std::size_t off = s.interpolation == Interpolation::CubicSpline ? part * s.components : 0;
        return s.values[key * stride() + off + i];
    }
};

std::vector<double> normalised(std::vector<double> q) {
    double len = 0.0;
    for (double c : q)
        len += c * c;
    len = std::sqrt(len);
    for (double& c : q)
        c /= len;
    return q;
}

// q(s) = sin((1-s)θ)/sinθ a + sin(sθ)/sinθ b, b negated first when a·b < 0 (the short arc).
std::vector<double> slerpRef(std::vector<double> a, std::vector<double> b, double s) {
    double d = 0.0;
    for (int i = 0; i < 4; ++i)
        d += a[std::size_t(i)] * b[std::size_t(i)];
    if (d < 0.0) {
        for (double& c : b)
            c = -c;
        d = -d;
    }
    const double theta = std::acos(std::min(d, 1.0));
    std::vector<double> out(4);
    for (std::size_t i = 0; i < 4; ++i)
        out[i] = theta < 1e-9
                     ? a[i] + s * (b[i] - a[i])
                     : (std::sin((1.0 - s) * theta) * a[i] + std::sin(s * theta) * b[i]) / std::sin(theta);
    return normalised(out);
}

std::vector<double> reference(const AnimationSampler& s, double t, bool rotation) {
    const Ref r{s};
    const std::size_t n = s.components, keys = s.times.size();
    std::vector<double> out(n);
    const auto value = [&](std::size_t k) {
        for (std::size_t i = 0; i < n; ++i)
            out[i] = r.at(k, 1, i);
    };
    if (keys == 1 || t <= s.times.front()) {
        value(0);
    } else if (t >= s.times.back()) {
        value(keys - 1);
    } else {
        std::size_t k = 0;
        while (!(s.times[k] <= t && t < s.times[k + 1]))
            ++k; // linear scan
        const double td = double(s.times[k + 1]) - s.times[k];
        const double u = (t - s.times[k]) / td;
        if (s.interpolation == Interpolation::Step) {
            value(k);
        } else if (s.interpolation == Interpolation::Linear && rotation) {
            std::vector<double> a(4), b(4);
            for (std::size_t i = 0; i < 4; ++i)
                a[i] = r.at(k, 1, i), b[i] = r.at(k + 1, 1, i);
            out = slerpRef(a, b, u);
        } else if (s.interpolation == Interpolation::Linear) {
            for (std::size_t i = 0; i < n; ++i)
                out[i] = (1.0 - u) * r.at(k, 1, i) + u * r.at(k + 1, 1, i);
        } else {
            const double u2 = u * u, u3 = u2 * u;
            for (std::size_t i = 0; i < n; ++i)
                out[i] = (2 * u3 - 3 * u2 + 1) * r.at(k, 1, i) + (u3 - 2 * u2 + u) * td * r.at(k, 2, i) +
                         (-2 * u3 + 3 * u2) * r.at(k + 1, 1, i) + (u3 - u2) * td * r.at(k + 1, 0, i);
        }
    }
    return rotation ? normalised(out) : out;
}

AnimationSampler randomSampler(Interpolation mode, std::size_t components, bool rotation, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> gap(0.1f, 0.7f), value(-2.0f, 2.0f);
    AnimationSampler s;
    s.interpolation = mode;
    s.components = components;
    float t = 0.3f;
    for (int k = 0; k < 7; ++k, t += gap(rng))
        s.times.push_back(t);
    const std::size_t perKey = mode == Interpolation::CubicSpline ? 3 : 1;
    for (std::size_t k = 0; k < s.times.size(); ++k) {
        for (std::size_t part = 0; part < perKey; ++part) {
            std::vector<float> v(components);
            for (float& c : v)
                c = value(rng);
            if (rotation && (part == 1 || perKey == 1)) { // a unit key, every other one negated
                float len = 0.0f;
                for (float c : v)
                    len += c * c;
                for (float& c : v)
                    c /= std::sqrt(len) * (k % 2 ? -1.0f : 1.0f);
            }
            s.values.insert(s.values.end(), v.begin(), v.end());
        }
    }
    return s;
}

// 100 times from half a second before the first key to half a second after the last, plus every key.
void compareWithReference(const AnimationSampler& s, bool rotation, double tolerance) {
    ASSERT_NO_THROW(s.validate());
    std::vector<float> times;
    for (int i = 0; i < 100; ++i)
        times.push_back(s.times.front() - 0.5f +
                        (s.times.back() - s.times.front() + 1.0f) * float(i) / 99.0f);
    times.insert(times.end(), s.times.begin(), s.times.end());
    std::vector<float> out(s.components);
    for (float t : times) {
        s.sample(t, out.data(), rotation);
        const std::vector<double> want = reference(s, t, rotation);
        for (std::size_t i = 0; i < s.components; ++i)
            ASSERT_NEAR(out[i], want[i], tolerance) << "t = " << t << ", component " << i;
    }
}

// ---------------------------------------------------------------- sampler tests
TEST(AnimationSampler, StepMatchesReference) {
    compareWithReference(randomSampler(Interpolation::Step, 3, false, 1), false, 0.0);
}

TEST(AnimationSampler, LinearMatchesReference) {
    compareWithReference(randomSampler(Interpolation::Linear, 3, false, 2), false, 1e-5);
    compareWithReference(randomSampler(Interpolation::Linear, 5, false, 3), false, 1e-5); // morph weights
}

TEST(AnimationSampler, CubicSplineMatchesReference) {
    compareWithReference(randomSampler(Interpolation::CubicSpline, 3, false, 4), false, 2e-5);
}

TEST(AnimationSampler, RotationModesMatchReference) {
    compareWithReference(randomSampler(Interpolation::Step, 4, true, 5), true, 1e-6);
    compareWithReference(randomSampler(Interpolation::Linear, 4, true, 6), true, 2e-5);
    compareWithReference(randomSampler(Interpolation::CubicSpline, 4, true, 7), true, 2e-5);
}

TEST(AnimationSampler, SingleKeyIsConstant) {
    for (Interpolation mode : {Interpolation::Step, Interpolation::Linear, Interpolation::CubicSpline}) {
        AnimationSampler s;
        s.interpolation = mode;
        s.times = {1.5f};
        s.values = mode == Interpolation::CubicSpline ? std::vector<float>{9, 9, 9, 1, 2, 3, 8, 8, 8}
                                                      : std::vector<float>{1, 2, 3};
        for (float t : {-1.0f, 0.0f, 1.5f, 2.0f, 100.0f}) {
            float out[3] = {};
            s.sample(t, out);
            EXPECT_EQ(out[0], 1.0f);
            EXPECT_EQ(out[1], 2.0f);
            EXPECT_EQ(out[2], 3.0f);
        }
    }
}

TEST(AnimationSampler, CubicSplineTangentsAreScaledByTheInterval) {
    // v0 = v1 = 0, b0 = 1, a1 = 0 over td = 2: p(s) = (s^3 - 2s^2 + s) td b0, 0.25 at s = 0.5.
    AnimationSampler s;
    s.interpolation = Interpolation::CubicSpline;
    s.components = 1;
    s.times = {0.0f, 2.0f};
    s.values = {0, 0, 1, 0, 0, 0};
    float out = 0.0f;
    s.sample(1.0f, &out);
    EXPECT_NEAR(out, 0.25f, 1e-6f);
}

TEST(AnimationSampler, CubicSplineDerivativeAtKeysIsTheTangent) {
    // Keys 0.5 to 3.5 s apart (a short interval's third derivative would swamp the difference).
    AnimationSampler s = randomSampler(Interpolation::CubicSpline, 3, false, 8);
    for (float& t : s.times)
        t *= 5.0f;
    const Ref r{s};
    const float h = 2e-3f;
    const auto p = [&](float t, std::size_t i) {
        float out[3];
        s.sample(t, out);
        return double(out[i]);
    };
    for (std::size_t k = 1; k + 1 < s.times.size(); ++k) {
        const float t = s.times[k];
        for (std::size_t i = 0; i < 3; ++i) {
            // Second-order one-sided differences: after the key the out-tangent, before it the in-tangent.
            const double right = (-3 * p(t, i) + 4 * p(t + h, i) - p(t + 2 * h, i)) / (2 * h);
            const double left = (3 * p(t, i) - 4 * p(t - h, i) + p(t - 2 * h, i)) / (2 * h);
            EXPECT_NEAR(right, r.at(k, 2, i), 3e-3) << "key " << k;
            EXPECT_NEAR(left, r.at(k, 0, i), 3e-3) << "key " << k;
        }
    }
}

TEST(AnimationSampler, RotationTakesTheShortArc) {
    // Identity to minus a 90 degree turn about z: the same rotation as +90, so half-way is +45.
    AnimationSampler s;
    s.components = 4;
    const float h = std::sqrt(0.5f);
    s.times = {0.0f, 1.0f};
    s.values = {0, 0, 0, 1, 0, 0, -h, -h};
    float q[4];
    s.sample(0.5f, q, true);
    const double sign = q[3] < 0 ? -1.0 : 1.0;
    EXPECT_NEAR(sign * q[2], std::sin(M_PI / 8), 1e-6);
    EXPECT_NEAR(sign * q[3], std::cos(M_PI / 8), 1e-6);
    EXPECT_NEAR(q[0], 0.0, 1e-7);
}

TEST(AnimationSampler, RotationIsNormalisedInEveryMode) {
    for (Interpolation mode : {Interpolation::Step, Interpolation::Linear, Interpolation::CubicSpline}) {
        AnimationSampler s = randomSampler(mode, 4, true, 9);
        for (float& v : s.values)
            v *= 3.0f; // keys of length 3
        for (int i = 0; i < 50; ++i) {
            float q[4];
            s.sample(s.times.front() + 0.037f * float(i), q, true);
            EXPECT_NEAR(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3], 1.0f, 1e-5f);
        }
    }
}

std::string validationMessage(const AnimationSampler& s) {
    try {
        s.validate();
    } catch (const std::invalid_argument& e) {
        return e.what();
    }
    return "(valid)";
}

TEST(AnimationSampler, ValidationSaysWhatIsWrong) {
    AnimationSampler s;
    s.times = {0.0f, 0.25f, 0.5f, 1.0f};
    s.values.assign(12, 1.0f);
    EXPECT_EQ(validationMessage(s), "(valid)");

    AnimationSampler e = s;
    e.times.clear();
    e.values.clear();
    EXPECT_EQ(validationMessage(e), "no keys");
    e = s;
    e.times[2] = 0.25f;
    EXPECT_EQ(validationMessage(e), "times not increasing at key 2 (0.25 after 0.25)");
    e = s;
    e.times[3] = 0.5f;
    EXPECT_EQ(validationMessage(e), "times not increasing at key 3 (0.5 after 0.5)");
    e = s;
    e.times[2] = NAN;
    EXPECT_EQ(validationMessage(e), "NaN or infinite time at key 2");
    e = s;
    e.times[3] = INFINITY;
    EXPECT_EQ(validationMessage(e), "NaN or infinite time at key 3");
    e = s;
    e.values[5] = NAN;
    EXPECT_EQ(validationMessage(e), "NaN or infinite value at 5");
    e = s;
    e.values.pop_back();
    EXPECT_NE(validationMessage(e).find("11 values for 4 keys of 3 components"), std::string::npos);
    e = s;
    e.interpolation = Interpolation::CubicSpline; // three values per key
    EXPECT_NE(validationMessage(e).find("12 values for 4 keys of 3 components (36 expected"),
              std::string::npos)
        << validationMessage(e);
    e = s;
    e.components = 0;
    EXPECT_NE(validationMessage(e).find("components"), std::string::npos);
    e = s;
    e.times[0] = -1.0f;
    EXPECT_NE(validationMessage(e).find("negative time at key 0"), std::string::npos);
}

TEST(Animation, DurationIsTheLastKeyOfAllSamplers) {
    Animation a;
    EXPECT_EQ(a.duration(), 0.0f);
    a.samplers.resize(2);
    a.samplers[0].times = {0.0f, 1.5f};
    a.samplers[1].times = {0.5f, 2.5f};
    EXPECT_EQ(a.duration(), 2.5f);
}

// ---------------------------------------------------------------- player
AnimationSampler linear3(std::vector<float> times, std::vector<float> values) {
    AnimationSampler s;
    s.times = std::move(times);
    s.values = std::move(values);
    return s;
}

// One animation per entry: translation over keys at 0 and `end` from `from` to `to`.
struct Rig {
    std::shared_ptr<Transform> node = Transform::create();
    AnimationPlayer player;
    explicit Rig(std::vector<std::pair<glm::vec3, glm::vec3>> moves, float end = 2.0f) {
        AnimationTarget target;
        target.transform = node;
        target.name = "node";
        player.targets.push_back(target);
        for (auto [from, to] : moves) {
            Animation a;
            a.name = "move" + std::to_string(player.animations.size());
            a.samplers.push_back(linear3({0.0f, end}, {from.x, from.y, from.z, to.x, to.y, to.z}));
            a.channels.push_back({0, 0, AnimationPath::Translation});
            player.animations.push_back(a);
        }
    }
    glm::vec3 translation() const { return glm::vec3(node->matrix()[3]); }
};

// x = t over [0, 2].
Rig xRig() {
    return Rig({{glm::vec3(0.0f), glm::vec3(2.0f, 0.0f, 0.0f)}});
}

// Switching between Loop and Clamp after several loops keeps the present time (no jump to the end).
TEST(AnimationPlayer, ChangingTheWrapKeepsThePresentTime) {
    Rig r = xRig(); // duration 2
    r.player.play(0);
    r.player.update(6.25); // the fourth loop, 0.25 in
    EXPECT_NEAR(r.player.time(0), 0.25, 1e-12);
    r.player.setWrap(AnimationPlayer::Wrap::Clamp);
    EXPECT_NEAR(r.player.time(0), 0.25, 1e-12);
    EXPECT_NEAR(r.translation().x, 0.25f, 1e-6f);
    r.player.update(6.5);
    EXPECT_NEAR(r.player.time(0), 0.5, 1e-12);
    r.player.setWrap(AnimationPlayer::Wrap::Loop);
    r.player.update(6.75);
    EXPECT_NEAR(r.player.time(0), 0.75, 1e-12);
}

TEST(AnimationPlayer, LoopWraps) {
    Rig r = xRig();
    r.player.play(0);
    r.player.update(2.25);
    EXPECT_EQ(r.player.time(0), 0.25);
    EXPECT_NEAR(r.translation().x, 0.25f, 1e-6f);
    r.player.update(7.5); // three loops and 1.5
    EXPECT_NEAR(r.player.time(0), 1.5, 1e-12);
}

TEST(AnimationPlayer, ClampHoldsTheEnds) {
    Rig r = xRig();
    r.player.setWrap(AnimationPlayer::Wrap::Clamp);
    r.player.play(0);
    r.player.update(3.0);
    EXPECT_EQ(r.player.time(0), 2.0);
    EXPECT_NEAR(r.translation().x, 2.0f, 1e-6f);
    r.player.setSpeed(-1.0); // turns back at once: the clamped time is the anchor
    r.player.update(3.5);
    EXPECT_NEAR(r.player.time(0), 1.5, 1e-12);
    r.player.update(10.0);
    EXPECT_EQ(r.player.time(0), 0.0);
}

TEST(AnimationPlayer, NegativeSpeedPlaysBackwardsAndWraps) {
    Rig r = xRig();
    r.player.setSpeed(-1.0);
    r.player.play(0); // from the end
    r.player.update(0.5);
    EXPECT_NEAR(r.player.time(0), 1.5, 1e-12);
    EXPECT_NEAR(r.translation().x, 1.5f, 1e-6f);
    r.player.update(2.5); // 2 - 2.5 = -0.5: wraps to 1.5, not -0.5
    EXPECT_NEAR(r.player.time(0), 1.5, 1e-12);
    r.player.update(3.75);
    EXPECT_NEAR(r.player.time(0), 0.25, 1e-12);
}

TEST(AnimationPlayer, SeekSpeedPauseResume) {
    Rig r = xRig();
    r.player.play(0);
    r.player.update(1.0);
    r.player.seek(0.5);
    EXPECT_EQ(r.player.time(0), 0.5);
    r.player.update(1.25);
    EXPECT_NEAR(r.player.time(0), 0.75, 1e-12);
    r.player.setSpeed(2.0);
    r.player.update(1.5);
    EXPECT_NEAR(r.player.time(0), 1.25, 1e-12);
    r.player.pause();
    EXPECT_FALSE(r.player.playing());
    r.player.update(5.0);
    EXPECT_NEAR(r.player.time(0), 1.25, 1e-12);
    r.player.seek(0.125); // while paused: the next update shows that frame
    r.player.update(6.0);
    EXPECT_NEAR(r.player.time(0), 0.125, 1e-12);
    EXPECT_NEAR(r.translation().x, 0.125f, 1e-6f);
    r.player.resume();
    r.player.update(6.25);
    EXPECT_NEAR(r.player.time(0), 0.625, 1e-12); // 0.125 + 0.25 s at speed 2
}

// Several paths, several animations, every kind of control call.
Rig richRig() {
    Rig r({{glm::vec3(0.0f), glm::vec3(3.0f, 1.0f, 0.0f)}, {glm::vec3(1.0f), glm::vec3(-2.0f, 0.0f, 4.0f)}},
          1.7f);
    for (std::size_t a = 0; a < 2; ++a) {
        AnimationSampler rot =
            randomSampler(a ? Interpolation::Linear : Interpolation::CubicSpline, 4, true, 20 + unsigned(a));
        AnimationSampler scale = randomSampler(Interpolation::Step, 3, false, 30 + unsigned(a));
        for (float& v : scale.values)
            v = 1.5f + 0.25f * v;
        r.player.animations[a].samplers.push_back(rot);
        r.player.animations[a].samplers.push_back(scale);
        r.player.animations[a].channels.push_back({1, 0, AnimationPath::Rotation});
        r.player.animations[a].channels.push_back({2, 0, AnimationPath::Scale});
    }
    return r;
}

TEST(AnimationPlayer, ReplayAtTheSameSimulationTimesIsBitIdentical) {
    Rig a = richRig(), b = richRig();
    // Control calls take effect at the last update's simulation time, so both players are updated
    // at the times of the calls; `a` also every 1/60 s in between, `b` only once more at the end.
    const auto control = [](AnimationPlayer& p, int frame) {
        if (frame == 0) p.play(0), p.setSpeed(1.3);
        if (frame == 60) p.crossFade(1, 0.75);
        if (frame == 150) p.setSpeed(-0.7);
        if (frame == 180) p.pause();
        if (frame == 200) p.seek(0.4), p.resume();
        if (frame == 240) p.setWeight(0, 0.3f);
    };
    const int last = 330;
    for (int frame = 0; frame <= last; ++frame) {
        const double sim = frame / 60.0;
        a.player.update(sim);
        control(a.player, frame);
        const bool callFrame =
            frame == 0 || frame == 60 || frame == 150 || frame == 180 || frame == 200 || frame == 240;
        if (callFrame || frame == last) {
            b.player.update(sim);
            control(b.player, frame);
        }
    }
    EXPECT_EQ(a.player.time(0), b.player.time(0));
    EXPECT_EQ(a.player.time(1), b.player.time(1));
    EXPECT_EQ(a.player.weight(0), b.player.weight(0));
    EXPECT_EQ(a.player.weight(1), b.player.weight(1));
    EXPECT_EQ(std::memcmp(&a.node->matrix(), &b.node->matrix(), sizeof(glm::mat4)), 0);
    EXPECT_GT(a.player.weight(1), 0.9f); // the fade ran
    EXPECT_NE(a.node->matrix(), glm::mat4(1.0f));
}

TEST(AnimationPlayer, CrossFadeIsContinuous) {
    // A: x from 0 to 4 over 4 s; B: y from 2 to -2 over 4 s.
    Rig r({{glm::vec3(0.0f), glm::vec3(4.0f, 0.0f, 0.0f)},
           {glm::vec3(0.0f, 2.0f, 0.0f), glm::vec3(0.0f, -2.0f, 0.0f)}},
          4.0f);
    const double dt = 1.0 / 240.0, fadeAt = 1.0, fade = 0.5;
    // Per step: |A'| + |B'| + |B - A| / fade (|B - A| <= 3 here), a little slack for rounding.
    const double bound = (1.0 + 1.0 + 3.0 / fade) * dt * 1.001;
    r.player.play(0);
    glm::vec3 previous{0.0f};
    for (int i = 0; i <= 480; ++i) {
        const double sim = i * dt;
        r.player.update(sim);
        if (i == 240) {
            ASSERT_EQ(sim, fadeAt);
            r.player.crossFade(1, fade);
            r.player.update(sim);
            EXPECT_NEAR(glm::distance(r.translation(), glm::vec3(1.0f, 0.0f, 0.0f)), 0.0f, 1e-6f)
                << "A's pose";
        }
        if (i == 300) { // mid-fade
            EXPECT_NEAR(r.player.weight(0), 0.5f, 1e-6f);
            EXPECT_NEAR(r.player.weight(1), 0.5f, 1e-6f);
        }
        if (i == 360) { // the fade's end: B's pose at 0.5 s into it
            EXPECT_NEAR(glm::distance(r.translation(), glm::vec3(0.0f, 1.5f, 0.0f)), 0.0f, 1e-6f)
                << "B's pose";
        }
        if (i > 0) {
            ASSERT_LE(glm::distance(r.translation(), previous), bound) << "jump at " << sim;
        }
        previous = r.translation();
    }
    EXPECT_EQ(r.player.current(), 1);
    EXPECT_EQ(r.player.weight(0), 0.0f);
    EXPECT_EQ(r.player.weight(1), 1.0f);
}

TEST(AnimationPlayer, PauseFreezesAFade) {
    Rig r({{glm::vec3(0.0f), glm::vec3(1.0f)}, {glm::vec3(5.0f), glm::vec3(6.0f)}});
    r.player.play(0);
    r.player.update(1.0);
    r.player.crossFade(1, 1.0);
    r.player.update(1.25);
    EXPECT_NEAR(r.player.weight(1), 0.25f, 1e-6f);
    r.player.pause();
    r.player.update(3.0);
    EXPECT_NEAR(r.player.weight(1), 0.25f, 1e-6f);
    EXPECT_NEAR(r.player.weight(0), 0.75f, 1e-6f);
    r.player.resume();
    r.player.update(3.25);
    EXPECT_NEAR(r.player.weight(1), 0.5f, 1e-6f);
    EXPECT_NEAR(r.player.time(1), 0.5, 1e-12);
    r.player.update(4.0);
    EXPECT_EQ(r.player.weight(1), 1.0f);
    EXPECT_EQ(r.player.weight(0), 0.0f);
}

TEST(AnimationPlayer, CrossFadeOfZeroSecondsIsAHardSwitch) {
    Rig r({{glm::vec3(0.0f), glm::vec3(1.0f)}, {glm::vec3(5.0f), glm::vec3(6.0f)}});
    r.player.play(0);
    r.player.update(1.0);
    r.player.crossFade(1, 0.0);
    r.player.update(1.0);
    EXPECT_EQ(r.player.weight(0), 0.0f);
    EXPECT_EQ(r.player.weight(1), 1.0f);
    EXPECT_NEAR(r.translation().x, 5.0f, 1e-6f);
}

TEST(AnimationPlayer, MixesWithTheRestPose) {
    // Constant keys: A translates to (2,0,0) and turns -90 degrees (negated) about z, B translates to
    // (4,0,0) and drives morph weights {1, 0}; the rest pose is (10,0,0), identity, scale 2.
    Rig r({{glm::vec3(2.0f, 0.0f, 0.0f), glm::vec3(2.0f, 0.0f, 0.0f)},
           {glm::vec3(4.0f, 0.0f, 0.0f), glm::vec3(4.0f, 0.0f, 0.0f)}});
    AnimationTarget& target = r.player.targets[0];
    target.translation = glm::vec3(10.0f, 0.0f, 0.0f);
    target.scale = glm::vec3(2.0f);
    target.weights = {0.2f, 0.4f};
    const float h = std::sqrt(0.5f);
    r.player.animations[0].samplers.push_back(linear3({0.0f}, {0, 0, -h, -h}));
    r.player.animations[0].samplers.back().components = 4;
    r.player.animations[0].channels.push_back({1, 0, AnimationPath::Rotation});
    AnimationSampler weights = linear3({0.0f}, {1.0f, 0.0f});
    weights.components = 2;
    r.player.animations[1].samplers.push_back(weights);
    r.player.animations[1].channels.push_back({1, 0, AnimationPath::Weights});

    r.player.play(0);
    r.player.setWeight(0, 0.5f);
    r.player.update(0.5);
    // Translation (0.5 * 2 + 0.5 * 10) / 1; rotation half-way to 90 degrees: 45; scale from the rest.
    const glm::mat4 want = glm::translate(glm::mat4(1.0f), glm::vec3(6.0f, 0.0f, 0.0f)) *
                           glm::rotate(glm::mat4(1.0f), float(M_PI / 4), glm::vec3(0.0f, 0.0f, 1.0f)) *
                           glm::scale(glm::mat4(1.0f), glm::vec3(2.0f));
    for (int c = 0; c < 4; ++c)
        for (int row = 0; row < 4; ++row)
            EXPECT_NEAR(r.node->matrix()[c][row], want[c][row], 1e-5f) << c << row;
    EXPECT_EQ(target.currentWeights, (std::vector<float>{0.2f, 0.4f})); // no weights channel plays

    r.player.setWeight(0, 0.25f);
    r.player.setWeight(1, 0.5f);
    r.player.update(0.75);
    EXPECT_NEAR(r.translation().x, 0.25f * 2 + 0.5f * 4 + 0.25f * 10, 1e-5f);
    ASSERT_EQ(target.currentWeights.size(), 2u);
    EXPECT_NEAR(target.currentWeights[0], 0.5f * 1 + 0.5f * 0.2f, 1e-6f);
    EXPECT_NEAR(target.currentWeights[1], 0.5f * 0 + 0.5f * 0.4f, 1e-6f);

    r.player.setWeight(0, 1.0f);
    r.player.setWeight(1, 1.0f);
    r.player.update(1.0);
    EXPECT_NEAR(r.translation().x, (2.0f + 4.0f) / 2.0f, 1e-5f); // W = 2: normalised, no rest
    EXPECT_NEAR(target.currentWeights[0], 1.0f, 1e-6f);

    r.player.setWeight(0, 0.0f);
    r.player.setWeight(1, 0.0f);
    r.player.update(1.25); // every weight 0: back to the rest pose
    EXPECT_NEAR(r.translation().x, 10.0f, 1e-6f);
    EXPECT_NEAR(r.node->matrix()[0][0], 2.0f, 1e-6f);
}

TEST(AnimationPlayer, RotationMixAlignsHemispheres) {
    // A turns 90 degrees about z, B the same turn written as -q: mixed, still 90 degrees (a plain
    // sum would cancel).
    Rig r({{glm::vec3(0.0f), glm::vec3(0.0f)}, {glm::vec3(0.0f), glm::vec3(0.0f)}});
    const float h = std::sqrt(0.5f);
    for (std::size_t a = 0; a < 2; ++a) {
        const float sign = a ? -1.0f : 1.0f;
        r.player.animations[a].samplers.push_back(linear3({0.0f}, {0, 0, sign * h, sign * h}));
        r.player.animations[a].samplers.back().components = 4;
        r.player.animations[a].channels.push_back({1, 0, AnimationPath::Rotation});
    }
    r.player.play(0);
    r.player.setWeight(0, 0.5f);
    r.player.setWeight(1, 0.5f);
    r.player.update(0.5);
    const glm::mat4 want = glm::rotate(glm::mat4(1.0f), float(M_PI / 2), glm::vec3(0.0f, 0.0f, 1.0f));
    for (int c = 0; c < 3; ++c)
        for (int row = 0; row < 3; ++row)
            EXPECT_NEAR(r.node->matrix()[c][row], want[c][row], 1e-5f) << c << row;
}

TEST(AnimationPlayer, ArgumentsAreChecked) {
    Rig r({{glm::vec3(0.0f), glm::vec3(1.0f)}, {glm::vec3(0.0f), glm::vec3(1.0f)}});
    try {
        r.player.play(5);
        FAIL() << "no exception";
    } catch (const std::out_of_range& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find("5"), std::string::npos) << m;
        EXPECT_NE(m.find("2 animations"), std::string::npos) << m;
    }
    EXPECT_THROW(r.player.setWeight(2, 1.0f), std::out_of_range);
    EXPECT_THROW(r.player.weight(2), std::out_of_range);
    EXPECT_THROW(r.player.time(2), std::out_of_range);
    EXPECT_THROW(r.player.crossFade(2, 1.0), std::out_of_range);
    EXPECT_THROW(r.player.setWeight(0, NAN), std::invalid_argument);
    EXPECT_THROW(r.player.setWeight(0, -0.5f), std::invalid_argument);
    EXPECT_THROW(r.player.crossFade(0, -1.0), std::invalid_argument);
    EXPECT_THROW(r.player.crossFade(0, NAN), std::invalid_argument);
    EXPECT_THROW(r.player.setSpeed(INFINITY), std::invalid_argument);
    EXPECT_THROW(r.player.seek(0.5), std::logic_error); // nothing playing yet
    EXPECT_EQ(r.player.find("move1"), 1);
    EXPECT_EQ(r.player.find("walk"), -1);
    EXPECT_EQ(r.player.current(), -1);
}

TEST(AnimatedGroup, DrivesATransformInTheUpdateTraversal) {
    auto root = AnimatedGroup::create();
    auto node = Transform::create();
    root->addChild(node);
    AnimationPlayer* player = animationPlayer(*root);
    ASSERT_EQ(player, &root->player());
    EXPECT_EQ(animationPlayer(*node), nullptr);
    AnimationTarget target;
    target.transform = node;
    player->targets.push_back(target);
    Animation a;
    a.samplers.push_back(linear3({0.0f, 2.0f}, {0, 0, 0, 0, 4, 0}));
    a.channels.push_back({0, 0, AnimationPath::Translation});
    player->animations.push_back(a);
    player->play(0);

    UpdateVisitor visitor;
    visitor.simulationTime = 0.5;
    root->accept(visitor);
    EXPECT_NEAR(node->matrix()[3].y, 1.0f, 1e-6f);
    visitor.simulationTime = 1.5;
    root->accept(visitor);
    EXPECT_NEAR(node->matrix()[3].y, 3.0f, 1e-6f);

    // The callback holds the player, not the group: the group goes when its last owner lets go.
    const std::weak_ptr<AnimatedGroup> weak = root;
    root.reset();
    EXPECT_TRUE(weak.expired());
}

} // namespace

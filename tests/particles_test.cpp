// ParticleSystemNode: the GPU simulation against its CPU reference (ParticleMath.h), the closed
// form kinematics, the rotation bounce, shapes' pixel areas, fog and soft-particle pixels against
// their formulas, capacity changes and bad input. Render tests are ≤ 128×128 on OSMesa.
#include "TestUtil.h"

#include <sgfx/CullVisitor.h>
#include <sgfx/Group.h>
#include <sgfx/Shapes.h>
#include <sgfx/gl/Objects.h>
#include <sgfx/nodes/fog/FogNode.h>
#include <sgfx/nodes/particles/ParticleSystemNode.h>
#include <sgfx/nodes/transparency/TransparencyBin.h>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include <cstring>
#include <functional>
#include <numeric>

using namespace sgfx;
using namespace sgfx::test;
using particles::ParticleRecord;

namespace {

constexpr int kSize = 128;

std::unique_ptr<Viewer> viewer(glm::vec3 eye, glm::vec3 at, float fovy = 40.0f) {
    auto v = Viewer::createHeadless(kSize, kSize);
    auto& cam = *v->camera();
    cam.setPerspective(fovy, 0.1f, 200.0f);
    cam.setLookAt(eye, at, {0, 0, 1});
    cam.computeNearFar = false;
    cam.clearColor = {0, 0, 0, 1};
    return v;
}

// One still particle at the emitter's centre (W = H = 0, v0 = a = 0, born at once).
ParticleSettings stillParticle(ParticleShape shape, float size, ParticlePath path) {
    ParticleSettings s;
    s.capacity = 1;
    s.emitter.size = {0.0f, 0.0f};
    s.emitter.acceleration = glm::vec3(0.0f);
    s.emitter.lifetime = 1000.0f;
    s.start = particles::StartMode::Burst;
    s.shape = shape;
    s.sizeStart = s.sizeEnd = size;
    s.path = path;
    return s;
}

// Unlit colour c: the particle shows exactly c (no lights, no ambient).
void emissiveLook(ParticleSystemNode& p, glm::vec3 c, BlendMode blend = BlendMode::Off) {
    auto st = ParticleSystemNode::defaultState();
    auto& m = **st->material.value;
    m.ambient = glm::vec3(0.0f);
    m.diffuse = glm::vec4(0.0f, 0.0f, 0.0f, 1.0f);
    m.emissive = c;
    st->blend.set(blend);
    p.setStateSet(st);
}

int litPixels(const Image& img) {
    int n = 0;
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x)
            n += pixelAt(img, x, y).r > 127;
    return n;
}

// The node's records after `steps` (each queued as its own step) on the GPU.
struct Sim {
    std::unique_ptr<Viewer> v;
    std::shared_ptr<ParticleSystemNode> node;
    std::shared_ptr<Transform> place;
};

Sim makeSim(const ParticleSettings& s, const glm::mat4& placement) {
    Sim sim;
    sim.v = viewer({0, -30, 5}, {0, 0, 0});
    sim.node = ParticleSystemNode::create(s);
    sim.place = Transform::create(placement);
    sim.place->addChild(sim.node);
    sim.v->setSceneData(sim.place);
    return sim;
}

void expectClose(const ParticleRecord& g, const ParticleRecord& c, std::uint32_t i, int step) {
    auto near = [](float a, float b, float absTol) {
        return std::abs(a - b) <= std::max(1e-5f * std::abs(b), absTol);
    };
    ASSERT_TRUE(near(g.age, c.age, 1e-5f))
        << "particle " << i << " step " << step << ": age " << g.age << " vs " << c.age;
    for (int k = 0; k < 3; ++k) {
        ASSERT_TRUE(near(g.position[k], c.position[k], 1e-4f))
            << "particle " << i << " step " << step << " P[" << k << "] " << g.position[k] << " vs "
            << c.position[k];
        ASSERT_TRUE(near(g.velocity[k], c.velocity[k], 1e-5f))
            << "particle " << i << " step " << step << " v[" << k << "] " << g.velocity[k] << " vs "
            << c.velocity[k];
        ASSERT_TRUE(near(g.angles0[k], c.angles0[k], 1e-5f)) << "particle " << i << " r0[" << k << "]";
        ASSERT_TRUE(near(g.angles[k], c.angles[k], 1e-5f))
            << "particle " << i << " step " << step << " r[" << k << "] " << g.angles[k] << " vs "
            << c.angles[k];
    }
}

// The CPU reference's step input for settings s and emitter placement `place` (dt and step unset).
particles::StepInput stepInputFor(const ParticleSettings& s, const glm::mat4& place) {
    particles::StepInput in;
    in.emitterToWorld = place;
    in.emitter = s.emitter;
    in.seed = s.seed;
    in.respawn = s.respawn;
    in.bounce = s.bounce;
    return in;
}

// The CPU reference's records at step 0, from the start mode.
std::vector<ParticleRecord> initialRecords(const ParticleSettings& s, const particles::StepInput& in) {
    std::vector<ParticleRecord> cpu(s.capacity);
    for (std::uint32_t i = 0; i < s.capacity; ++i)
        cpu[i] = particles::initial(in, i, s.start, 0, s.capacity);
    return cpu;
}

struct RefCase {
    ParticleLayout layout;
    particles::Respawn respawn;
    particles::RotationBounce bounce;
    particles::StartMode start;
    ParticleUpdate update = ParticleUpdate::TransformFeedback;
};

class GpuMatchesCpu : public ::testing::TestWithParam<RefCase> {};

} // namespace

// ---------------------------------------------------------------- CPU reference alone
TEST(ParticleMath, RotationStaysInRangeAndTurnsAtBothEnds) {
    for (const auto mode : {particles::RotationBounce::Reflect, particles::RotationBounce::Clamp}) {
        const float krot = 0.7f, kvel = 1.3f;
        float r = 0.3f;
        int flipsLow = 0, flipsHigh = 0;
        for (int i = 0; i < 2000; ++i) {
            const float dt = 0.01f + 0.05f * float(i % 7);
            const float next = particles::bounceAngle(r, krot, kvel, dt, mode);
            ASSERT_GE(std::abs(next), 0.0f);
            ASSERT_LE(std::abs(next), 2.0f * krot + 1e-6f) << "step " << i;
            const bool up = !std::signbit(r), nextUp = !std::signbit(next);
            if (up && !nextUp) ++flipsHigh;
            if (!up && nextUp) ++flipsLow;
            r = next;
        }
        EXPECT_GT(flipsHigh, 10) << "mode " << int(mode);
        EXPECT_GT(flipsLow, 10) << "mode " << int(mode);
    }
}

TEST(ParticleMath, ReflectedBounceDoesNotDependOnTheStepButTheSeedsClampDoes) {
    // The seed's clamp drops the overshoot at each end, so the swing's phase depends on the frame
    // rate; the reflected default gives the same angle for any split of the same time.
    const float krot = 0.4f, kvel = 2.5f, T = 2.7f;
    auto run = [&](particles::RotationBounce mode, int steps) {
        float r = 0.2f;
        for (int i = 0; i < steps; ++i)
            r = particles::bounceAngle(r, krot, kvel, T / float(steps), mode);
        return r;
    };
    using enum particles::RotationBounce;
    EXPECT_NEAR(run(Reflect, 7), run(Reflect, 300), 1e-4f);
    EXPECT_GT(std::abs(run(Clamp, 7) - run(Clamp, 300)), 0.1f);
}

TEST(ParticleMath, CarriedAgeKeepsEmissionSteadyWhereTheSeedsRuleSynchronises) {
    particles::StepInput in;
    in.emitter.lifetime = 2.0f;
    std::vector<ParticleRecord> carry(1000), paper(1000);
    for (std::uint32_t i = 0; i < 1000; ++i)
        carry[i] = paper[i] = particles::initial(in, i, particles::StartMode::Steady, 0, 1000);
    in.dt = 7.3f; // a hitch longer than the lifetime
    in.step = 1;
    auto spread = [](const std::vector<ParticleRecord>& ps) {
        double m = 0, m2 = 0;
        for (const auto& p : ps)
            m += p.age, m2 += double(p.age) * p.age;
        m /= double(ps.size());
        return std::sqrt(m2 / double(ps.size()) - m * m);
    };
    for (std::uint32_t i = 0; i < 1000; ++i) {
        in.respawn = particles::Respawn::CarryAge;
        carry[i] = particles::update(carry[i], in, i);
        in.respawn = particles::Respawn::Paper;
        paper[i] = particles::update(paper[i], in, i);
    }
    EXPECT_NEAR(spread(carry), 2.0 / std::sqrt(12.0), 0.05); // still uniform over [0, tmax)
    EXPECT_EQ(spread(paper), 0.0);                           // every particle born together
}

// ---------------------------------------------------------------- GPU simulation
TEST_P(GpuMatchesCpu, After200VariedStepsEveryRecordMatches) {
    const RefCase c = GetParam();
    ParticleSettings s;
    s.capacity = 3000;
    s.seed = 77;
    s.layout = c.layout;
    s.respawn = c.respawn;
    s.bounce = c.bounce;
    s.start = c.start;
    s.update = c.update;
    s.emitter.size = {4.0f, 2.0f};
    s.emitter.velocity = {1.0f, -0.5f, 3.0f};
    s.emitter.velocitySpread = 0.8f;
    s.emitter.acceleration = {0.2f, 0.0f, -9.81f};
    s.emitter.rotationRange = 0.9f;
    s.emitter.rotationSpeed = 2.2f;
    s.emitter.lifetime = 1.5f;
    const glm::mat4 place =
        glm::rotate(glm::translate(glm::mat4(1.0f), {3, 1, 2}), 0.4f, glm::vec3(0.3f, 0.2f, 1.0f));
    Sim sim = makeSim(s, place);
    sim.v->frame(0.0); // step 0: the start mode's records
    ASSERT_EQ(sim.node->steps(), 0u);

    particles::StepInput in = stepInputFor(s, place);
    std::vector<ParticleRecord> cpu = initialRecords(s, in);
    {
        const auto gpu = sim.node->readRecords();
        ASSERT_EQ(gpu.size(), cpu.size());
        for (std::uint32_t i = 0; i < s.capacity; ++i)
            expectClose(gpu[i], cpu[i], i, 0);
    }
    int respawns = 0;
    for (int step = 1; step <= 200; ++step) {
        float dt = 0.004f * float(step % 11);               // includes ΔT = 0
        if (step % 37 == 0) dt = 2.3f * s.emitter.lifetime; // longer than tmax
        sim.node->queueStep(dt);
        in.dt = dt;
        in.step = std::uint32_t(step);
        for (std::uint32_t i = 0; i < s.capacity; ++i) {
            const ParticleRecord next = particles::update(cpu[i], in, i);
            respawns += next.age < cpu[i].age;
            cpu[i] = next;
        }
        if (step % 50 == 0 || step == 200) {
            sim.v->frame(0.0); // runs the queued steps (advance(0) adds none)
            const auto gpu = sim.node->readRecords();
            for (std::uint32_t i = 0; i < s.capacity; ++i)
                expectClose(gpu[i], cpu[i], i, step);
            ASSERT_EQ(sim.node->lastFrame().update, c.update); // the path asked for ran
        }
    }
    EXPECT_EQ(sim.node->steps(), 200u);
    EXPECT_GT(respawns, int(s.capacity)); // every particle respawned at least once on average
}

INSTANTIATE_TEST_SUITE_P(
    Particles, GpuMatchesCpu,
    ::testing::Values(RefCase{ParticleLayout::Interleaved, particles::Respawn::CarryAge,
                              particles::RotationBounce::Reflect, particles::StartMode::Steady},
                      RefCase{ParticleLayout::Split, particles::Respawn::CarryAge,
                              particles::RotationBounce::Reflect, particles::StartMode::Ramp},
                      RefCase{ParticleLayout::Interleaved, particles::Respawn::Paper,
                              particles::RotationBounce::Clamp, particles::StartMode::Burst},
                      RefCase{ParticleLayout::Split, particles::Respawn::Paper,
                              particles::RotationBounce::Clamp, particles::StartMode::Steady},
                      RefCase{ParticleLayout::Split, particles::Respawn::CarryAge,
                              particles::RotationBounce::Reflect, particles::StartMode::Ramp,
                              ParticleUpdate::Compute},
                      RefCase{ParticleLayout::Interleaved, particles::Respawn::Paper,
                              particles::RotationBounce::Clamp, particles::StartMode::Burst,
                              ParticleUpdate::Compute}));

// ---------------------------------------------------------------- update paths
// 10^4 particles (two rows of compute work groups), 20 fixed steps of 1/30 s with a 0.25 s life
// (every particle respawns about twice), on each update path and layout: every record equals the
// CPU reference (ParticleMath.h) within expectClose's tolerance.
struct UpdateCase {
    ParticleUpdate update;
    ParticleLayout layout;
};
class UpdatePaths : public ::testing::TestWithParam<UpdateCase> {};

ParticleSettings movingSystem(std::uint32_t n) {
    ParticleSettings s;
    s.capacity = n;
    s.seed = 5;
    s.emitter.size = {3.0f, 1.0f};
    s.emitter.velocity = {0.5f, 1.0f, 4.0f};
    s.emitter.velocitySpread = 1.5f;
    s.emitter.acceleration = {0.0f, 0.3f, -9.81f};
    s.emitter.rotationRange = 1.1f;
    s.emitter.rotationSpeed = 3.0f;
    s.emitter.lifetime = 0.25f;
    return s;
}

// The CPU reference after `steps` steps of `dt` from the start mode's records.
std::vector<ParticleRecord> cpuReference(const ParticleSettings& s, const glm::mat4& place, int steps,
                                         float dt) {
    particles::StepInput in = stepInputFor(s, place);
    std::vector<ParticleRecord> cpu = initialRecords(s, in);
    in.dt = dt;
    for (int step = 1; step <= steps; ++step) {
        in.step = std::uint32_t(step);
        for (std::uint32_t i = 0; i < s.capacity; ++i)
            cpu[i] = particles::update(cpu[i], in, i);
    }
    return cpu;
}

TEST_P(UpdatePaths, TwentyFixedStepsMatchTheCpuReference) {
    ParticleSettings s = movingSystem(10000);
    s.update = GetParam().update;
    s.layout = GetParam().layout;
    const glm::mat4 place =
        glm::rotate(glm::translate(glm::mat4(1.0f), {-2, 4, 1}), 0.7f, glm::vec3(0, 0, 1));
    Sim sim = makeSim(s, place);
    sim.v->frame(0.0);
    for (int step = 0; step < 20; ++step)
        sim.node->queueStep(1.0f / 30.0f);
    sim.v->frame(0.0);
    ASSERT_EQ(sim.node->steps(), 20u);
    EXPECT_EQ(sim.node->lastFrame().update, s.update);
    EXPECT_EQ(sim.node->lastFrame().steps, 20u);
    EXPECT_FALSE(sim.node->lastFrame().measured);
    const auto cpu = cpuReference(s, place, 20, 1.0f / 30.0f);
    const auto gpu = sim.node->readRecords();
    ASSERT_EQ(gpu.size(), cpu.size());
    for (std::uint32_t i = 0; i < s.capacity; ++i)
        expectClose(gpu[i], cpu[i], i, 20);
}

INSTANTIATE_TEST_SUITE_P(
    Particles, UpdatePaths,
    ::testing::Values(UpdateCase{ParticleUpdate::TransformFeedback, ParticleLayout::Interleaved},
                      UpdateCase{ParticleUpdate::TransformFeedback, ParticleLayout::Split},
                      UpdateCase{ParticleUpdate::Compute, ParticleLayout::Interleaved},
                      UpdateCase{ParticleUpdate::Compute, ParticleLayout::Split}));

// Auto times both paths once (into the spare copy) from 2^16 particles on, keeps one, reports it,
// and the particles are still exactly the reference's: the timing steps did not touch them.
// Below 2^16 it takes transform feedback untimed.
TEST(Particles, AutoUpdatePicksAPathReportsItAndLeavesTheParticlesAlone) {
    ParticleSettings s = movingSystem(1u << 16);
    ASSERT_EQ(s.update, ParticleUpdate::Auto); // the default
    Sim sim = makeSim(s, glm::mat4(1.0f));
    sim.v->frame(0.0);
    EXPECT_EQ(sim.node->lastFrame().steps, 0u);
    for (int step = 0; step < 3; ++step)
        sim.node->queueStep(1.0f / 30.0f);
    sim.v->frame(0.0);
    const ParticleFrameInfo first = sim.node->lastFrame();
    EXPECT_TRUE(first.measured);
    EXPECT_GT(first.transformFeedbackMs, 0.0f);
    EXPECT_GT(first.computeMs, 0.0f);
    EXPECT_EQ(first.update, first.computeMs <= first.transformFeedbackMs ? ParticleUpdate::Compute
                                                                         : ParticleUpdate::TransformFeedback);
    EXPECT_EQ(first.steps, 3u);
    const auto cpu = cpuReference(s, glm::mat4(1.0f), 3, 1.0f / 30.0f);
    const auto gpu = sim.node->readRecords();
    for (std::uint32_t i = 0; i < s.capacity; ++i)
        expectClose(gpu[i], cpu[i], i, 3);
    // Measured once: the next frame keeps the choice and its timings.
    sim.node->queueStep(1.0f / 30.0f);
    sim.v->frame(0.0);
    EXPECT_EQ(sim.node->lastFrame().update, first.update);
    EXPECT_EQ(sim.node->lastFrame().computeMs, first.computeMs);
    EXPECT_EQ(sim.node->lastFrame().steps, 1u);
    // Below 2^16: transform feedback, untimed.
    s.capacity = (1u << 16) - 1;
    sim.node->setSettings(s);
    sim.node->queueStep(1.0f / 30.0f);
    sim.v->frame(0.0);
    EXPECT_EQ(sim.node->lastFrame().update, ParticleUpdate::TransformFeedback);
    EXPECT_FALSE(sim.node->lastFrame().measured);
}

// The compute path's program and bindings leave no GL object behind, and switching paths on a
// running system keeps its particles.
TEST(Particles, ComputeUpdateLeaksNoGlObjectsAndSwitchesPathsMidRun) {
    const long before = gl::liveObjects().total();
    {
        ParticleSettings s = movingSystem(1000);
        s.update = ParticleUpdate::Compute;
        s.layout = ParticleLayout::Split;
        Sim sim = makeSim(s, glm::mat4(1.0f));
        sim.v->frame(0.0);
        for (int step = 0; step < 3; ++step)
            sim.node->queueStep(1.0f / 30.0f);
        sim.v->frame(0.0); // steps 1..3 by compute
        EXPECT_EQ(sim.node->lastFrame().update, ParticleUpdate::Compute);
        s.update = ParticleUpdate::TransformFeedback;
        sim.node->setSettings(s);
        sim.node->queueStep(1.0f / 30.0f);
        sim.v->frame(0.0); // step 4 by transform feedback
        EXPECT_EQ(sim.node->lastFrame().update, ParticleUpdate::TransformFeedback);
        const auto cpu = cpuReference(s, glm::mat4(1.0f), 4, 1.0f / 30.0f);
        const auto gpu = sim.node->readRecords();
        for (std::uint32_t i = 0; i < s.capacity; ++i)
            expectClose(gpu[i], cpu[i], i, 4);
        sim.node->releaseGLObjects();
        s.update = ParticleUpdate::Compute;
        sim.node->setSettings(s);
        sim.node->queueStep(1.0f / 30.0f);
        sim.v->frame(0.0); // made again after the release
        EXPECT_EQ(sim.node->lastFrame().update, ParticleUpdate::Compute);
    }
    EXPECT_EQ(gl::liveObjects().total(), before);
}

TEST(Particles, KinematicsFollowTheClosedForm) {
    ParticleSettings s;
    s.capacity = 64;
    s.start = particles::StartMode::Burst;
    s.emitter.size = {10.0f, 6.0f};
    s.emitter.velocity = {2.0f, -1.0f, 12.0f};
    s.emitter.velocitySpread = 0.0f;
    s.emitter.acceleration = {0.5f, 0.25f, -9.81f};
    s.emitter.lifetime = 100.0f; // no respawn
    Sim sim = makeSim(s, glm::mat4(1.0f));
    sim.v->frame(0.0);
    const auto start = sim.node->readRecords();
    double T = 0.0;
    for (int i = 0; i < 60; ++i) {
        const float dt = 0.01f + 0.002f * float(i % 5);
        sim.node->queueStep(dt);
        T += dt;
    }
    sim.v->frame(0.0);
    const auto end = sim.node->readRecords();
    for (std::size_t i = 0; i < end.size(); ++i) {
        const glm::dvec3 p0(start[i].position), v0(s.emitter.velocity), a(s.emitter.acceleration);
        const glm::dvec3 expected = p0 + v0 * T + 0.5 * a * T * T;
        for (int k = 0; k < 3; ++k)
            EXPECT_NEAR(end[i].position[k], expected[k], 2e-4 * std::max(1.0, std::abs(expected[k])))
                << "particle " << i << " axis " << k;
        EXPECT_NEAR(end[i].age, T, 1e-5);
    }
}

TEST(Particles, GpuRotationStaysInRange) {
    ParticleSettings s;
    s.capacity = 500;
    s.emitter.rotationRange = 0.6f;
    s.emitter.rotationSpeed = 5.0f;
    s.emitter.lifetime = 50.0f;
    Sim sim = makeSim(s, glm::mat4(1.0f));
    sim.v->frame(0.0);
    std::vector<ParticleRecord> before = sim.node->readRecords();
    int flips = 0;
    for (int f = 0; f < 40; ++f) {
        sim.node->queueStep(0.05f);
        sim.v->frame(0.0);
        const auto now = sim.node->readRecords();
        for (std::size_t i = 0; i < now.size(); ++i)
            for (int k = 0; k < 3; ++k) {
                ASSERT_LE(std::abs(now[i].angles[k]), 1.2f + 1e-5f);
                flips += std::signbit(now[i].angles[k]) != std::signbit(before[i].angles[k]);
            }
        before = now;
    }
    EXPECT_GT(flips, 500);
}

TEST(Particles, SteadyStartHasUniformAgesAndNoBurst) {
    ParticleSettings s;
    s.capacity = 4000;
    s.emitter.lifetime = 2.0f;
    Sim sim = makeSim(s, glm::mat4(1.0f));
    sim.v->frame(0.0);
    const auto r = sim.node->readRecords();
    double mean = 0;
    for (const auto& p : r) {
        ASSERT_GE(p.age, 0.0f);
        ASSERT_LT(p.age, 2.0f);
        mean += p.age;
    }
    EXPECT_NEAR(mean / double(r.size()), 1.0, 0.01);
    // Births in one step of 0.1 s: n·Δt/tmax, as in every later step.
    sim.node->queueStep(0.1f);
    sim.v->frame(0.0);
    const auto after = sim.node->readRecords();
    int born = 0;
    for (std::size_t i = 0; i < r.size(); ++i)
        born += after[i].age < r[i].age;
    EXPECT_NEAR(born, 200, 2);
}

TEST(Particles, CapacityChangeKeepsLiveParticles) {
    ParticleSettings s;
    s.capacity = 1000;
    s.emitter.lifetime = 3.0f;
    s.emitter.velocity = {0, 0, 2};
    Sim sim = makeSim(s, glm::mat4(1.0f));
    for (int i = 0; i < 5; ++i)
        sim.v->frame(0.05);
    const auto before = sim.node->readRecords();
    sim.node->setCapacity(2500);
    sim.v->frame(0.0);
    const auto grown = sim.node->readRecords();
    ASSERT_EQ(grown.size(), 2500u);
    for (std::size_t i = 0; i < before.size(); ++i)
        ASSERT_EQ(std::memcmp(&grown[i], &before[i], sizeof(ParticleRecord)), 0) << "particle " << i;
    for (std::size_t i = before.size(); i < grown.size(); ++i)
        ASSERT_LT(grown[i].age, 0.0f) << "new particle " << i << " is born at the steady rate, not at once";
    sim.node->setCapacity(400);
    sim.v->frame(0.0);
    const auto shrunk = sim.node->readRecords();
    ASSERT_EQ(shrunk.size(), 400u);
    for (std::size_t i = 0; i < shrunk.size(); ++i)
        ASSERT_EQ(std::memcmp(&shrunk[i], &grown[i], sizeof(ParticleRecord)), 0) << "particle " << i;
    // Across a layout change too.
    ParticleSettings split = sim.node->settings();
    split.layout = ParticleLayout::Split;
    sim.node->setSettings(split);
    sim.v->frame(0.0);
    const auto relaid = sim.node->readRecords();
    for (std::size_t i = 0; i < relaid.size(); ++i)
        ASSERT_EQ(std::memcmp(&relaid[i], &shrunk[i], sizeof(ParticleRecord)), 0) << "particle " << i;
}

TEST(Particles, PauseTimeScaleAndReset) {
    ParticleSettings s;
    s.capacity = 10;
    s.start = particles::StartMode::Burst;
    s.emitter.lifetime = 100.0f;
    Sim sim = makeSim(s, glm::mat4(1.0f));
    sim.v->frame(0.0);
    sim.node->timeScale = 0.5f;
    sim.v->frame(0.2);
    EXPECT_NEAR(sim.node->readRecords()[3].age, 0.1f, 1e-6f);
    sim.node->paused = true;
    sim.v->frame(0.2);
    EXPECT_NEAR(sim.node->readRecords()[3].age, 0.1f, 1e-6f);
    sim.node->paused = false;
    sim.node->reset();
    sim.v->frame(0.0);
    EXPECT_EQ(sim.node->steps(), 0u);
    EXPECT_EQ(sim.node->readRecords()[3].age, 0.0f);
}

// ---------------------------------------------------------------- drawing
class ParticlePaths : public ::testing::TestWithParam<ParticlePath> {};

TEST_P(ParticlePaths, SpriteCoversTheExpectedSquare) {
    const float d = 10.0f, k = 1.5f, fovy = 40.0f;
    auto v = viewer({0, -d, 0}, {0, 0, 0}, fovy);
    auto p = ParticleSystemNode::create(stillParticle(ParticleShape::Sprite, k, GetParam()));
    emissiveLook(*p, glm::vec3(1.0f));
    v->setSceneData(p);
    v->frame(0.0);
    const double f = (kSize / 2.0) / std::tan(glm::radians(fovy) / 2.0); // pixels per unit at distance 1
    const double side = k * f / d;
    EXPECT_NEAR(litPixels(v->capture()), side * side, 2.0 * side) << "side " << side << " px";
    // Centred: the middle pixel is lit, the corners are not.
    EXPECT_GT(pixelAt(v->capture(), kSize / 2, kSize / 2).r, 250);
    EXPECT_EQ(pixelAt(v->capture(), 2, 2).r, 0);
}

TEST_P(ParticlePaths, HexagonAndTetrahedronCoverTheirProjectedArea) {
    for (const ParticleShape shape : {ParticleShape::Hexagon, ParticleShape::Tetrahedron}) {
        // Looking down −Z with an orthographic camera: pixel areas are projected areas.
        auto v = orthoTopViewer(kSize, 1.0f);
        ParticleSettings s = stillParticle(shape, 1.2f, GetParam());
        s.emitter.rotationRange = 1.0f;
        s.seed = 5;
        auto p = ParticleSystemNode::create(s);
        emissiveLook(*p, glm::vec3(1.0f));
        v->setSceneData(p);
        v->frame(0.0);
        const ParticleRecord r = p->readRecords().at(0);
        // The shader's MR and corners, projected onto z = const.
        const glm::vec3 turn = r.angles0 + (glm::abs(r.angles) - s.emitter.rotationRange);
        const glm::mat3 mr = glm::mat3(glm::rotate(glm::mat4(1.0f), turn.x, {1, 0, 0})) *
                             glm::mat3(glm::rotate(glm::mat4(1.0f), turn.y, {0, 1, 0})) *
                             glm::mat3(glm::rotate(glm::mat4(1.0f), turn.z, {0, 0, 1}));
        std::vector<glm::dvec2> pts;
        if (shape == ParticleShape::Hexagon) {
            for (int j = 0; j < 6; ++j) {
                const double a = j * 2.0 * 3.14159265358979 / 6.0;
                const glm::vec3 w = mr * (0.5f * 1.2f * glm::vec3(std::cos(a), std::sin(a), 0.0f));
                pts.push_back({w.x, w.y});
            }
        } else {
            const glm::vec3 c[4] = {{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}};
            for (const auto& q : c) {
                const glm::vec3 w = mr * (q * (1.2f / std::sqrt(8.0f)));
                pts.push_back({w.x, w.y});
            }
        }
        // Convex hull area (gift wrapping is plenty for ≤ 6 points).
        std::sort(pts.begin(), pts.end(),
                  [](auto a, auto b) { return a.x < b.x || (a.x == b.x && a.y < b.y); });
        std::vector<glm::dvec2> hull;
        for (int pass = 0; pass < 2; ++pass) {
            const std::size_t base = hull.size();
            for (const auto& q : pts) {
                while (hull.size() >= base + 2) {
                    const auto& o = hull[hull.size() - 2];
                    const auto& a = hull.back();
                    if ((a.x - o.x) * (q.y - o.y) - (a.y - o.y) * (q.x - o.x) > 0) break;
                    hull.pop_back();
                }
                hull.push_back(q);
            }
            hull.pop_back();
            std::reverse(pts.begin(), pts.end());
        }
        double area = 0, perimeter = 0;
        for (std::size_t i = 0; i < hull.size(); ++i) {
            const auto& a = hull[i];
            const auto& b = hull[(i + 1) % hull.size()];
            area += a.x * b.y - a.y * b.x;
            perimeter += glm::length(b - a);
        }
        const double pxPerUnit = kSize / 2.0;
        area = std::abs(area) / 2.0 * pxPerUnit * pxPerUnit;
        EXPECT_NEAR(litPixels(v->capture()), area, 0.5 * perimeter * pxPerUnit + 4.0)
            << (shape == ParticleShape::Hexagon ? "hexagon" : "tetrahedron");
    }
}

INSTANTIATE_TEST_SUITE_P(Particles, ParticlePaths,
                         ::testing::Values(ParticlePath::GeometryShader, ParticlePath::Instanced,
                                           ParticlePath::Pulled, ParticlePath::PointSprite));

TEST(Particles, TrianglePathsDrawTheSameImage) {
    // Geometry shader, instancing and vertex pulling make the same triangles from the same
    // records: every shape's image is the same to the last bit of each channel (±1).
    for (const ParticleShape shape :
         {ParticleShape::Sprite, ParticleShape::Hexagon, ParticleShape::Tetrahedron, ParticleShape::Quad}) {
        std::vector<Image> images;
        for (const ParticlePath path :
             {ParticlePath::GeometryShader, ParticlePath::Instanced, ParticlePath::Pulled}) {
            for (const ParticleLayout layout : {ParticleLayout::Interleaved, ParticleLayout::Split}) {
                auto v = viewer({0, -12, 4}, {0, 0, 2});
                ParticleSettings s;
                s.capacity = 400;
                s.shape = shape;
                s.path = path;
                s.layout = layout;
                s.sizeStart = 0.3f;
                s.sizeEnd = 0.6f;
                s.stretch = 0.5f;
                s.colorStart = {1.0f, 0.5f, 0.2f, 1.0f};
                s.colorEnd = {0.2f, 0.6f, 1.0f, 1.0f};
                s.emitter.size = {6.0f, 6.0f};
                s.emitter.velocity = {0, 0, 2};
                s.emitter.velocitySpread = 0.5f;
                s.emitter.rotationRange = 1.0f;
                s.emitter.rotationSpeed = 1.0f;
                s.emitter.lifetime = 2.0f;
                auto p = ParticleSystemNode::create(s);
                auto root = Group::create();
                root->addChild(p);
                root->addChild(Light::create());
                v->setSceneData(root);
                for (int f = 0; f < 3; ++f)
                    v->frame(0.1);
                images.push_back(v->capture());
                ASSERT_EQ(p->resolvedPath(), path);
            }
        }
        ASSERT_GT(litPixels(images[0]), 100) << "shape " << int(shape);
        for (std::size_t i = 1; i < images.size(); ++i)
            EXPECT_EQ(channelsDiffering(images[0], images[i], 1), 0)
                << "shape " << int(shape) << " image " << i;
    }
}

TEST(Particles, AutoPicksPointSpritesForSpritesAndPullingForTheRest) {
    auto v = viewer({0, -12, 4}, {0, 0, 2});
    auto sprite = ParticleSystemNode::create(ParticleSettings{});
    ParticleSettings hex;
    hex.shape = ParticleShape::Hexagon;
    auto hexagons = ParticleSystemNode::create(hex);
    auto root = Group::create();
    root->addChild(sprite);
    root->addChild(hexagons);
    v->setSceneData(root);
    v->frame(0.1);
    EXPECT_EQ(sprite->resolvedPath(), ParticlePath::PointSprite);
    EXPECT_EQ(hexagons->resolvedPath(), ParticlePath::Pulled);
    ParticleSettings forced = hex;
    forced.path = ParticlePath::PointSprite; // sprites only: the others are pulled
    hexagons->setSettings(forced);
    EXPECT_EQ(hexagons->resolvedPath(), ParticlePath::Pulled);
}

TEST(Particles, FoggedParticleMatchesTheFogFormula) {
    const float d = 20.0f;
    auto v = viewer({0, -d, 0}, {0, 0, 0});
    FogParameters fp;
    fp.density = 0.04f;
    fp.falloff = 0.0f; // homogeneous: optical depth ρ0·L
    fp.color = {0.2f, 0.4f, 0.8f};
    auto fog = FogNode::create(fp);
    auto p = ParticleSystemNode::create(stillParticle(ParticleShape::Sprite, 3.0f, ParticlePath::Auto));
    const glm::vec3 c(0.9f, 0.6f, 0.1f);
    emissiveLook(*p, c);
    fog->addChild(p);
    v->setSceneData(fog);
    v->frame(0.0);
    const double t = std::exp(-0.04 * d); // the sprite's centre is at distance d
    const glm::ivec4 px = pixelAt(v->capture(), kSize / 2, kSize / 2);
    for (int ch = 0; ch < 3; ++ch)
        EXPECT_NEAR(px[ch], srgbByte(c[ch] * t + fp.color[ch] * (1.0 - t)), 1) << "channel " << ch;
}

// A black double-sided wall `gap` behind the origin, facing a camera on -Y (soft-particle tests).
std::shared_ptr<Node> blackWallBehind(float gap) {
    auto wall = Transform::create(
        glm::rotate(glm::translate(glm::mat4(1.0f), {0, gap, 0}), glm::radians(90.0f), glm::vec3(1, 0, 0)));
    auto quad = shapes::quad(20, 20);
    auto black = Material::create();
    black->ambient = glm::vec3(0);
    black->diffuse = glm::vec4(0, 0, 0, 1);
    quad->getOrCreateStateSet().material.set(black);
    quad->getOrCreateStateSet().cullFace.set(CullFace::None);
    wall->addChild(quad);
    return wall;
}

TEST(Particles, SoftParticleFadesByTheGapToTheSurfaceBehind) {
    const float d = 10.0f, gap = 0.3f, softness = 1.2f;
    auto v = viewer({0, -d, 0}, {0, 0, 0});
    auto root = Group::create();
    root->addChild(blackWallBehind(gap));
    ParticleSettings s = stillParticle(ParticleShape::Sprite, 2.0f, ParticlePath::Auto);
    s.softness = softness;
    auto p = ParticleSystemNode::create(s);
    emissiveLook(*p, glm::vec3(0.8f), BlendMode::Premultiplied);
    root->addChild(p);
    v->setSceneData(root);
    v->frame(0.0);
    // The sprite faces the eye; at the centre pixel it lies exactly `gap` in front of the wall.
    const double fade = gap / softness;
    EXPECT_NEAR(pixelAt(v->capture(), kSize / 2, kSize / 2).r, srgbByte(0.8 * fade), 2);
    // Without softness: the full colour.
    s.softness = 0.0f;
    p->setSettings(s);
    v->frame(0.0);
    EXPECT_NEAR(pixelAt(v->capture(), kSize / 2, kSize / 2).r, srgbByte(0.8), 1);
}

// Claimed by an OIT bin, soft particles are drawn in the bin's pass (before the transparent half
// of the main pass) and read the same scene depth there. One layer over black: the composite is
// the premultiplied colour, so the fade is the same as in the sorted case.
TEST(Particles, SoftParticleInAnOitBinFadesByTheGapToTheSurfaceBehind) {
    const float d = 10.0f, gap = 0.3f, softness = 1.2f;
    auto v = viewer({0, -d, 0}, {0, 0, 0});
    auto root = Group::create();
    root->addChild(blackWallBehind(gap));
    auto bin = TransparencyBin::create(TransparencyMode::WeightedBlended);
    root->addChild(bin);
    ParticleSettings s = stillParticle(ParticleShape::Sprite, 2.0f, ParticlePath::Auto);
    s.softness = softness;
    auto p = ParticleSystemNode::create(s);
    emissiveLook(*p, glm::vec3(0.8f), BlendMode::Premultiplied);
    bin->addChild(p);
    v->setSceneData(root);
    v->frame(0.0);
    expectNoGlErrors(*v);
    const double fade = gap / softness;
    EXPECT_NEAR(pixelAt(v->capture(), kSize / 2, kSize / 2).r, srgbByte(0.8 * fade), 2);
    s.softness = 0.0f;
    p->setSettings(s);
    v->frame(0.0);
    EXPECT_NEAR(pixelAt(v->capture(), kSize / 2, kSize / 2).r, srgbByte(0.8), 1);
}

TEST(Particles, BlendedParticlesAreClaimedByAnOitBinAndSortedOtherwise) {
    auto cam = Camera::create();
    cam->setPerspective(60.0f, 0.1f, 100.0f);
    cam->setLookAt({0, -10, 0}, {0, 0, 0}, {0, 0, 1});
    auto smoke = ParticleSystemNode::smoke();
    auto bin = TransparencyBin::create(TransparencyMode::WeightedBlended);
    bin->addChild(smoke);
    cam->addChild(bin);
    RenderQueue q;
    CullVisitor cv(*cam, q);
    cv.run(*cam);
    ASSERT_EQ(q.claimed.size(), 1u);
    EXPECT_EQ(q.claimed[0].drawable, smoke.get());
    bin->setMode(TransparencyMode::Sorted);
    RenderQueue q2;
    CullVisitor cv2(*cam, q2);
    cv2.run(*cam);
    ASSERT_EQ(q2.transparent.size(), 1u);
    EXPECT_EQ(q2.transparent[0].drawable, smoke.get());
}

TEST(Particles, PresetsRenderUnderFogAoAndOitWithoutErrorsOrNaN) {
    auto v = viewer({0, -25, 6}, {0, 0, 4});
    v->renderer().options().colorTarget = RendererOptions::ColorTarget::Rgba32F;
    auto root = Group::create();
    auto fog = FogNode::create(FogParameters::ground());
    root->addChild(fog);
    auto bin = TransparencyBin::create(TransparencyMode::WeightedBlended);
    fog->addChild(bin);
    auto sun = Light::create();
    fog->addChild(sun);
    const std::vector<std::shared_ptr<ParticleSystemNode>> all = {ParticleSystemNode::rain({20, 20}, 2000),
                                                                  ParticleSystemNode::snow({20, 20}, 2000),
                                                                  ParticleSystemNode::leaves({10, 10}, 500),
                                                                  ParticleSystemNode::smoke(1.0f, 300),
                                                                  ParticleSystemNode::waterJet(),
                                                                  ParticleSystemNode::sparks(500)};
    for (std::size_t i = 0; i < all.size(); ++i) {
        auto t = Transform::create(
            glm::translate(glm::mat4(1.0f), {float(i) * 3.0f - 7.5f, 0.0f, i < 3 ? 10.0f : 0.0f}));
        t->addChild(all[i]);
        bin->addChild(t);
    }
    v->setSceneData(root);
    for (int f = 0; f < 5; ++f)
        v->frame(1.0 / 30.0);
    const FloatImage img = v->renderer().readPixelsLinear();
    int lit = 0;
    for (std::size_t i = 0; i < img.rgba.size(); ++i) {
        ASSERT_TRUE(std::isfinite(img.rgba[i])) << "component " << i;
        lit += i % 4 == 0 && img.rgba[i] > 0.01f;
    }
    EXPECT_GT(lit, 500);
    for (const auto& p : all)
        EXPECT_EQ(p->steps(), 5u) << p->name; // one step per frame
}

// ---------------------------------------------------------------- bad input
TEST(Particles, BadSettingsAreRefusedAndTheSystemKeepsRunning) {
    ParticleSettings good;
    good.capacity = 100;
    Sim sim = makeSim(good, glm::mat4(1.0f));
    sim.v->frame(0.1);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const std::vector<std::pair<std::function<void(ParticleSettings&)>, std::string>> cases = {
        {[](ParticleSettings& s) { s.capacity = 0; }, "capacity = 0"},
        {[](ParticleSettings& s) { s.capacity = ParticleSystemNode::kMaxCapacity + 1; },
         "capacity = 16777217"},
        {[](ParticleSettings& s) { s.emitter.lifetime = 0.0f; }, "tmax"},
        {[](ParticleSettings& s) { s.emitter.lifetime = -1.0f; }, "tmax"},
        {[&](ParticleSettings& s) { s.emitter.velocity.y = nan; }, "v0"},
        {[&](ParticleSettings& s) { s.emitter.acceleration.z = nan; }, "acceleration"},
        {[&](ParticleSettings& s) { s.emitter.size.x = nan; }, "W"},
        {[](ParticleSettings& s) { s.emitter.velocitySpread = -1.0f; }, "kv"},
        {[](ParticleSettings& s) { s.emitter.rotationRange = 4.0f; }, "krot"},
        {[](ParticleSettings& s) { s.sizeStart = -0.1f; }, "sizeStart"},
        {[](ParticleSettings& s) { s.colorEnd.a = 2.0f; }, "colorEnd"},
        {[](ParticleSettings& s) { s.shape = ParticleShape(9); }, "shape"},
        {[](ParticleSettings& s) { s.update = ParticleUpdate(3); }, "update has an invalid value 3"},
    };
    for (const auto& [edit, needle] : cases) {
        ParticleSettings bad = good;
        edit(bad);
        try {
            sim.node->setSettings(bad);
            ADD_FAILURE() << "accepted: " << needle;
        } catch (const std::invalid_argument& e) {
            EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
        }
        EXPECT_EQ(sim.node->settings().capacity, 100u);
    }
    EXPECT_THROW(sim.node->advance(-1.0), std::invalid_argument);
    EXPECT_THROW(sim.node->queueStep(nan), std::invalid_argument);
    ParticleSettings none;
    none.capacity = 0;
    EXPECT_THROW(ParticleSystemNode::create(none), std::invalid_argument);
    const auto steps = sim.node->steps();
    sim.v->frame(0.1);
    EXPECT_EQ(sim.node->steps(), steps + 1);
    EXPECT_EQ(sim.node->readRecords().size(), 100u);
}

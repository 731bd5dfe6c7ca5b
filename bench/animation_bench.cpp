// Keyframe sampling throughput (Google Benchmark): 1000 channels of each interpolation with 30 keys
// sampled at random times, and AnimationPlayer::update on 100 targets x 3 paths, alone and in a
// cross-fade (two animations mixed). Run: build/bench/animation_bench; items_per_second / 1000 is
// channels per ms.
#include <sgfx/Animation.h>
#include <sgfx/Group.h>

#include <benchmark/benchmark.h>

#include <cmath>
#include <random>
#include <vector>

namespace {

constexpr std::size_t kKeys = 30;
constexpr float kKeyStep = 1.0f / 30.0f;

sgfx::AnimationSampler makeSampler(sgfx::Interpolation mode, std::size_t components, bool rotation,
                                   std::mt19937& rng) {
    std::uniform_real_distribution<float> value(-1.0f, 1.0f);
    sgfx::AnimationSampler s;
    s.interpolation = mode;
    s.components = components;
    const std::size_t perKey = mode == sgfx::Interpolation::CubicSpline ? 3 : 1;
    for (std::size_t k = 0; k < kKeys; ++k) {
        s.times.push_back(float(k) * kKeyStep);
        for (std::size_t i = 0; i < perKey * components; ++i)
            s.values.push_back(value(rng));
    }
    if (rotation && perKey == 1) // unit keys
        for (std::size_t k = 0; k < kKeys; ++k) {
            float* q = s.values.data() + k * 4;
            const float len = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
            for (int i = 0; i < 4; ++i)
                q[i] /= len;
        }
    return s;
}

// items_per_second: channels sampled (and mixed) per second; ns_per_channel its inverse.
void counters(benchmark::State& state, std::size_t channelsPerIteration) {
    state.SetItemsProcessed(state.iterations() * std::int64_t(channelsPerIteration));
    state.counters["ns_per_channel"] =
        benchmark::Counter(double(channelsPerIteration),
                           benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

// 1000 channels (range(0): 0 Step, 1 Linear, 2 CubicSpline; range(1): 1 = rotation) each sampled
// once per iteration at its own random time.
void SampleChannels(benchmark::State& state) {
    const auto mode = sgfx::Interpolation(state.range(0));
    const bool rotation = state.range(1) != 0;
    const std::size_t n = 1000, components = rotation ? 4 : 3;
    std::mt19937 rng(11);
    std::vector<sgfx::AnimationSampler> samplers;
    for (std::size_t i = 0; i < n; ++i)
        samplers.push_back(makeSampler(mode, components, rotation, rng));
    std::uniform_real_distribution<float> when(0.0f, float(kKeys - 1) * kKeyStep);
    std::vector<float> times(n);
    for (float& t : times)
        t = when(rng);
    float out[4];
    for (auto _ : state) {
        for (std::size_t i = 0; i < n; ++i) {
            samplers[i].sample(times[i], out, rotation);
            benchmark::DoNotOptimize(out);
        }
        benchmark::ClobberMemory();
    }
    state.SetLabel(std::string(mode == sgfx::Interpolation::Step     ? "step"
                               : mode == sgfx::Interpolation::Linear ? "linear"
                                                                     : "cubic") +
                   (rotation ? " rotation" : " vec3"));
    counters(state, n);
}
BENCHMARK(SampleChannels)->ArgsProduct({{0, 1, 2}, {0, 1}})->Unit(benchmark::kMicrosecond);

// 100 targets x translation (Linear), rotation (Linear slerp), scale (CubicSpline), per update.
// range(0): 1 = two animations mid-cross-fade (600 channels sampled and mixed).
void PlayerUpdate(benchmark::State& state) {
    const bool fade = state.range(0) != 0;
    std::mt19937 rng(12);
    std::vector<std::shared_ptr<sgfx::Transform>> nodes;
    sgfx::AnimationPlayer player;
    for (int a = 0; a < 2; ++a) {
        sgfx::Animation anim;
        for (std::size_t t = 0; t < 100; ++t) {
            const std::size_t base = anim.samplers.size();
            anim.samplers.push_back(makeSampler(sgfx::Interpolation::Linear, 3, false, rng));
            anim.samplers.push_back(makeSampler(sgfx::Interpolation::Linear, 4, true, rng));
            anim.samplers.push_back(makeSampler(sgfx::Interpolation::CubicSpline, 3, false, rng));
            anim.channels.push_back({base, t, sgfx::AnimationPath::Translation});
            anim.channels.push_back({base + 1, t, sgfx::AnimationPath::Rotation});
            anim.channels.push_back({base + 2, t, sgfx::AnimationPath::Scale});
        }
        player.animations.push_back(anim);
    }
    for (std::size_t t = 0; t < 100; ++t) {
        nodes.push_back(sgfx::Transform::create());
        sgfx::AnimationTarget target;
        target.transform = nodes.back();
        player.targets.push_back(target);
    }
    player.play(0);
    if (fade) player.crossFade(1, 1e9); // stays mid-fade for the whole run
    double sim = 0.0;
    for (auto _ : state) {
        sim += 1.0 / 60.0;
        player.update(sim);
        benchmark::DoNotOptimize(nodes.front()->matrix());
    }
    state.SetLabel(fade ? "100 targets x 3 paths, 2 animations mixed" : "100 targets x 3 paths");
    counters(state, fade ? 600 : 300);
}
BENCHMARK(PlayerUpdate)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

} // namespace

BENCHMARK_MAIN();

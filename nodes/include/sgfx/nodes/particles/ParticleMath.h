#pragma once
/// @file
/// CPU reference of the particle simulation (seed: gpu-particles-transform-feedback-2014, section
/// "Обработка массива частиц"): the same equations, in the same order and with the same random
/// numbers as particle_motion.glsl, so the GPU state can be checked particle by particle.
#include "sgfx/Export.h"
#include <glm/glm.hpp>

#include <cmath>
#include <cstdint>

namespace sgfx::particles {

/// One particle, as the seed stores it: age t (4 bytes), position P (12), velocity v (12),
/// initial angles r0 (12), angle changes r (12) = 52 bytes. World space.
struct SGFX_API ParticleRecord {
    float age = 0.0f; ///< < 0: not born yet
    glm::vec3 position{0.0f};
    glm::vec3 velocity{0.0f};
    glm::vec3 angles0{0.0f};
    glm::vec3 angles{0.0f};
};
static_assert(sizeof(ParticleRecord) == 52);

/// The seed's emitter E: a W×H rectangle in the z = 0 plane of its own frame, placed by the
/// node's world matrix. Vectors are world space, as in the seed.
struct SGFX_API Emitter {
    glm::vec2 size{1.0f, 1.0f};                 ///< W, H (m)
    glm::vec3 velocity{0.0f, 0.0f, 0.0f};       ///< v0 (m/s)
    float velocitySpread = 0.0f;                ///< kv ≥ 0 (m/s): v = v0 + 2·kv·Vrand
    glm::vec3 acceleration{0.0f, 0.0f, -9.81f}; ///< a (m/s²)
    float rotationRange = 0.0f;                 ///< krot ∈ [0, π] (rad)
    float rotationSpeed = 0.0f;                 ///< kvel ≥ 0 (rad/s)
    float lifetime = 1.0f;                      ///< tmax > 0 (s)
};

/// What happens to the time left over when a particle dies within a step.
enum class Respawn : std::uint8_t {
    CarryAge, ///< default: the new particle is already that old (emission stays steady at any ΔT)
    Paper,    ///< the seed: the new particle starts at age 0 (a long step respawns all in sync)
};
/// How |r| turns round at 0 and 2·krot.
enum class RotationBounce : std::uint8_t {
    Reflect, ///< default: the overshoot is reflected (the swing does not depend on the frame rate)
    Clamp,   ///< the seed: |r| is clamped to the end (each bounce loses the overshoot)
};
/// How the first frame looks.
enum class StartMode : std::uint8_t {
    Steady, ///< default: ages staggered over [0, tmax), already in flight: steady from frame one
    Ramp,   ///< ages staggered over [−tmax, 0): particles are born at the steady rate from frame one
    Burst,  ///< every particle born at once
};

/// What one simulation step reads besides the particle itself.
struct SGFX_API StepInput {
    glm::mat4 emitterToWorld{1.0f}; ///< Mmodel
    Emitter emitter;
    float dt = 0.0f; ///< ΔT
    std::uint32_t step = 0;
    std::uint32_t seed = 0;
    Respawn respawn = Respawn::CarryAge;
    RotationBounce bounce = RotationBounce::Reflect;
};

inline constexpr float kTwoPi = 6.28318530717958647692f;

/// PCG output hash (O'Neill): one 32-bit round, exact on every GPU.
constexpr std::uint32_t pcgHash(std::uint32_t v) {
    const std::uint32_t state = v * 747796405u + 2891336453u;
    const std::uint32_t word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

/// frand of the seed: a stateless stream per (system seed, particle index, step).
class SGFX_API Random {
public:
    Random(std::uint32_t seed, std::uint32_t index, std::uint32_t step)
        : state_(pcgHash(seed ^ pcgHash(index ^ pcgHash(step)))) {}
    float next() {
        state_ = pcgHash(state_);
        return float(state_ >> 8) * (1.0f / 16777216.0f); // [0, 1), exact in float
    }
    glm::vec3 centred() { // Vrand = (frand − 0.5, frand − 0.5, frand − 0.5)
        const float x = next() - 0.5f;
        const float y = next() - 0.5f;
        const float z = next() - 0.5f;
        return {x, y, z};
    }

private:
    std::uint32_t state_;
};

/// One component of r after dt: |r| moves by kvel·dt in the direction its sign encodes, inside
/// [0, 2·krot]; the direction flips at either end.
inline float bounceAngle(float r, float krot, float kvel, float dt, RotationBounce mode) {
    const float s = r >= 0.0f ? 1.0f : -1.0f;
    const float span = 2.0f * krot;
    const float x = std::abs(r) + s * kvel * dt;
    if (mode == RotationBounce::Clamp) {
        if (x <= 0.0f) return s > 0.0f ? -0.0f : 0.0f;
        if (x >= span) return -s * span;
        return s * x;
    }
    if (span <= 0.0f) return 0.0f;
    // Fold the straight motion into [0, span]: a triangle wave of period 2·span.
    const float period = 2.0f * span;
    const float u = x - period * std::floor(x / period);
    return u < span ? s * u : -s * (period - u);
}

inline glm::vec3 bounceAngles(glm::vec3 r, const StepInput& in, float dt) {
    const float k = in.emitter.rotationRange, w = in.emitter.rotationSpeed;
    return {bounceAngle(r.x, k, w, dt, in.bounce), bounceAngle(r.y, k, w, dt, in.bounce),
            bounceAngle(r.z, k, w, dt, in.bounce)};
}

/// P' = P + v·ΔT + ½·a·ΔT², v' = v + a·ΔT, r' bounced.
inline void advance(ParticleRecord& p, const StepInput& in, float dt) {
    const glm::vec3 a = in.emitter.acceleration;
    p.position = p.position + p.velocity * dt + 0.5f * a * (dt * dt);
    p.velocity = p.velocity + a * dt;
    p.angles = bounceAngles(p.angles, in, dt);
}

/// A new particle (seed: P' = Mmodel·(W(frand − 0.5), H(frand − 0.5), 0, 1), v' = v0 + 2·kv·Vrand,
/// r0' = 2π·(frand, frand, frand), r' = 4·krot·Vrand), then `age` seconds of flight.
inline ParticleRecord spawn(const StepInput& in, std::uint32_t index, float age) {
    Random rng(in.seed, index, in.step);
    const Emitter& e = in.emitter;
    const float x = rng.next() - 0.5f;
    const float y = rng.next() - 0.5f;
    ParticleRecord p;
    p.position = glm::vec3(in.emitterToWorld * glm::vec4(e.size.x * x, e.size.y * y, 0.0f, 1.0f));
    p.velocity = e.velocity + 2.0f * e.velocitySpread * rng.centred();
    const float r0x = rng.next();
    const float r0y = rng.next();
    const float r0z = rng.next();
    p.angles0 = kTwoPi * glm::vec3(r0x, r0y, r0z);
    p.angles = 4.0f * e.rotationRange * rng.centred();
    p.age = age;
    if (age > 0.0f) advance(p, in, age);
    return p;
}

/// M'[i] from M[i] for one step of in.dt.
inline ParticleRecord update(const ParticleRecord& m, const StepInput& in, std::uint32_t index) {
    const float tmax = in.emitter.lifetime;
    const float t = m.age + in.dt;
    if (m.age < 0.0f) { // waiting to be born
        if (t < 0.0f) {
            ParticleRecord p = m;
            p.age = t;
            return p;
        }
        return spawn(in, index, in.respawn == Respawn::CarryAge ? t : 0.0f);
    }
    if (t >= tmax) {
        float age = 0.0f;
        if (in.respawn == Respawn::CarryAge) {
            age = t - tmax * std::floor(t / tmax);
            if (!(age >= 0.0f && age < tmax)) age = 0.0f; // rounding at an exact multiple
        }
        return spawn(in, index, age);
    }
    ParticleRecord p = m;
    p.age = t;
    advance(p, in, in.dt);
    return p;
}

/// The record at reset (step 0): `count` particles, `first` .. `first + count` of them.
inline ParticleRecord initial(const StepInput& in, std::uint32_t index, StartMode mode, std::uint32_t first,
                              std::uint32_t count) {
    const float tmax = in.emitter.lifetime;
    const float stagger = (float(index - first) + 0.5f) / float(count);
    switch (mode) {
    case StartMode::Burst:
        return spawn(in, index, 0.0f);
    case StartMode::Ramp: {
        ParticleRecord p;
        p.position = glm::vec3(in.emitterToWorld[3]);
        p.age = -tmax * stagger;
        return p;
    }
    case StartMode::Steady:
    default:
        return spawn(in, index, tmax * stagger * 0.999999f);
    }
}

} // namespace sgfx::particles

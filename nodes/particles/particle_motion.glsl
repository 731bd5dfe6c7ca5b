// The seed's update rules for one particle (section "Обработка массива частиц"); ParticleMath.h
// is the CPU mirror, statement for statement.
uniform mat4 u_emitter;      // Mmodel: emitter frame → world
uniform vec2 u_emitterSize;  // W, H
uniform vec3 u_velocity;     // v0
uniform float u_spread;      // kv
uniform vec3 u_acceleration; // a
uniform float u_krot;
uniform float u_kvel;
uniform float u_tmax;
uniform float u_dt;          // ΔT
uniform uint u_step;
uniform uint u_seed;
uniform int u_carryAge;      // Respawn::CarryAge (1) or the seed's age 0 (0)
uniform int u_reflect;       // RotationBounce::Reflect (1) or the seed's clamp (0)

struct Particle {
    float age;
    vec3 position;
    vec3 velocity;
    vec3 angles0;
    vec3 angles;
};

float bounceAngle(float r, float dt) {
    float s = r >= 0.0 ? 1.0 : -1.0;
    float span = 2.0 * u_krot;
    float x = abs(r) + s * u_kvel * dt;
    if (u_reflect == 0) {
        if (x <= 0.0) return s > 0.0 ? -0.0 : 0.0;
        if (x >= span) return -s * span;
        return s * x;
    }
    if (span <= 0.0) return 0.0;
    float period = 2.0 * span;
    float u = x - period * floor(x / period);
    return u < span ? s * u : -s * (period - u);
}

void advanceParticle(inout Particle p, float dt) {
    p.position = p.position + p.velocity * dt + 0.5 * u_acceleration * (dt * dt);
    p.velocity = p.velocity + u_acceleration * dt;
    p.angles = vec3(bounceAngle(p.angles.x, dt), bounceAngle(p.angles.y, dt), bounceAngle(p.angles.z, dt));
}

Particle spawnParticle(uint index, float age) {
    uint rng = particleRandomStart(u_seed, index, u_step);
    float x = frand(rng) - 0.5;
    float y = frand(rng) - 0.5;
    Particle p;
    p.position = (u_emitter * vec4(u_emitterSize.x * x, u_emitterSize.y * y, 0.0, 1.0)).xyz;
    p.velocity = u_velocity + 2.0 * u_spread * vrand(rng);
    float r0x = frand(rng);
    float r0y = frand(rng);
    float r0z = frand(rng);
    p.angles0 = 6.28318530717958647692 * vec3(r0x, r0y, r0z);
    p.angles = 4.0 * u_krot * vrand(rng);
    p.age = age;
    if (age > 0.0) advanceParticle(p, age);
    return p;
}

Particle updateParticle(Particle m, uint index) {
    float t = m.age + u_dt;
    if (m.age < 0.0) {
        if (t < 0.0) {
            m.age = t;
            return m;
        }
        return spawnParticle(index, u_carryAge != 0 ? t : 0.0);
    }
    if (t >= u_tmax) {
        float age = 0.0;
        if (u_carryAge != 0) {
            age = t - u_tmax * floor(t / u_tmax);
            if (!(age >= 0.0 && age < u_tmax)) age = 0.0;
        }
        return spawnParticle(index, age);
    }
    Particle p = m;
    p.age = t;
    advanceParticle(p, u_dt);
    return p;
}

// frand of the seed as a stateless stream per (system seed, particle index, step): PCG output
// hash, exact integer arithmetic, so ParticleMath.h reproduces it bit for bit.
uint particleHash(uint v) {
    uint state = v * 747796405u + 2891336453u;
    uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

uint particleRandomStart(uint seed, uint index, uint step) {
    return particleHash(seed ^ particleHash(index ^ particleHash(step)));
}

float frand(inout uint state) {
    state = particleHash(state);
    return float(state >> 8) * (1.0 / 16777216.0);
}

vec3 vrand(inout uint state) { // Vrand = (frand − 0.5, frand − 0.5, frand − 0.5)
    float x = frand(state) - 0.5;
    float y = frand(state) - 0.5;
    float z = frand(state) - 0.5;
    return vec3(x, y, z);
}

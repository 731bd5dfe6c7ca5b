// Phase functions p(cos θ), θ between the light's direction of travel and the ray scattered
// towards the eye; each integrates to 1 over the sphere (VolumeMath.h is the CPU mirror).
// Lecture 12: Rayleigh f ∝ 1 + cos²θ (normalised here: 3/(16π)); Henyey–Greenstein, eq. (2).
uniform int u_phase; // 0 isotropic, 1 Henyey–Greenstein, 2 Rayleigh
uniform float u_g;

float volumePhase(float cosTheta) {
    const float inv4Pi = 0.07957747154594767;
    if (u_phase == 1) {
        float d = 1.0 + u_g * u_g - 2.0 * u_g * cosTheta;
        return inv4Pi * (1.0 - u_g * u_g) / (d * sqrt(d));
    }
    if (u_phase == 2) return 0.05968310365946075 * (1.0 + cosTheta * cosTheta); // 3/(16π)
    return inv4Pi;
}

#pragma once
/// @file
/// CPU mirror of oit_weight.glsl and of the composite pass (McGuire & Bavoil 2013), for tests
/// and for users who want to predict a pixel.
#include <algorithm>
#include <cmath>
#include <span>

namespace sgfx::oit {

/// w(z, α) of equations 7–10 (see OitWeight); z in depth-scale units, d the window depth.
template <class T> T weight(int equation, T alpha, T z, T d) {
    z = std::abs(z);
    auto clampW = [](T w) { return std::clamp(w, T(1e-2), T(3e3)); };
    switch (equation) {
    case 7:
        return alpha * clampW(T(10) / (T(1e-5) + std::pow(z / T(5), T(2)) + std::pow(z / T(200), T(6))));
    case 8:
        return alpha * clampW(T(10) / (T(1e-5) + std::pow(z / T(10), T(3)) + std::pow(z / T(200), T(6))));
    case 9:
        return alpha * clampW(T(0.03) / (T(1e-5) + std::pow(z / T(200), T(4))));
    case 10:
        return alpha * std::max(T(1e-2), T(3e3) * std::pow(T(1) - d, T(3)));
    default:
        return alpha; // constant
    }
}

/// One transparent layer over a pixel: straight colour, alpha, view depth.
struct Layer {
    double r, g, b; ///< straight (not premultiplied) linear colour
    double alpha;
    double weight; ///< w(z, α)
};

/// Eq. 6: C = (Σ C_i α_i w_i / Σ α_i w_i)·(1 − Π(1 − α_i)) + C_0·Π(1 − α_i), per channel.
inline void composite(std::span<const Layer> layers, const double background[3], double out[3]) {
    double sum[3] = {0, 0, 0}, sumA = 0, reveal = 1;
    for (const Layer& l : layers) {
        sum[0] += l.r * l.alpha * l.weight;
        sum[1] += l.g * l.alpha * l.weight;
        sum[2] += l.b * l.alpha * l.weight;
        sumA += l.alpha * l.weight;
        reveal *= 1 - l.alpha;
    }
    for (int c = 0; c < 3; ++c)
        out[c] = (sumA > 0 ? sum[c] / std::max(sumA, 1e-5) : 0.0) * (1 - reveal) + background[c] * reveal;
}

} // namespace sgfx::oit

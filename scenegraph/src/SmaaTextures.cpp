#include "sgfx/SmaaTextures.h"

#include <algorithm>
#include <cmath>
#include <optional>

namespace sgfx::smaa {

namespace {

// ∫ of the line from (x1, h1) to (x2, h2) over the pixel [a, a + 1] (clipped to the line), split
// into the part below zero (x, as a positive area) and above it (y).
glm::dvec2 segment(double x1, double h1, double x2, double h2, double a) {
    const double lo = std::max(a, x1), hi = std::min(a + 1.0, x2);
    if (!(hi > lo)) return {0.0, 0.0};
    auto h = [&](double x) { return h1 + (h2 - h1) * (x - x1) / (x2 - x1); };
    auto part = [](double l, double r, double hl, double hr) { // a piece not crossing zero
        const double mean = 0.5 * (hl + hr) * (r - l);
        return mean < 0.0 ? glm::dvec2(-mean, 0.0) : glm::dvec2(0.0, mean);
    };
    const double hl = h(lo), hr = h(hi);
    if ((hl < 0.0) == (hr < 0.0) || hl == 0.0 || hr == 0.0) return part(lo, hi, hl, hr);
    const double z = lo + (hi - lo) * hl / (hl - hr); // the zero crossing: two triangles
    return part(lo, z, hl, 0.0) + part(z, hi, 0.0, hr);
}

// The revectorised line's height at a crossing edge: half a pixel into this side (negative)
// or the other side (positive), the paper's orthogonal patterns (its section 4.1).
std::optional<double> endHeight(int c, int otherEnd) {
    if (c == kThis) return -0.5;
    if (c == kOther) return 0.5;
    // Both sides crossed: read as the Z shape the other end completes, else no information.
    if (c == kBoth && (otherEnd == kThis || otherEnd == kOther)) return otherEnd == kThis ? 0.5 : -0.5;
    return std::nullopt;
}

} // namespace

glm::vec2 area(int c1, int c2, int d1, int d2) {
    const std::optional<double> h1 = endHeight(c1, c2), h2 = endHeight(c2, c1);
    const double d = d1 + d2 + 1.0, a = d1;
    glm::dvec2 r(0.0);
    if (h1 && h2 && *h1 != *h2) {
        r = segment(0.0, *h1, d, *h2, a); // Z: one line from end to end
    } else {
        // L (one end) or U (both ends on one side): each end's half rises to the middle.
        if (h1) r += segment(0.0, *h1, 0.5 * d, 0.0, a);
        if (h2) r += segment(0.5 * d, 0.0, d, *h2, a);
    }
    return glm::vec2(r);
}

const std::vector<float>& areaTexture() {
    static const std::vector<float> texels = [] {
        std::vector<float> t(std::size_t(kAreaSize) * kAreaSize * 2, 0.0f);
        for (int c2 = 0; c2 < 5; ++c2)
            for (int c1 = 0; c1 < 5; ++c1)
                for (int d2 = 0; d2 < kMaxDistance; ++d2)
                    for (int d1 = 0; d1 < kMaxDistance; ++d1) {
                        const glm::vec2 v = area(c1, c2, d1, d2);
                        const std::size_t i = (std::size_t(c2 * kMaxDistance + d2) * kAreaSize +
                                               std::size_t(c1 * kMaxDistance + d1)) *
                                              2;
                        t[i] = v.x;
                        t[i + 1] = v.y;
                    }
        return t;
    }();
    return texels;
}

namespace {

// ∫ over [x0, x1] of clamp(h(x) − b, 0, 1) for the line h from (0, h0) to (n, hn): the area of the
// square [x0, x1] × [b, b + 1] below the line. Exact: the integrand is linear between the points
// where the line crosses b and b + 1, so the trapezoid rule is exact on each piece.
double areaBelow(double h0, double hn, double n, double x0, double x1, double b) {
    auto h = [&](double x) { return h0 + (hn - h0) * x / n; };
    auto f = [&](double x) { return std::clamp(h(x) - b, 0.0, 1.0); };
    std::vector<double> xs{x0, x1};
    for (double level : {b, b + 1.0}) {
        const double x = (level - h0) * n / (hn - h0); // the slope is never 0 here
        if (x > x0 && x < x1) xs.push_back(x);
    }
    std::sort(xs.begin(), xs.end());
    double sum = 0.0;
    for (std::size_t i = 1; i < xs.size(); ++i)
        sum += 0.5 * (f(xs[i - 1]) + f(xs[i])) * (xs[i] - xs[i - 1]);
    return sum;
}

} // namespace

glm::vec2 diagonalArea(int c1, int c2, int d1, int d2) {
    // Run pixel k covers [k, k + 1] × [k − 1, k]; its left and top edges' midpoints lie on
    // y = x − 0.5. Going on horizontally past an end lifts the lower end (shallower) or lowers
    // the upper one; vertically the reverse.
    const double n = d1 + d2 + 1.0, k = d1;
    const double h0 = -0.5 + 0.25 * ((c1 & 1) - (c1 >> 1 & 1));
    const double hn = n - 0.5 + 0.25 * ((c2 >> 1 & 1) - (c2 & 1));
    const double inside = areaBelow(h0, hn, n, k, k + 1.0, k - 1.0);
    const double above = areaBelow(h0, hn, n, k, k + 1.0, k);
    return glm::vec2(float(1.0 - inside), float(above));
}

const std::vector<float>& diagonalAreaTexture() {
    static const std::vector<float> texels = [] {
        std::vector<float> t(std::size_t(kDiagonalAreaSize) * kDiagonalAreaSize * 2, 0.0f);
        for (int c2 = 0; c2 < 4; ++c2)
            for (int c1 = 0; c1 < 4; ++c1)
                for (int d2 = 0; d2 < kMaxDiagonal; ++d2)
                    for (int d1 = 0; d1 < kMaxDiagonal; ++d1) {
                        const glm::vec2 v = diagonalArea(c1, c2, d1, d2);
                        const std::size_t i = (std::size_t(c2 * kMaxDiagonal + d2) * kDiagonalAreaSize +
                                               std::size_t(c1 * kMaxDiagonal + d1)) *
                                              2;
                        t[i] = v.x;
                        t[i + 1] = v.y;
                    }
        return t;
    }();
    return texels;
}

int searchDecode(bool farSide, int line, int crossing) {
    if (line == 2 || crossing == 2 || line < 0 || line > 4 || crossing < 0 || crossing > 4) return 0;
    const bool lineFirst = line >= 3, lineNext = line == 1 || line == 4;
    const bool crossFirst = crossing >= 3, crossNext = crossing == 1 || crossing == 4;
    if (!lineFirst) return 0;
    if (farSide) { // a crossing edge ends the line after its pixel
        if (crossFirst || !lineNext) return 1;
        return crossNext ? 2 : 3;
    }
    if (crossFirst) return 0; // a crossing edge ends the line before its pixel
    return !lineNext || crossNext ? 1 : 3;
}

const std::vector<float>& searchTexture() {
    static const std::vector<float> texels = [] {
        std::vector<float> t(std::size_t(kSearchWidth) * kSearchHeight);
        for (int far = 0; far < 2; ++far)
            for (int c = 0; c < 5; ++c)
                for (int l = 0; l < 5; ++l)
                    t[std::size_t((c + 5 * far) * kSearchWidth + l)] = float(searchDecode(far != 0, l, c));
        return t;
    }();
    return texels;
}

} // namespace sgfx::smaa

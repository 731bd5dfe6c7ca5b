// SMAA's generated look-up textures (no GL): the area texture against trapezoids integrated by
// hand here, and the search texture's decoding, run over random edge strings the way the weights
// shader runs it (bilinear fetches of two pixels at 0.75 / 0.25), against a plain scan.
#include <sgfx/SmaaTextures.h>

#include <gtest/gtest.h>

#include <random>
#include <vector>

using namespace sgfx;

namespace {

// The texel the weights shader fetches for crossing codes c1, c2 and distances d1, d2.
glm::vec2 texel(int c1, int c2, int d1, int d2) {
    const std::vector<float>& t = smaa::areaTexture();
    const std::size_t i = (std::size_t(c2 * smaa::kMaxDistance + d2) * smaa::kAreaSize +
                           std::size_t(c1 * smaa::kMaxDistance + d1)) *
                          2;
    return {t[i], t[i + 1]};
}

} // namespace

TEST(SmaaTextures, AreaOfAnLIsTheTrapezoidUnderItsHalfLine) {
    ASSERT_EQ(smaa::areaTexture().size(), std::size_t(smaa::kAreaSize) * smaa::kAreaSize * 2);
    // A crossing on this side at the first end only: the line rises from half a pixel below the
    // edge at the end (x = 0) to the edge at the middle of the d = d1 + d2 + 1 pixels, its depth
    // below the edge 0.5·(1 − 2x/d). Pixel [d1, d1 + 1] fully in the first half: a trapezoid.
    for (auto [d1, d2] : {std::pair{0, 5}, std::pair{2, 9}, std::pair{0, 0}, std::pair{10, 30}}) {
        const double d = d1 + d2 + 1.0;
        auto depth = [&](double x) { return std::max(0.0, 0.5 * (1.0 - 2.0 * x / d)); };
        double expected;
        if (d1 + 1 <= d / 2)
            expected = 0.5 * (depth(d1) + depth(d1 + 1));
        else // the middle pixel: a triangle up to d/2
            expected = 0.5 * depth(d1) * (d / 2 - d1);
        const glm::vec2 a = texel(smaa::kThis, smaa::kNone, d1, d2);
        EXPECT_NEAR(a.x, expected, 1e-6) << d1 << "," << d2;
        EXPECT_EQ(a.y, 0.0f);
        // The mirror image: the crossing on the other side gives the same area to the other pixel.
        const glm::vec2 m = texel(smaa::kOther, smaa::kNone, d1, d2);
        EXPECT_NEAR(m.y, expected, 1e-6);
        EXPECT_EQ(m.x, 0.0f);
    }
    // Past the middle an L gives nothing; no crossing at all gives nothing.
    EXPECT_EQ(texel(smaa::kThis, smaa::kNone, 6, 2), glm::vec2(0.0f));
    EXPECT_EQ(texel(smaa::kNone, smaa::kNone, 1, 1), glm::vec2(0.0f));
}

TEST(SmaaTextures, AreaOfAZAndAU) {
    // Z: from half a pixel below at x = 0 to half above at x = d, crossing the edge at d/2.
    // d1 = 1, d2 = 1 (d = 3): the middle pixel [1, 2] holds two triangles of base ½ and height
    // 1/6 (the line climbs 1/3 a pixel): 1/24 each side.
    const glm::vec2 z = texel(smaa::kThis, smaa::kOther, 1, 1);
    EXPECT_NEAR(z.x, 1.0 / 24, 1e-6);
    EXPECT_NEAR(z.y, 1.0 / 24, 1e-6);
    // Its first pixel [0, 1]: depths 0.5 and 1/6, a trapezoid of 1/3.
    EXPECT_NEAR(texel(smaa::kThis, smaa::kOther, 0, 2).x, (0.5 + 1.0 / 6) / 2, 1e-6);
    // U over d = 4 (both ends on this side): each half falls to the middle; pixel [1, 2] under
    // the first half, depths 0.5·(1 − 2/4) = 0.25 at 1 and 0 at 2: 1/8.
    const glm::vec2 u = texel(smaa::kThis, smaa::kThis, 1, 2);
    EXPECT_NEAR(u.x, 0.125, 1e-6);
    EXPECT_EQ(u.y, 0.0f);
    // Both sides crossed at one end, this side at the other: read as a Z.
    EXPECT_EQ(texel(smaa::kBoth, smaa::kThis, 0, 2), texel(smaa::kOther, smaa::kThis, 0, 2));
}

TEST(SmaaTextures, SearchDecodingFindsTheLinesEndsOnRandomEdges) {
    // One row of pixels: line[i] (the edge the line runs along) and cross[i] (the crossing edge
    // on pixel i's far side, `farSide`, or between pixel i − 1 and i, not). From pixel 0 the line
    // goes on while the line edge is set and no crossing edge cuts it; its last pixel by a plain
    // scan, against the shader's walk: fetch pairs (i, i + 1) at weights 0.75 / 0.25, decode.
    std::mt19937 random(29);
    for (int trial = 0; trial < 4000; ++trial) {
        const bool farSide = trial % 2;
        const int n = 24;
        std::vector<int> line(n + 2), cross(n + 2);
        for (int i = 0; i < n + 2; ++i) {
            line[i] = random() % 8 != 0;
            cross[i] = random() % 6 == 0;
        }
        line[0] = 1;
        if (!farSide) cross[0] = 0; // pixel 0 is on the line
        int scan = 0;
        while (scan + 1 < n && (farSide ? !cross[scan] : true) && line[scan + 1] &&
               (farSide || !cross[scan + 1]))
            ++scan;
        int walk = -1;
        for (int i = 0; i < n; i += 2) {
            const double l = 0.75 * line[i] + 0.25 * line[i + 1], c = 0.75 * cross[i] + 0.25 * cross[i + 1];
            const int k = int(smaa::searchTexture()[std::size_t(
                (int(std::lround(4 * c)) + 5 * farSide) * smaa::kSearchWidth + int(std::lround(4 * l)))]);
            EXPECT_EQ(k, smaa::searchDecode(farSide, int(std::lround(4 * l)), int(std::lround(4 * c))));
            if (k < 3) {
                walk = i - 1 + k;
                break;
            }
        }
        if (walk < 0 || scan + 1 >= n) continue; // ran past the row: not decided here
        EXPECT_EQ(walk, scan) << "trial " << trial;
    }
}

TEST(SmaaTextures, DiagonalAreaOfAStraight45DegreeRunIsAnEighth) {
    // No bend at either end: the line y = x − 0.5 through the edges' midpoints cuts a right
    // triangle with legs of half a pixel off the run pixel and off the pixel above: 1/8 each.
    ASSERT_EQ(smaa::diagonalAreaTexture().size(),
              std::size_t(smaa::kDiagonalAreaSize) * smaa::kDiagonalAreaSize * 2);
    for (auto [d1, d2] : {std::pair{1, 1}, std::pair{0, 5}, std::pair{7, 3}, std::pair{19, 19}}) {
        const glm::vec2 a = smaa::diagonalArea(0, 0, d1, d2);
        EXPECT_NEAR(a.x, 0.125, 1e-6) << d1 << "," << d2;
        EXPECT_NEAR(a.y, 0.125, 1e-6) << d1 << "," << d2;
        const std::size_t i = (std::size_t(3 * smaa::kMaxDiagonal + d2) * smaa::kDiagonalAreaSize +
                               std::size_t(3 * smaa::kMaxDiagonal + d1)) *
                              2; // both ends going on both ways: the shifts cancel
        EXPECT_NEAR(smaa::diagonalAreaTexture()[i], 0.125f, 1e-6) << d1 << "," << d2;
    }
}

TEST(SmaaTextures, DiagonalAreaMatchesAPointCount) {
    // The header's line (ends moved a quarter pixel by the crossing codes) against a count of a
    // 500 × 500 grid of points below it in the run pixel and the pixel above: error ≤ 1/500 + ε.
    constexpr int kGrid = 500;
    for (int c1 = 0; c1 < 4; ++c1)
        for (int c2 = 0; c2 < 4; ++c2)
            for (auto [d1, d2] : {std::pair{0, 2}, std::pair{1, 1}, std::pair{3, 0}, std::pair{4, 9}}) {
                const double n = d1 + d2 + 1.0, k = d1;
                const double y0 = -0.5 + 0.25 * ((c1 & 1) ? 1 : 0) - 0.25 * ((c1 & 2) ? 1 : 0);
                const double y1 = n - 0.5 - 0.25 * ((c2 & 1) ? 1 : 0) + 0.25 * ((c2 & 2) ? 1 : 0);
                int inRun = 0, inAbove = 0;
                for (int i = 0; i < kGrid; ++i)
                    for (int j = 0; j < kGrid; ++j) {
                        const double x = k + (i + 0.5) / kGrid, f = (j + 0.5) / kGrid;
                        const double line = y0 + (y1 - y0) * x / n;
                        inRun += (k - 1.0 + f) < line;
                        inAbove += (k + f) < line;
                    }
                const glm::vec2 a = smaa::diagonalArea(c1, c2, d1, d2);
                const double tol = 1.0 / kGrid + 1e-4;
                EXPECT_NEAR(a.x, 1.0 - double(inRun) / (kGrid * kGrid), tol) << c1 << c2 << d1 << d2;
                EXPECT_NEAR(a.y, double(inAbove) / (kGrid * kGrid), tol) << c1 << c2 << d1 << d2;
            }
}

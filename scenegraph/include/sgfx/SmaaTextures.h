#pragma once
// SMAA's look-up textures (Jimenez et al. 2012, "SMAA: Enhanced Subpixel Morphological
// Antialiasing"), generated on the CPU at first use by sgfx's own code (docs/anti-aliasing.md).
// Public so tests can check them against hand-computed values.
#include "sgfx/Export.h"

#include <glm/glm.hpp>

#include <vector>

namespace sgfx::smaa {

// A line end's crossing edges as the weights pass reads them: one bilinear fetch between the
// line's own side (weight 0.75) and the other side (0.25) of the edge texture, times 4 and
// rounded. 0: none, 1: on the other side only, 3: on this side only, 4: both. 2 does not occur.
enum Crossing : int { kNone = 0, kOther = 1, kThis = 3, kBoth = 4 };

// Distances along a line, 0..kMaxDistance − 1 (longer ones are clamped): the ultra preset's 32
// search steps of two pixels each, plus the pixels decoded at each end.
inline constexpr int kMaxDistance = 72;

// The fractions of a pixel at distance d1 from a line's first end and d2 from its other end
// that the revectorised line gives to the neighbour across the edge (x: this pixel takes from
// the other side, y: the other side's pixel takes from this one), for crossing codes c1, c2.
SGFX_API glm::vec2 area(int c1, int c2, int d1, int d2);

// The area texture: 5·kMaxDistance square, two floats a texel, rows bottom first; texel
// (c1·kMaxDistance + d1, c2·kMaxDistance + d2) holds area(c1, c2, d1, d2).
SGFX_API const std::vector<float>& areaTexture();
inline constexpr int kAreaSize = 5 * kMaxDistance;

// The search texture: decoding of one bilinear fetch of two neighbouring pixels along a line,
// the nearer (weight 0.75) and the next (0.25): line = 4 × the fetched line edge, crossing = 4 ×
// the fetched crossing edge, both rounded. `farSide`: the crossing edge of a pixel lies on its
// far side along the search (else between it and the pixel before). The value is how many of
// the two pixels still belong to the line before it ends (0, 1 or 2), or 3: both do and the line
// goes on.
SGFX_API int searchDecode(bool farSide, int line, int crossing);
// 5 × 10 floats, texel (line, crossing + 5·farSide) = searchDecode(farSide, line, crossing).
SGFX_API const std::vector<float>& searchTexture();
inline constexpr int kSearchWidth = 5, kSearchHeight = 10;

// Diagonal patterns (the paper's sec. 4.2): a run of pixels along a 45° staircase, each with both
// its crossing edges (top and left for '/', top and the right neighbour's left for '\\'). The run
// is d1 + d2 + 1 pixels long, this one d1 from its lower end. c1, c2: how the staircase goes on
// past the lower and upper end, bit 0 horizontally (the line is shallower there), bit 1
// vertically (steeper). The revectorised line runs through the edge midpoints, each end moved a
// quarter pixel toward the side the staircase goes on. x: the part of this pixel beyond the line
// (this pixel takes it from above), y: the part of the pixel above on this side (it takes it from
// this one), both exact areas (the line clipped against the pixel squares). Mirrored for '\\'.
SGFX_API glm::vec2 diagonalArea(int c1, int c2, int d1, int d2);
// Distances 0..kMaxDiagonal − 1: the ultra preset's 16 one-pixel steps plus the ends.
inline constexpr int kMaxDiagonal = 20;
// 4·kMaxDiagonal square, two floats a texel: texel (c1·kMaxDiagonal + d1, c2·kMaxDiagonal + d2).
SGFX_API const std::vector<float>& diagonalAreaTexture();
inline constexpr int kDiagonalAreaSize = 4 * kMaxDiagonal;

} // namespace sgfx::smaa

#pragma once
/// @file
/// Triangle order of loaded meshes through meshoptimizer (Debian's libmeshoptimizer-dev, optional
/// at build time): vertex-cache order (T. Forsyth 2006, "Linear-speed vertex cache
/// optimisation", as meshoptimizer implements it), then overdraw order (Sander, Nehab & Barczak
/// 2007, "Fast triangle reordering for vertex locality and reduced overdraw"), then vertex-fetch
/// order. The triangles stay the same set, each with the same three vertex records and winding;
/// only their order and the vertices' order change, so an opaque, depth-tested mesh draws the same
/// image.
#include "sgfx/Export.h"
#include <sgfx/Geometry.h>
#include <sgfx/LOD.h>

#include <array>
#include <cstddef>
#include <string>
#include <vector>

namespace sgfx {

/// Which of the three orders optimizeMesh applies.
struct SGFX_API MeshOrderOptions {
    bool vertexCache = true;
    /// Trades up to this factor of vertex-cache misses (ACMR) for less overdraw; 0 turns the
    /// overdraw pass off.
    float overdrawThreshold = 1.05f;
    bool vertexFetch = true;
};

/// Whether sgfx was built with meshoptimizer (SGFX_HAVE_MESHOPTIMIZER).
SGFX_API bool meshOptimizerAvailable();

/// Reorders the triangles and vertices of `geometry` (exact duplicate vertices over all its
/// streams are welded first; vertices no triangle uses are dropped) and dirties it. Returns false,
/// leaving it untouched, with the reason in `*reason` when given: sgfx built without
/// meshoptimizer, a mode other than Triangles, a skinned or morphed geometry (joints, weights or
/// morph targets), a blended or transparent-bin StateSet or one without depth
/// test or depth writes (the order is visible there), or fewer than two triangles. Throws
/// std::invalid_argument (Geometry::validate) for arrays that disagree or an index out of range.
SGFX_API bool optimizeMesh(Geometry& geometry, const MeshOrderOptions& options = {},
                           std::string* reason = nullptr);

/// optimizeMesh on every Geometry under `root`, once each however often it is shared; a geometry
/// drawn anywhere under a blended or depth-less StateSet (resolved from `root` down) is left as it
/// is. Returns how many were reordered. Without meshoptimizer it says so once on stderr.
SGFX_API std::size_t optimizeMeshes(Node& root, const MeshOrderOptions& options = {});

/// Levels of detail made at load (meshoptimizer's edge-collapse simplifier, quadric error,
/// Garland & Heckbert 1997), switched so that no level is more than `errorPixels` off on screen.
struct SGFX_API AutoLodOptions {
    bool enabled = false; ///< for GltfOptions::autoLod; makeErrorLod ignores it
    /// No level under this many triangles, and no LOD for a mesh under twice as many.
    std::size_t minTriangles = 64;
    float errorPixels = 1.0f; ///< the largest projected error of a shown level
    /// The smallest focal length, in pixels (viewport height / (2 tan(fovy / 2))), the ranges hold
    /// for: a level's error is measured from the nearest point of the LOD's sphere, which a wider
    /// view (shorter focal length) sees closer at the same projected size. 500: 720 rows at 72°.
    float focalPixels = 500.0f;
    /// Keep the mesh's open border where it is, so meshes that meet there do not crack apart.
    bool lockBorder = true;
    /// The most threads the work uses at once (0: std::thread::hardware_concurrency()): addAutoLods
    /// spreads the meshes over them; makeErrorLod alone bounds a large level's two sides on two
    /// unless this is 1. The LODs are the same for any count.
    unsigned threads = 0;
};

/// How hausdorffBound settled its pieces (diagnostics for benches and tests; summed over both sides).
struct SGFX_API HausdorffBoundStats {
    /// The bound that gave a settled piece its number: the projection along the piece's normal, the
    /// convexity bound through one triangle, the centroid's distance plus the radius (Lipschitz), a
    /// bound inherited from the parent piece, or exact (all corners share a nearest triangle).
    enum Path { Projection, Convex, Lipschitz, Inherited, Exact, Paths };
    std::array<std::size_t, Paths> settled{}; ///< settled pieces, by path
    std::size_t atMaxDepth = 0;               ///< settled at the split limit, above the accept threshold
    std::size_t queries = 0;                  ///< nearest-point queries through the other side's BVH
    /// Projection bounds tried, and why they failed: a degenerate piece, one orientation not
    /// covering it, the covered area exceeding it (overlap), or the height clip still cutting area.
    std::size_t projections = 0, degenerate = 0, uncovered = 0, overlap = 0, cut = 0;
    std::size_t crackMargins =
        0;              ///< projection bounds that charged a crack margin above the absolute slack / 4
    float lower = 0.0f; ///< the largest distance found at a point: a lower bound of the result
    float upper = 0.0f; ///< the bound before float rounding is added
    Path worst = Exact; ///< the path of the piece that set `upper`
    std::array<float, 2> sides{}; ///< hausdorffBound's two one-sided bounds: a to b's surface, b to a's
    std::array<glm::vec3, 3> worstPiece{}; ///< the piece that set `upper`
    int worstDepth = 0;                    ///< its number of splits
    void add(const HausdorffBoundStats& o);
};

/// One simplified level and its errors (absolute, in the geometry's frame).
struct SGFX_API AutoLodLevel {
    std::shared_ptr<Geometry> geometry;
    /// meshoptimizer's estimate (result_error times meshopt_simplifyScale). Reported only: in 0.18
    /// it is the square root of a collapse's area-weighted mean squared distance to the collapsed
    /// triangles' planes, not a bound (tests/auto_lod_test.cpp finds levels it under-estimates).
    float simplifierError = 0.0f;
    /// An upper bound of the symmetric Hausdorff distance to the full mesh (hausdorffBound): what
    /// sets the ranges.
    float measuredError = 0.0f;
    float minPixels = 0.0f, maxPixels = 0.0f; ///< the projected diameters it is shown at
    HausdorffBoundStats boundStats;           ///< how measuredError was found
};

/// The largest distance from a sample point of either mesh to the other's surface: 8 points per
/// triangle (corners, edge midpoints, centroid and one inner point), each to the nearest point of
/// the other mesh's triangles through its TriangleBvh. A lower bound of the Hausdorff distance
/// (sampling can only under-estimate it); hausdorffBound is the upper bound the ranges use.
SGFX_API float hausdorffDistance(const Geometry& a, const Geometry& b);

/// An upper bound of the symmetric Hausdorff distance between the drawn surfaces of `a` and `b`
/// (triangles of zero area draw nothing and are left out; it never under-estimates; float rounding
/// is added). For each side, each triangle is bounded first by convexity: its distance to one
/// triangle of the other surface is at most the largest of its corners' (exact when one triangle is
/// nearest to all three corners). Then along its normal: the other surface's triangles (less those
/// within ~1 degree of edge-on) are projected onto its plane and clipped to it; where those of one
/// orientation cover it (the other surface is a graph over it), every point is at most the largest
/// distance from a corner of a clipped polygon to its triangle, plus sqrt(2 x uncovered area /
/// smallest angle) for cracks up to 1e-3 of its area. Where neither is within the slack of the
/// largest distance found at a point (relativeSlack times it plus absoluteSlack), a branch and
/// bound: pieces are split where their corners' nearest triangles change (at the point of each
/// edge where the two triangles' distances balance), slivers are bounded by their longest edge plus
/// their height, and the centroid's distance plus the radius (Lipschitz) is the last resort; at
/// most 8 splits and 256 pieces per triangle (past that the looser bound is kept). The two sides
/// run on two threads for large meshes. `stats`, when given, gets the counts of how pieces were
/// settled. Throws std::invalid_argument for a negative or non-finite slack or a geometry without
/// triangles.
SGFX_API float hausdorffBound(const Geometry& a, const Geometry& b, float relativeSlack = 0.1f,
                              float absoluteSlack = 0.0f, HausdorffBoundStats* stats = nullptr);

/// An LOD over `full` (shared, finest) and simplified copies with ½, ¼, ... of its triangles,
/// down to options.minTriangles. Level i's error is its hausdorffBound (relative slack 0.1, absolute
/// slack r t / (4 f); the level's vertices are full's, so they need no distance query, and no piece
/// is refined below the finer level's error), never less
/// than a finer level's; with r the full mesh's bounding radius, f = focalPixels and t =
/// errorPixels, level i is shown while the projected diameter p <= 2f / (1 + e_i f / (r t)), the
/// size at which an error e_i seen from the sphere's nearest point spans t pixels. The copies
/// share full's StateSet and vertex streams' kinds (a subset of its vertices each). Returns
/// nullptr, with the reason in `*reason`, for a mesh it does not simplify: sgfx without
/// meshoptimizer, not indexed Triangles, skinned or morphed, instanced, too few triangles, or no
/// level that removes at least a fifth of the triangles. `levels` gets the simplified levels.
SGFX_API std::shared_ptr<LOD> makeErrorLod(const std::shared_ptr<Geometry>& full,
                                           const AutoLodOptions& options,
                                           std::vector<AutoLodLevel>* levels = nullptr,
                                           std::string* reason = nullptr);

/// Puts makeErrorLod's LOD in place of every Geometry child of a Group under `root`, one LOD per
/// Geometry however often it is shared (parents of a shared mesh share its LOD). Existing LOD
/// nodes and what is under them are left alone. Returns how many LODs were made. The meshes are
/// simplified on options.threads threads; the graph itself is changed on the caller's thread only.
SGFX_API std::size_t addAutoLods(Node& root, const AutoLodOptions& options);

} // namespace sgfx

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

#include <cstddef>
#include <string>

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
/// test or depth writes (the order is visible there), or fewer than two triangles.
SGFX_API bool optimizeMesh(Geometry& geometry, const MeshOrderOptions& options = {},
                           std::string* reason = nullptr);

/// optimizeMesh on every Geometry under `root`, once each however often it is shared; a geometry
/// drawn anywhere under a blended or depth-less StateSet (resolved from `root` down) is left as it
/// is. Returns how many were reordered. Without meshoptimizer it says so once on stderr.
SGFX_API std::size_t optimizeMeshes(Node& root, const MeshOrderOptions& options = {});

} // namespace sgfx

#pragma once
/// @file
/// Levels of detail made by edge-collapse decimation (OpenMesh's DecimaterT with quadric error
/// metrics, Garland & Heckbert 1997), and an LOD node that shows them by size on screen.
#include "sgfx/Export.h"
#include <sgfx/Geometry.h>
#include <sgfx/LOD.h>

#include <memory>
#include <span>
#include <vector>

namespace sgfx {

/// One decimated copy of `geometry` per ratio, each with about ratio × its triangles (more
/// where the mesh cannot collapse further: boundary and UV/colour-seam vertices are locked so
/// nothing cracks, and non-manifold triangles are kept as they are). Half-edge collapses keep a subset of the
/// positions; normals are recomputed smooth (area-weighted, shared across seams by position), so hard edges
/// soften; texcoords and colours are carried per vertex; tangents are dropped. A ratio of 1 gives an
/// unchanged copy. The copies have no state set. Throws std::invalid_argument for geometry that is not
/// PrimitiveMode::Triangles, has no triangles or is invalid (Geometry::validate), or for a ratio that is NaN
/// or outside (0, 1].
SGFX_API std::vector<std::shared_ptr<Geometry>> simplify(const Geometry& geometry,
                                                         std::span<const float> triangleRatios);
SGFX_API std::shared_ptr<Geometry> simplify(const Geometry& geometry, float triangleRatio);

/// One level of makeLod: this share of the triangles, shown from minPixels of projected diameter
/// up to the next finer level's minPixels.
struct SGFX_API LodLevel {
    float triangleRatio = 1.0f;
    float minPixels = 0.0f;
};

/// Full detail above 300 px, half the triangles from 100 px, 12 % below.
SGFX_API std::span<const LodLevel> defaultLodLevels();

/// An LOD whose children are `full` (for a ratio of 1, shared, not copied) and decimated copies,
/// finest first, each sharing full's state set. Levels must come with strictly decreasing
/// minPixels (std::invalid_argument otherwise, or for a bad ratio, as simplify).
SGFX_API std::shared_ptr<LOD> makeLod(std::shared_ptr<Geometry> full,
                                      std::span<const LodLevel> levels = defaultLodLevels());

} // namespace sgfx

#pragma once
/// @file
/// The questions a simulation asks every frame, on top of Intersection.h.
#include "sgfx/Export.h"
#include "sgfx/Intersection.h"

#include <cstddef>
#include <optional>

namespace sgfx {

class Viewer;

/// Options shared by the helpers.
struct SGFX_API QueryOptions {
    NodeMask mask = ~NodeMask{0}; ///< nodes with (nodeMask & mask) == 0 are ignored
    /// World frame of the scene node's parent (identity when the scene is the root).
    glm::dmat4 parentToWorld{1.0};
};

/// The highest surface under the world point (x, y): the nearest hit of a vertical segment through
/// the scene's world bound (Z up). nullopt where there is no surface below (x, y).
SGFX_API std::optional<Intersection> terrainHit(Node& scene, double x, double y,
                                                const QueryOptions& options = {});
/// terrainHit(...)->point.z, or nullopt.
SGFX_API std::optional<double> heightOfTerrain(Node& scene, double x, double y,
                                               const QueryOptions& options = {});

/// True when no triangle lies on the segment from `a` to `b` (world). Stops at the first hit.
SGFX_API bool lineOfSight(Node& scene, const glm::dvec3& a, const glm::dvec3& b,
                          const QueryOptions& options = {});

/// The world segment that a pixel of `camera`'s viewport covers from its near to its far plane.
/// (x, y): pixels from the viewport's top-left corner (mouse coordinates), fractions allowed.
struct SGFX_API PickRay {
    glm::dvec3 start, end;
};
SGFX_API PickRay pickRay(const Camera& camera, double x, double y);

/// What a click hits: the nearest triangle under the pixel, with LODs as shown and billboards
/// as turned in that view.
struct SGFX_API PickResult {
    Intersection hit;
    const Camera* camera = nullptr; ///< the view that was clicked
};
SGFX_API std::optional<PickResult> pick(const Camera& camera, Node& scene, double x, double y,
                                        NodeMask mask = ~NodeMask{0});
/// The viewer's channel whose viewport holds the target pixel (x, y) (origin top left), then as
/// above. nullopt when no viewport holds it or nothing is hit.
SGFX_API std::optional<PickResult> pick(Viewer& viewer, double x, double y, NodeMask mask = ~NodeMask{0});

/// What the query caches below `scene` hold, each counted once however often it is shared: the
/// geometries' triangle BVHs, and the subtree indexes (the scene's and the nested ones). Builds
/// what is missing, like prepareForQueries. The geometries' own arrays are not counted.
struct SGFX_API QueryMemory {
    std::size_t bvhBytes = 0;
    std::size_t indexBytes = 0;
    std::size_t triangles = 0; ///< in the BVHs (degenerate triangles are left out of them)
};
SGFX_API QueryMemory queryMemory(Node& scene);

/// Computes every bound and builds every BVH below `scene` now, so that queries started on other
/// threads afterwards find them built (and a first query pays no build). Not thread-safe itself:
/// call it on the thread that changes the scene.
SGFX_API void prepareForQueries(Node& scene);

} // namespace sgfx

#pragma once
/// @file
/// Scene queries in OpenSceneGraph's vocabulary: intersectors (what is asked) run by an
/// IntersectionVisitor (how the graph is walked). Everything is read-only and in double precision
/// from the world down to each triangle, so a hit on a 100 km terrain is exact to well under a
/// millimetre. See docs/queries.md for the threading rules.
#include "sgfx/Export.h"
#include "sgfx/Math.h"
#include "sgfx/NodeVisitor.h"
#include "sgfx/TriangleBvh.h"

#include <glm/glm.hpp>

#include <array>
#include <cstdint>
#include <limits>
#include <optional>
#include <vector>

namespace sgfx {

class Camera;
struct SubtreeIndex;

/// One hit of a query on one triangle.
struct SGFX_API Intersection {
    /// Line and ray: distance from the start along the line (metres); sphere: from the centre to
    /// the nearest point of the triangle; polytope: of `point` from the polytope's first plane.
    double distance = 0.0;
    double ratio = 0.0;    ///< line segment: distance / length (0 at the start, 1 at the end)
    glm::dvec3 point{0.0}; ///< world
    glm::dvec3 geometricNormal{
        0.0};                    ///< unit, world, on the front side (winding and the transform's determinant)
    glm::dvec3 normal{0.0};      ///< the vertex normals interpolated, unit, world; geometricNormal when none
    glm::dvec3 barycentric{0.0}; ///< weights of the triangle's three vertices at `point`
    std::optional<glm::dvec2> texcoord; ///< TEXCOORD_0 interpolated, when the geometry has them
    std::vector<Node*> nodePath;        ///< from the visited node down to `geometry`
    Geometry* geometry = nullptr;
    std::uint32_t primitiveIndex = 0;             ///< triangle number in draw order (strips: per triangle)
    std::array<std::uint32_t, 3> vertexIndices{}; ///< the triangle's vertices in the geometry
    std::uint32_t instanceIndex = 0;              ///< entry of Geometry::instances (0 when not instanced)
    glm::dmat4 worldMatrix{1.0};                  ///< geometry frame to world (instance matrix included)
};

/// A node's frame relative to the world while a query walks the graph.
struct SGFX_API QueryFrame {
    glm::dmat4 toWorld{1.0};
    glm::dmat4 toLocal{1.0};
    static QueryFrame of(const glm::dmat4& toWorld);
};

/// What the visitor hands an intersector with a geometry.
struct SGFX_API QueryContext {
    const std::vector<Node*>* path = nullptr; ///< down to the geometry
    std::uint32_t instance = 0;
};

/// The question a query asks. Hits are collected during a visit and sorted by distance at its end.
class SGFX_API Intersector {
public:
    /// All: every hit. Nearest: only the closest (the search prunes everything farther).
    /// Any: the first hit found ends the whole visit (line of sight).
    enum class Limit : std::uint8_t { All, Nearest, Any };
    Limit limit = Limit::All;

    virtual ~Intersector() = default;
    const std::vector<Intersection>& intersections() const { return hits_; }
    bool containsIntersections() const { return !hits_.empty(); }
    /// The closest hit; nullptr when there is none.
    const Intersection* nearest() const { return hits_.empty() ? nullptr : &hits_.front(); }
    /// Forgets the hits, for another visit.
    virtual void reset() { hits_.clear(); }

    // For traversals (IntersectionVisitor):
    /// Puts the query into `frame`'s local coordinates for the entry() calls that follow (one
    /// transform per frame rather than one per box).
    virtual void setFrame(const QueryFrame& frame) = 0;
    /// An order key for `box`, in the local coordinates of the frame set last: where the query
    /// enters it (lines: the parameter t; others 0), +infinity when it cannot touch it
    /// (conservative). Traversals visit smaller keys first and skip keys beyond reach().
    virtual double entry(const QueryBox& box) const = 0;
    bool mayHit(const QueryBox& box) const { return entry(box) != std::numeric_limits<double>::infinity(); }
    /// The largest entry key still worth visiting (shrinks as Limit::Nearest finds closer hits).
    virtual double reach() const { return std::numeric_limits<double>::infinity(); }
    /// Tests the triangles of `geometry` (through its BVH, in `frame`) and records hits. Leaves the
    /// frame set by setFrame as it was.
    virtual void intersect(const Geometry& geometry, const TriangleBvh& bvh, const QueryFrame& frame,
                           const QueryContext& context) = 0;
    /// True when the limit is met and the visit can stop (Any, after a hit).
    bool done() const { return limit == Limit::Any && !hits_.empty(); }
    /// Sorts the hits by distance (the visitor calls it at the end of a visit).
    void finish();

protected:
    /// Keeps `hit` as the limit says (Nearest: only if it is closer than the kept one).
    void record(Intersection&& hit);
    /// Fills the hit's world data from its triangle: point from barycentrics, normals, texcoord.
    static void complete(Intersection& hit, const Geometry& geometry, const QueryFrame& frame,
                         const QueryContext& context);
    std::vector<Intersection> hits_;
};

/// A line segment from `start` to `end` (world; OSG's LineSegmentIntersector), or with
/// `infinite()` a ray from `start` through `end` (OSG's RayIntersector). Both faces of every
/// triangle are hit; Intersection::geometricNormal tells which side.
class SGFX_API LineSegmentIntersector : public Intersector {
public:
    /// Throws std::invalid_argument when a point is not finite or start == end.
    LineSegmentIntersector(const glm::dvec3& start, const glm::dvec3& end);
    const glm::dvec3& start() const { return start_; }
    const glm::dvec3& end() const { return end_; }

    void setFrame(const QueryFrame& frame) override;
    double entry(const QueryBox& box) const override;
    double reach() const override { return searchLimit(); }
    void intersect(const Geometry& geometry, const TriangleBvh& bvh, const QueryFrame& frame,
                   const QueryContext& context) override;

protected:
    /// The parameter range searched along start + t (end - start): [0, 1] for a segment.
    double tMax_ = 1.0;

private:
    double searchLimit() const; ///< tMax_, or the kept hit's t under Limit::Nearest
    glm::dvec3 start_, end_;
    double length_;
    glm::dvec3 localStart_{0.0}, localDirection_{0.0}, localReciprocal_{0.0}; ///< in the frame set last
};

/// A ray from `origin` along `direction` with no end (OSG's RayIntersector).
class SGFX_API RayIntersector : public LineSegmentIntersector {
public:
    /// Throws std::invalid_argument when origin or direction is not finite or direction is 0.
    RayIntersector(const glm::dvec3& origin, const glm::dvec3& direction);
};

/// The triangles that touch a convex volume given by planes whose normals point inwards (OSG's
/// PolytopeIntersector): box selection, a frustum. Each hit's point is the centroid of the part
/// of the triangle inside the volume.
class SGFX_API PolytopeIntersector : public Intersector {
public:
    /// At least one plane; throws std::invalid_argument for a non-finite or zero normal.
    explicit PolytopeIntersector(std::vector<Plane> planes);
    /// A world box.
    static PolytopeIntersector box(const glm::dvec3& min, const glm::dvec3& max);
    /// The frustum of `camera` restricted to the window rectangle [x0, x1] × [y0, y1] (pixels of
    /// its viewport, origin at the top left like mouse coordinates), from the near to the far plane.
    static PolytopeIntersector windowRect(const Camera& camera, double x0, double y0, double x1, double y1);
    struct DPlane {
        glm::dvec3 n;
        double d; ///< n·p + d >= 0 inside
    };
    const std::vector<DPlane>& planes() const { return planes_; }

    void setFrame(const QueryFrame& frame) override;
    double entry(const QueryBox& box) const override;
    void intersect(const Geometry& geometry, const TriangleBvh& bvh, const QueryFrame& frame,
                   const QueryContext& context) override;

private:
    PolytopeIntersector() = default;
    std::vector<glm::dvec4> localPlanes(const QueryFrame& frame) const;
    std::vector<DPlane> planes_;
    std::vector<glm::dvec4> local_; ///< the planes in the frame set last
};

/// The triangles within `radius` of `center` (world): proximity, collision of a sphere.
class SGFX_API SphereIntersector : public Intersector {
public:
    /// Throws std::invalid_argument for a non-finite centre or a radius that is not > 0.
    SphereIntersector(const glm::dvec3& center, double radius);

    void setFrame(const QueryFrame& frame) override;
    double entry(const QueryBox& box) const override;
    void intersect(const Geometry& geometry, const TriangleBvh& bvh, const QueryFrame& frame,
                   const QueryContext& context) override;

private:
    /// The box around the sphere's image in a frame (an ellipsoid under scaling).
    static QueryBox localBox(const glm::dvec3& center, double radius, const QueryFrame& frame);
    glm::dvec3 center_;
    double radius_;
    QueryBox local_; ///< localBox in the frame set last
};

/// A view for queries that depend on it: LODs as shown and billboards turned towards its eye.
struct SGFX_API QueryView {
    glm::dmat4 viewMatrix{1.0};
    glm::mat4 projectionMatrix{1.0f};
    int viewportHeight = 1;
    static QueryView of(const Camera& camera);
};

/// Walks a graph for an intersector (OSG's osgUtil::IntersectionVisitor).
/// - Transforms, mirrored ones included, in double precision; instanced geometry per instance.
/// - Node masks: a node is skipped when (nodeMask & queryMask) == 0.
/// - LODs: the finest level (default), or the level `view` shows.
/// - Billboards: turned towards `view`'s eye; without a view, in their rest pose.
/// - A subgraph shared by several parents yields one hit per node path.
/// - Drawables (particles, volumes) and points and lines are not hit. A camera with a render
///   target is skipped (its children are drawn into a texture, not placed in the world).
/// - Skinned meshes would be hit in their bind pose (sgfx has no skinning yet).
/// The graph must not change during a visit (docs/queries.md); visits on other threads may run
/// while a frame is culled and drawn.
class SGFX_API IntersectionVisitor : public NodeVisitor {
public:
    enum class LodSelection : std::uint8_t {
        Finest, ///< the children drawn when the LOD is largest on screen
        Shown,  ///< the children `view` draws (needs a view)
    };
    explicit IntersectionVisitor(Intersector& intersector, NodeMask queryMask = ~NodeMask{0});

    LodSelection lodSelection = LodSelection::Finest;
    std::optional<QueryView> view;
    /// Use (and build once, then cache) a BVH over the geometries below the node the visit starts
    /// at; off: the graph is walked node by node as OpenSceneGraph does.
    bool useSubtreeIndex = true;

    /// Visits `node` (whose parent frame is `parentToWorld`), then sorts the hits.
    /// Throws std::invalid_argument for LodSelection::Shown without a view.
    void visit(Node& node, const glm::dmat4& parentToWorld = glm::dmat4(1.0));

    void apply(Node& node) override;
    void apply(Group& group) override;
    void apply(Transform& transform) override;
    void apply(LOD& lod) override;
    void apply(Switch& sw) override;         ///< the children that are on
    void apply(Sequence& sequence) override; ///< the child shown
    void apply(Billboard& billboard) override;
    void apply(Geometry& geometry) override;
    void apply(Drawable& drawable) override;
    void apply(Camera& camera) override;
    void apply(Light& light) override;

    std::size_t geometriesTested() const { return geometriesTested_; } ///< in this visitor's life

private:
    bool enterBound(const Node& node);
    void pushFrame(const glm::dmat4& local);
    void popFrame();
    void testGeometry(Geometry& geometry, const QueryFrame& frame);
    void visitIndexed(Group& group);
    void walkIndex(const SubtreeIndex& index, const QueryFrame& base);

    Intersector& intersector_;
    std::vector<QueryFrame> frames_;
    std::size_t geometriesTested_ = 0;
    std::uint64_t frameVersion_ = 1; ///< moves whenever frames_.back() changes
    std::uint64_t frameSet_ = 0;     ///< the version the intersector's setFrame last saw
    bool atStart_ = false;
};

} // namespace sgfx

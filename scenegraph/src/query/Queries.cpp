// Terrain height, line of sight, picking (Queries.h).
#include "sgfx/Queries.h"

#include "SubtreeIndex.h"

#include "sgfx/Camera.h"
#include "sgfx/Geometry.h"
#include "sgfx/Viewer.h"

#include <cmath>
#include <stdexcept>
#include <string>
#include <unordered_set>

namespace sgfx {

std::optional<Intersection> terrainHit(Node& scene, double x, double y, const QueryOptions& options) {
    if (!std::isfinite(x) || !std::isfinite(y))
        throw std::invalid_argument("sgfx: terrainHit: the point (" + std::to_string(x) + ", " +
                                    std::to_string(y) + ") is not finite");
    const BoundingSphere& s = scene.bound();
    if (!s.valid()) return std::nullopt;
    // The scene's world bound along Z: a world sphere holds it whatever the parent transform.
    const glm::dvec3 c(options.parentToWorld * glm::dvec4(glm::dvec3(s.center), 1.0));
    const double r = double(s.radius) * double(maxAxisScale(glm::mat4(options.parentToWorld))) + 1.0;
    LineSegmentIntersector line({x, y, c.z + r}, {x, y, c.z - r});
    line.limit = Intersector::Limit::Nearest;
    IntersectionVisitor iv(line, options.mask);
    iv.visit(scene, options.parentToWorld);
    if (!line.nearest()) return std::nullopt;
    return *line.nearest();
}

std::optional<double> heightOfTerrain(Node& scene, double x, double y, const QueryOptions& options) {
    auto hit = terrainHit(scene, x, y, options);
    if (!hit) return std::nullopt;
    return hit->point.z;
}

bool lineOfSight(Node& scene, const glm::dvec3& a, const glm::dvec3& b, const QueryOptions& options) {
    if (a == b) return true; // nothing lies between a point and itself
    LineSegmentIntersector line(a, b);
    line.limit = Intersector::Limit::Any;
    IntersectionVisitor iv(line, options.mask);
    iv.visit(scene, options.parentToWorld);
    return !line.containsIntersections();
}

PickRay pickRay(const Camera& camera, double x, double y) {
    const Viewport& vp = camera.viewport;
    if (!std::isfinite(x) || !std::isfinite(y) || vp.width <= 0 || vp.height <= 0)
        throw std::invalid_argument("sgfx: pickRay: the point (" + std::to_string(x) + ", " +
                                    std::to_string(y) + ") is not finite or the camera's viewport is empty");
    // Pixel → normalised device coordinates (y up), then through the inverse view-projection
    // at the near (z = -1) and far (z = 1) planes.
    const double nx = 2.0 * x / vp.width - 1.0, ny = 1.0 - 2.0 * y / vp.height;
    const glm::dmat4 inv = glm::inverse(glm::dmat4(camera.projectionMatrix) * glm::dmat4(camera.viewMatrix));
    auto unproject = [&](double z) {
        const glm::dvec4 p = inv * glm::dvec4(nx, ny, z, 1.0);
        return glm::dvec3(p) / p.w;
    };
    return {unproject(-1.0), unproject(1.0)};
}

std::optional<PickResult> pick(const Camera& camera, Node& scene, double x, double y, NodeMask mask) {
    const PickRay ray = pickRay(camera, x, y);
    LineSegmentIntersector line(ray.start, ray.end);
    line.limit = Intersector::Limit::Nearest;
    IntersectionVisitor iv(line, mask);
    iv.view = QueryView::of(camera);
    iv.lodSelection = IntersectionVisitor::LodSelection::Shown;
    iv.visit(scene);
    if (!line.nearest()) return std::nullopt;
    return PickResult{*line.nearest(), &camera};
}

std::optional<PickResult> pick(Viewer& viewer, double x, double y, NodeMask mask) {
    if (!viewer.sceneData()) return std::nullopt;
    // Every channel's viewport, in target pixels from the top left. (One camera today; the
    // channels of a multi-view viewer join this loop.)
    const Camera& camera = *viewer.camera();
    const Viewport& vp = camera.viewport;
    // A window's target is its framebuffer; a headless context has no size of its own (0), and
    // its target reaches as high as the viewport.
    const double targetHeight =
        viewer.context().isWindow() ? double(viewer.context().height()) : double(vp.y + vp.height);
    const double vx = x - vp.x, vy = y - (targetHeight - double(vp.y + vp.height));
    if (vx < 0.0 || vy < 0.0 || vx > vp.width || vy > vp.height) return std::nullopt;
    return pick(camera, *viewer.sceneData(), vx, vy, mask);
}

namespace {

// Bounds first, then every geometry's BVH and the root's index.
class Preparer : public NodeVisitor {
public:
    Preparer()
        : NodeVisitor(Mode::AllChildren) {}
    void apply(Geometry& g) override { g.triangleBvh(); }
};

} // namespace

namespace {

class MemoryCounter : public NodeVisitor {
public:
    MemoryCounter()
        : NodeVisitor(Mode::AllChildren) {}
    void apply(Geometry& g) override {
        const auto bvh = g.triangleBvh();
        if (!seen_.insert(bvh.get()).second) return;
        memory.bvhBytes += bvh->memoryBytes();
        memory.triangles += bvh->triangles().size();
    }
    void countIndex(const SubtreeIndex& index) {
        if (!seen_.insert(&index).second) return;
        memory.indexBytes += index.memoryBytes();
        for (const SubtreeIndex::Item& item : index.items)
            if (item.nested) countIndex(*item.nested);
    }
    QueryMemory memory;

private:
    std::unordered_set<const void*> seen_;
};

} // namespace

QueryMemory queryMemory(Node& scene) {
    scene.bound();
    MemoryCounter counter;
    scene.accept(counter);
    if (auto* group = dynamic_cast<Group*>(&scene)) counter.countIndex(*group->subtreeIndex());
    return counter.memory;
}

void prepareForQueries(Node& scene) {
    scene.bound();
    Preparer p;
    scene.accept(p);
    if (auto* group = dynamic_cast<Group*>(&scene)) group->subtreeIndex();
}

} // namespace sgfx

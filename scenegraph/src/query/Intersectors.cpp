// The intersectors: lines and rays, polytopes, spheres; the hit data they share.
#include "BvhWalk.h"
#include "sgfx/Camera.h"
#include "sgfx/Geometry.h"
#include "sgfx/Intersection.h"
#include "sgfx/Math.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace sgfx {

namespace {

bool finite(const glm::dvec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

glm::dvec3 position(const Geometry& g, std::uint32_t i) {
    return glm::dvec3(g.positions[i]);
}

glm::dvec3 transformPoint(const glm::dmat4& m, const glm::dvec3& p) {
    return glm::dvec3(m * glm::dvec4(p, 1.0));
}

std::string vecText(const glm::dvec3& v) {
    return "(" + std::to_string(v.x) + ", " + std::to_string(v.y) + ", " + std::to_string(v.z) + ")";
}

} // namespace

// ------------------------------------------------------------------------------ frames, hits
QueryFrame QueryFrame::of(const glm::dmat4& toWorld) {
    QueryFrame f;
    f.toWorld = toWorld;
    f.toLocal = glm::inverse(toWorld);
    return f;
}

void Intersector::finish() {
    std::stable_sort(hits_.begin(), hits_.end(),
                     [](const Intersection& a, const Intersection& b) { return a.distance < b.distance; });
}

void Intersector::record(Intersection&& hit) {
    if (limit == Limit::All || hits_.empty()) {
        hits_.push_back(std::move(hit));
    } else if (limit == Limit::Nearest && hit.distance < hits_.front().distance) {
        hits_.front() = std::move(hit);
    }
}

void Intersector::complete(Intersection& hit, const Geometry& g, const QueryFrame& frame,
                           const QueryContext& context) {
    const auto [i0, i1, i2] = hit.vertexIndices;
    const glm::dvec3 b = hit.barycentric;
    const glm::dvec3 p0 = position(g, i0), p1 = position(g, i1), p2 = position(g, i2);
    hit.point = transformPoint(frame.toWorld, b.x * p0 + b.y * p1 + b.z * p2);
    // Normals go through the inverse transpose, which also keeps the front side under a mirror
    // (the world winding flips with the determinant's sign; glTF 2.0 §3.7.4).
    const glm::dmat3 normalMatrix = glm::transpose(glm::dmat3(frame.toLocal));
    hit.geometricNormal = glm::normalize(normalMatrix * glm::cross(p1 - p0, p2 - p0));
    hit.normal = hit.geometricNormal;
    if (g.normals.size() == g.positions.size()) {
        const glm::dvec3 n =
            normalMatrix * (b.x * glm::dvec3(g.normals[i0]) + b.y * glm::dvec3(g.normals[i1]) +
                            b.z * glm::dvec3(g.normals[i2]));
        const double len = glm::length(n);
        if (len > 0.0 && std::isfinite(len)) hit.normal = n / len;
    }
    if (g.texcoords.size() == g.positions.size())
        hit.texcoord = b.x * glm::dvec2(g.texcoords[i0]) + b.y * glm::dvec2(g.texcoords[i1]) +
                       b.z * glm::dvec2(g.texcoords[i2]);
    hit.nodePath = *context.path;
    hit.geometry = const_cast<Geometry*>(&g); // a hit hands the node back to the caller
    hit.instanceIndex = context.instance;
    hit.worldMatrix = frame.toWorld;
}

// --------------------------------------------------------------------------- line and ray
LineSegmentIntersector::LineSegmentIntersector(const glm::dvec3& start, const glm::dvec3& end)
    : start_(start)
    , end_(end)
    , length_(glm::length(end - start)) {
    if (!finite(start) || !finite(end))
        throw std::invalid_argument("sgfx: LineSegmentIntersector: start " + vecText(start) + " or end " +
                                    vecText(end) + " is not finite");
    if (!(length_ > 0.0))
        throw std::invalid_argument("sgfx: LineSegmentIntersector: start and end are the same point " +
                                    vecText(start));
}

RayIntersector::RayIntersector(const glm::dvec3& origin, const glm::dvec3& direction)
    : LineSegmentIntersector(origin, origin + direction) {
    tMax_ = std::numeric_limits<double>::infinity();
}

double LineSegmentIntersector::searchLimit() const {
    return limit == Limit::Nearest && !hits_.empty() ? hits_.front().ratio : tMax_;
}

void LineSegmentIntersector::setFrame(const QueryFrame& frame) {
    localStart_ = transformPoint(frame.toLocal, start_);
    localDirection_ = transformPoint(frame.toLocal, end_) - localStart_;
    for (int a = 0; a < 3; ++a)
        localReciprocal_[a] = localDirection_[a] == 0.0 ? 0.0 : 1.0 / localDirection_[a];
}

double LineSegmentIntersector::entry(const QueryBox& box) const {
    return query::LineSlab(localStart_, localDirection_, localReciprocal_)
        .entry(box.min, box.max, searchLimit());
}

void LineSegmentIntersector::intersect(const Geometry& g, const TriangleBvh& bvh, const QueryFrame& frame,
                                       const QueryContext& context) {
    // Both ends into the geometry's frame: an affine map keeps the parameter t the same.
    const glm::dvec3 o = transformPoint(frame.toLocal, start_);
    const glm::dvec3 d = transformPoint(frame.toLocal, end_) - o;
    const query::LineSlab slab(o, d);
    const auto& tris = bvh.triangles();
    const glm::vec3* corner = bvh.corners().data();
    auto entry = [&](const BvhNodes::Node& n) { return slab.entry(n, searchLimit()); };
    auto bound = [&] { return searchLimit(); };
    auto leaf = [&](std::uint32_t first, std::uint32_t count) {
        for (std::uint32_t k = first; k < first + count; ++k) {
            const glm::dvec3 v0(corner[3 * k]);
            // Möller & Trumbore (1997), in double.
            const glm::dvec3 e1 = glm::dvec3(corner[3 * k + 1]) - v0, e2 = glm::dvec3(corner[3 * k + 2]) - v0;
            const glm::dvec3 p = glm::cross(d, e2);
            const double det = glm::dot(e1, p);
            if (det == 0.0) continue; // the line runs in the triangle's plane: no crossing
            const double inv = 1.0 / det;
            const glm::dvec3 s = o - v0;
            const double u = glm::dot(s, p) * inv;
            if (u < 0.0 || u > 1.0) continue;
            const glm::dvec3 q = glm::cross(s, e1);
            const double v = glm::dot(d, q) * inv;
            if (v < 0.0 || u + v > 1.0) continue;
            const double t = glm::dot(e2, q) * inv;
            if (t < 0.0 || t > searchLimit()) continue;
            Intersection hit;
            hit.ratio = t;
            hit.distance = t * length_;
            hit.barycentric = {1.0 - u - v, u, v};
            hit.primitiveIndex = tris[k].primitive;
            hit.vertexIndices = tris[k].v;
            complete(hit, g, frame, context);
            record(std::move(hit));
            if (done()) return false;
        }
        return true;
    };
    query::walkNearFirst(bvh.bvh(), entry, bound, leaf);
}

// ------------------------------------------------------------------------------- polytope
PolytopeIntersector::PolytopeIntersector(std::vector<Plane> planes) {
    if (planes.empty()) throw std::invalid_argument("sgfx: PolytopeIntersector: no planes");
    for (std::size_t i = 0; i < planes.size(); ++i) {
        const glm::dvec3 n(planes[i].n);
        const double len = glm::length(n);
        if (!(len > 0.0) || !std::isfinite(len) || !std::isfinite(planes[i].d))
            throw std::invalid_argument("sgfx: PolytopeIntersector: plane " + std::to_string(i) +
                                        " has a zero or non-finite normal or offset");
        planes_.push_back({n / len, double(planes[i].d) / len});
    }
}

PolytopeIntersector PolytopeIntersector::box(const glm::dvec3& min, const glm::dvec3& max) {
    if (!finite(min) || !finite(max) || min.x > max.x || min.y > max.y || min.z > max.z)
        throw std::invalid_argument("sgfx: PolytopeIntersector::box: min " + vecText(min) + " and max " +
                                    vecText(max) + " are not finite or not ordered");
    PolytopeIntersector p;
    for (int a = 0; a < 3; ++a) {
        glm::dvec3 n(0.0);
        n[a] = 1.0;
        p.planes_.push_back({n, -min[a]});
        p.planes_.push_back({-n, max[a]});
    }
    return p;
}

PolytopeIntersector PolytopeIntersector::windowRect(const Camera& camera, double x0, double y0, double x1,
                                                    double y1) {
    const Viewport& vp = camera.viewport;
    if (!(x0 < x1) || !(y0 < y1) || !std::isfinite(x0 + y0 + x1 + y1) || vp.width <= 0 || vp.height <= 0)
        throw std::invalid_argument("sgfx: PolytopeIntersector::windowRect: the rectangle [" +
                                    std::to_string(x0) + ", " + std::to_string(x1) + "] x [" +
                                    std::to_string(y0) + ", " + std::to_string(y1) +
                                    "] is empty or not finite, or the viewport is");
    // The rectangle in normalised device coordinates (y up), then a matrix that maps it onto
    // [-1, 1]²: the frustum planes of the product are the sub-frustum's (Gribb & Hartmann 2001).
    const double ax = 2.0 * x0 / vp.width - 1.0, bx = 2.0 * x1 / vp.width - 1.0;
    const double ay = 1.0 - 2.0 * y1 / vp.height, by = 1.0 - 2.0 * y0 / vp.height;
    glm::dmat4 pick(1.0);
    pick[0][0] = 2.0 / (bx - ax);
    pick[3][0] = -(bx + ax) / (bx - ax);
    pick[1][1] = 2.0 / (by - ay);
    pick[3][1] = -(by + ay) / (by - ay);
    const glm::dmat4 m = pick * glm::dmat4(camera.projectionMatrix) * glm::dmat4(camera.viewMatrix);
    auto row = [&](int r) { return glm::dvec4(m[0][r], m[1][r], m[2][r], m[3][r]); };
    PolytopeIntersector p;
    // Near first: hits are measured from it.
    for (const glm::dvec4 q : {row(3) + row(2), row(3) - row(2), row(3) + row(0), row(3) - row(0),
                               row(3) + row(1), row(3) - row(1)}) {
        const double len = glm::length(glm::dvec3(q));
        p.planes_.push_back({glm::dvec3(q) / len, q.w / len});
    }
    return p;
}

namespace {

// A world plane n·p + d in a frame's local coordinates: (M^T (n, d)) · (p, 1).
glm::dvec4 localPlane(const PolytopeIntersector::DPlane& pl, const QueryFrame& frame) {
    return glm::transpose(frame.toWorld) * glm::dvec4(pl.n, pl.d);
}

double planeDistance(const glm::dvec4& pl, const glm::dvec3& p) {
    return glm::dot(glm::dvec3(pl), p) + pl.w;
}

// Sutherland–Hodgman: the part of polygon `poly` on the inner side of `pl`.
void clipPolygon(std::vector<glm::dvec3>& poly, std::vector<glm::dvec3>& scratch, const glm::dvec4& pl) {
    scratch.clear();
    for (std::size_t i = 0; i < poly.size(); ++i) {
        const glm::dvec3& a = poly[i];
        const glm::dvec3& b = poly[(i + 1) % poly.size()];
        const double da = planeDistance(pl, a), db = planeDistance(pl, b);
        if (da >= 0.0) scratch.push_back(a);
        if ((da >= 0.0) != (db >= 0.0)) scratch.push_back(a + (b - a) * (da / (da - db)));
    }
    poly.swap(scratch);
}

// Barycentric weights of p (in the triangle's plane) with respect to a, b, c.
glm::dvec3 barycentricOf(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
    const glm::dvec3 v0 = b - a, v1 = c - a, v2 = p - a;
    const double d00 = glm::dot(v0, v0), d01 = glm::dot(v0, v1), d11 = glm::dot(v1, v1);
    const double d20 = glm::dot(v2, v0), d21 = glm::dot(v2, v1);
    const double den = d00 * d11 - d01 * d01;
    const double v = (d11 * d20 - d01 * d21) / den, w = (d00 * d21 - d01 * d20) / den;
    return {1.0 - v - w, v, w};
}

} // namespace

namespace {

// Whether the box can touch the volume: no plane has the whole box outside.
bool boxMayTouch(const std::vector<glm::dvec4>& planes, const glm::dvec3& min, const glm::dvec3& max) {
    for (const glm::dvec4& pl : planes) {
        // The box corner farthest along the plane's normal.
        const glm::dvec3 far(pl.x > 0 ? max.x : min.x, pl.y > 0 ? max.y : min.y, pl.z > 0 ? max.z : min.z);
        const double slack = 1e-9 * (glm::length(glm::dvec3(pl)) * glm::length(far) + std::abs(pl.w));
        if (planeDistance(pl, far) < -slack) return false;
    }
    return true;
}

} // namespace

std::vector<glm::dvec4> PolytopeIntersector::localPlanes(const QueryFrame& frame) const {
    std::vector<glm::dvec4> local;
    local.reserve(planes_.size());
    for (const DPlane& world : planes_)
        local.push_back(localPlane(world, frame));
    return local;
}

void PolytopeIntersector::setFrame(const QueryFrame& frame) {
    local_ = localPlanes(frame);
}

double PolytopeIntersector::entry(const QueryBox& box) const {
    return boxMayTouch(local_, box.min, box.max) ? 0.0 : query::kMiss;
}

void PolytopeIntersector::intersect(const Geometry& g, const TriangleBvh& bvh, const QueryFrame& frame,
                                    const QueryContext& context) {
    const std::vector<glm::dvec4> local = localPlanes(frame);
    std::vector<glm::dvec3> poly, scratch;
    auto test = [&](const BvhNodes::Node& n) {
        return boxMayTouch(local, glm::dvec3(n.min), glm::dvec3(n.max));
    };
    const auto& tris = bvh.triangles();
    auto leaf = [&](std::uint32_t first, std::uint32_t count) {
        for (std::uint32_t k = first; k < first + count; ++k) {
            const TriangleBvh::Triangle& tri = tris[k];
            const glm::dvec3 a = position(g, tri.v[0]), b = position(g, tri.v[1]), c = position(g, tri.v[2]);
            poly = {a, b, c};
            for (const glm::dvec4& pl : local) {
                clipPolygon(poly, scratch, pl);
                if (poly.empty()) break;
            }
            if (poly.empty()) continue;
            glm::dvec3 centroid(0.0);
            for (const glm::dvec3& p : poly)
                centroid += p;
            centroid /= double(poly.size());
            Intersection hit;
            hit.barycentric = barycentricOf(centroid, a, b, c);
            hit.primitiveIndex = tri.primitive;
            hit.vertexIndices = tri.v;
            complete(hit, g, frame, context);
            hit.distance = glm::dot(planes_.front().n, hit.point) + planes_.front().d;
            record(std::move(hit));
            if (done()) return false;
        }
        return true;
    };
    query::walk(bvh.bvh(), test, leaf);
}

// --------------------------------------------------------------------------------- sphere
SphereIntersector::SphereIntersector(const glm::dvec3& center, double radius)
    : center_(center)
    , radius_(radius) {
    if (!finite(center) || !(radius > 0.0) || !std::isfinite(radius))
        throw std::invalid_argument("sgfx: SphereIntersector: centre " + vecText(center) + " or radius " +
                                    std::to_string(radius) + " is not finite, or the radius is not > 0");
}

QueryBox SphereIntersector::localBox(const glm::dvec3& center, double radius, const QueryFrame& frame) {
    // The local image of the sphere is an ellipsoid; its box has half extent r·|row i| of the
    // inverse's 3×3 part on axis i.
    const glm::dvec3 c = transformPoint(frame.toLocal, center);
    const glm::dmat3 inv(frame.toLocal);
    QueryBox box;
    for (int a = 0; a < 3; ++a) {
        const double e = radius * glm::length(glm::dvec3(inv[0][a], inv[1][a], inv[2][a])) * (1.0 + 1e-9);
        box.min[a] = c[a] - e;
        box.max[a] = c[a] + e;
    }
    return box;
}

void SphereIntersector::setFrame(const QueryFrame& frame) {
    local_ = localBox(center_, radius_, frame);
}

double SphereIntersector::entry(const QueryBox& box) const {
    for (int a = 0; a < 3; ++a)
        if (local_.max[a] < box.min[a] || local_.min[a] > box.max[a]) return query::kMiss;
    return 0.0;
}

void SphereIntersector::intersect(const Geometry& g, const TriangleBvh& bvh, const QueryFrame& frame,
                                  const QueryContext& context) {
    const QueryBox sphere = localBox(center_, radius_, frame);
    auto test = [&](const BvhNodes::Node& n) {
        for (int a = 0; a < 3; ++a)
            if (sphere.max[a] < double(n.min[a]) || sphere.min[a] > double(n.max[a])) return false;
        return true;
    };
    const auto& tris = bvh.triangles();
    auto leaf = [&](std::uint32_t first, std::uint32_t count) {
        for (std::uint32_t k = first; k < first + count; ++k) {
            const TriangleBvh::Triangle& tri = tris[k];
            // In world space: the sphere stays a sphere there whatever the transform.
            const glm::dvec3 a = transformPoint(frame.toWorld, position(g, tri.v[0]));
            const glm::dvec3 b = transformPoint(frame.toWorld, position(g, tri.v[1]));
            const glm::dvec3 c = transformPoint(frame.toWorld, position(g, tri.v[2]));
            const glm::dvec3 w = closestOnTriangle(center_, a, b, c);
            const double dist = glm::length(w.x * a + w.y * b + w.z * c - center_);
            if (dist > radius_) continue;
            Intersection hit;
            hit.barycentric = w;
            hit.primitiveIndex = tri.primitive;
            hit.vertexIndices = tri.v;
            hit.distance = dist;
            complete(hit, g, frame, context);
            record(std::move(hit));
            if (done()) return false;
        }
        return true;
    };
    query::walk(bvh.bvh(), test, leaf);
}

} // namespace sgfx

#pragma once
/// @file
/// Value types for bounds and frusta. World is right-handed, Z up, metres.
#include "sgfx/Export.h"
#include <glm/glm.hpp>

#include <array>

namespace sgfx {

/// A sphere that holds a node and everything below it (an empty one has a negative radius).
struct SGFX_API BoundingSphere {
    glm::vec3 center{0.0f};
    float radius = -1.0f; ///< negative = invalid (empty)

    bool valid() const { return radius >= 0.0f; }
    void expandBy(const glm::vec3& p);
    void expandBy(const BoundingSphere& s);
    BoundingSphere transformed(const glm::mat4& m) const;
};

/// Axis-aligned box, used to build tight spheres from vertex data.
struct SGFX_API BoundingBox {
    glm::vec3 min{std::numeric_limits<float>::max()};
    glm::vec3 max{-std::numeric_limits<float>::max()};
    bool valid() const { return min.x <= max.x; }
    void expandBy(const glm::vec3& p) {
        min = glm::min(min, p);
        max = glm::max(max, p);
    }
    glm::vec3 center() const { return (min + max) * 0.5f; }
};

/// A plane n·p + d = 0; distance() is positive on the side the normal points to.
struct SGFX_API Plane {
    glm::vec3 n{0, 0, 1};
    float d = 0; ///< n·p + d = signed distance
    float distance(const glm::vec3& p) const { return glm::dot(n, p) + d; }
};

/// The largest column length of m's 3×3 part: how much m can stretch a bounding sphere's radius.
SGFX_API float maxAxisScale(const glm::mat4& m);
/// Whether m's 3×3 part is a rotation times a uniform scale (columns orthogonal and of equal
/// length, to 1e-6 relative): then maxAxisScale(a * m) = maxAxisScale(a) * maxAxisScale(m) for
/// any `a` that is one too.
SGFX_API bool isSimilarity(const glm::mat4& m);

enum class Containment { Outside, Intersects, Inside };

/// Six planes from a view-projection matrix (Gribb/Hartmann), normals point inwards.
struct SGFX_API Frustum {
    std::array<Plane, 6> planes; ///< left, right, bottom, top, near, far
    static Frustum fromMatrix(const glm::mat4& viewProj);
    Containment classify(const BoundingSphere& s) const;
};

/// Barycentric weights of the point of triangle abc closest to p (Ericson, Real-Time Collision
/// Detection, 5.1.5), in float or double: the point is w.x·a + w.y·b + w.z·c.
template <class T, glm::qualifier Q>
glm::vec<3, T, Q> closestOnTriangle(const glm::vec<3, T, Q>& p, const glm::vec<3, T, Q>& a,
                                    const glm::vec<3, T, Q>& b, const glm::vec<3, T, Q>& c) {
    using V = glm::vec<3, T, Q>;
    const V ab = b - a, ac = c - a, ap = p - a;
    const T d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
    if (d1 <= T(0) && d2 <= T(0)) return {1, 0, 0};
    const V bp = p - b;
    const T d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
    if (d3 >= T(0) && d4 <= d3) return {0, 1, 0};
    const T vc = d1 * d4 - d3 * d2;
    if (vc <= T(0) && d1 >= T(0) && d3 <= T(0)) {
        const T v = d1 / (d1 - d3);
        return {1 - v, v, 0};
    }
    const V cp = p - c;
    const T d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
    if (d6 >= T(0) && d5 <= d6) return {0, 0, 1};
    const T vb = d5 * d2 - d1 * d6;
    if (vb <= T(0) && d2 >= T(0) && d6 <= T(0)) {
        const T w = d2 / (d2 - d6);
        return {1 - w, 0, w};
    }
    const T va = d3 * d6 - d5 * d4;
    if (va <= T(0) && (d4 - d3) >= T(0) && (d5 - d6) >= T(0)) {
        const T w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return {0, 1 - w, w};
    }
    const T denom = T(1) / (va + vb + vc);
    const T v = vb * denom, w = vc * denom;
    return {1 - v - w, v, w};
}

} // namespace sgfx

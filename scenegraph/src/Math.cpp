#include "sgfx/Math.h"

#include <algorithm>
#include <cmath>

namespace sgfx {

void BoundingSphere::expandBy(const glm::vec3& p) {
    if (!valid()) {
        center = p;
        radius = 0.0f;
        return;
    }
    const glm::vec3 d = p - center;
    const float dist = glm::length(d);
    if (dist <= radius) return;
    // Smallest sphere holding the old one and p.
    const float newRadius = 0.5f * (dist + radius);
    center += d * ((newRadius - radius) / dist);
    radius = newRadius;
}

void BoundingSphere::expandBy(const BoundingSphere& s) {
    if (!s.valid()) return;
    if (!valid()) {
        *this = s;
        return;
    }
    const glm::vec3 d = s.center - center;
    const float dist = glm::length(d);
    if (dist + s.radius <= radius) return;
    if (dist + radius <= s.radius) {
        *this = s;
        return;
    }
    const float newRadius = 0.5f * (dist + radius + s.radius);
    center += d * ((newRadius - radius) / dist);
    radius = newRadius;
}

float maxAxisScale(const glm::mat4& m) {
    const glm::vec3 x(m[0]), y(m[1]), z(m[2]);
    // One square root: a correctly rounded sqrt is monotonic, so this equals the largest of the
    // three column lengths bit for bit (as transformed() computes them).
    return std::sqrt(std::max({glm::dot(x, x), glm::dot(y, y), glm::dot(z, z)}));
}

bool isSimilarity(const glm::mat4& m) {
    const glm::vec3 x(m[0]), y(m[1]), z(m[2]);
    const float xx = glm::dot(x, x), yy = glm::dot(y, y), zz = glm::dot(z, z);
    const float tolerance = 1e-6f * std::max({xx, yy, zz});
    return std::abs(xx - yy) <= tolerance && std::abs(xx - zz) <= tolerance &&
           std::abs(glm::dot(x, y)) <= tolerance && std::abs(glm::dot(x, z)) <= tolerance &&
           std::abs(glm::dot(y, z)) <= tolerance;
}

BoundingSphere BoundingSphere::transformed(const glm::mat4& m) const {
    if (!valid()) return *this;
    BoundingSphere out;
    out.center = glm::vec3(m * glm::vec4(center, 1.0f));
    // The largest axis scale bounds any shear or non-uniform scale.
    const float sx = glm::length(glm::vec3(m[0]));
    const float sy = glm::length(glm::vec3(m[1]));
    const float sz = glm::length(glm::vec3(m[2]));
    out.radius = radius * std::max({sx, sy, sz});
    return out;
}

Frustum Frustum::fromMatrix(const glm::mat4& vp) {
    // Row i of the matrix is (vp[0][i], vp[1][i], vp[2][i], vp[3][i]) in GLM's column-major layout.
    auto row = [&](int i) { return glm::vec4(vp[0][i], vp[1][i], vp[2][i], vp[3][i]); };
    const glm::vec4 r0 = row(0), r1 = row(1), r2 = row(2), r3 = row(3);
    const glm::vec4 p[6] = {r3 + r0, r3 - r0, r3 + r1, r3 - r1, r3 + r2, r3 - r2};
    Frustum f;
    for (int i = 0; i < 6; ++i) {
        const float len = glm::length(glm::vec3(p[i]));
        f.planes[i].n = glm::vec3(p[i]) / len;
        f.planes[i].d = p[i].w / len;
    }
    return f;
}

Containment Frustum::classify(const BoundingSphere& s) const {
    if (!s.valid()) return Containment::Outside;
    Containment result = Containment::Inside;
    for (const Plane& p : planes) {
        const float d = p.distance(s.center);
        if (d < -s.radius) return Containment::Outside;
        if (d < s.radius) result = Containment::Intersects;
    }
    return result;
}

} // namespace sgfx

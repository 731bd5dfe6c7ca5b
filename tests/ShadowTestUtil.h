#pragma once
// What the shadow tests share: sun directions, a top view of the plane z = 0, and the expected
// shadow as the convex hull of points projected onto the plane, computed without the shadow code.
#include "TestUtil.h"

#include <sgfx/Group.h>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

namespace sgfx::test::shadows {

inline double deg(double d) {
    return d * std::numbers::pi / 180.0;
}

/// Unit vector towards a sun at this azimuth (from +X towards +Y) and elevation, degrees.
inline glm::dvec3 sunVector(double azimuthDeg, double elevationDeg) {
    const double a = deg(azimuthDeg), e = deg(elevationDeg);
    return {std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e)};
}

/// The red channel of a float image (row 0 at the top).
inline double red(const FloatImage& img, int x, int y) {
    return img.rgba[(std::size_t(y) * std::size_t(img.width) + std::size_t(x)) * 4];
}

/// A white Lambert material without highlights: a pixel lit by a sun of colour 1 is N·L.
inline std::shared_ptr<Material> white() {
    auto m = Material::create();
    m->diffuse = glm::vec4(1.0f);
    m->specular = glm::vec3(0.0f);
    return m;
}

template <class N> std::shared_ptr<N> lambert(std::shared_ptr<N> g) {
    g->getOrCreateStateSet().material.set(white());
    return g;
}

inline std::shared_ptr<Transform> placed(std::shared_ptr<Node> n, const glm::mat4& m) {
    auto t = Transform::create(m);
    t->addChild(std::move(n));
    return t;
}

/// The top view: `size`² pixels over [−half, half]² metres, an orthographic camera 10 m up whose
/// depth range [5, 15] keeps the cascades small, a float target.
inline std::unique_ptr<Viewer> topViewer(int size, double half, int unrolledLights = 8) {
    auto v = orthoTopViewer(size, float(half));
    v->camera()->projectionMatrix =
        glm::ortho(-float(half), float(half), -float(half), float(half), 5.0f, 15.0f);
    v->renderer().options().colorTarget = RendererOptions::ColorTarget::Rgba32F;
    v->renderer().options().maxUnrolledLights = unrolledLights;
    return v;
}

// ---- the expected shadow: convex hulls and distances to them

using Hull = std::vector<glm::dvec2>;

inline double cross(const glm::dvec2& o, const glm::dvec2& a, const glm::dvec2& b) {
    return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
}

/// Andrew's monotone chain, counter-clockwise.
inline Hull convexHull(std::vector<glm::dvec2> p) {
    std::sort(p.begin(), p.end(), [](auto a, auto b) { return a.x < b.x || (a.x == b.x && a.y < b.y); });
    Hull h(2 * p.size());
    std::size_t k = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
        while (k >= 2 && cross(h[k - 2], h[k - 1], p[i]) <= 0)
            --k;
        h[k++] = p[i];
    }
    for (std::size_t i = p.size() - 1, t = k + 1; i-- > 0;) {
        while (k >= t && cross(h[k - 2], h[k - 1], p[i]) <= 0)
            --k;
        h[k++] = p[i];
    }
    h.resize(k - 1);
    return h;
}

/// Signed distance to the hull's boundary: negative inside.
inline double signedDistance(const Hull& h, const glm::dvec2& q) {
    double inside = -1e30, edge = 1e30;
    for (std::size_t i = 0; i < h.size(); ++i) {
        const glm::dvec2 a = h[i], b = h[(i + 1) % h.size()], ab = b - a;
        const double t = std::clamp(glm::dot(q - a, ab) / glm::dot(ab, ab), 0.0, 1.0);
        edge = std::min(edge, glm::length(q - (a + t * ab)));
        inside = std::max(inside, -cross(a, b, q) / glm::length(ab));
    }
    return inside <= 0.0 ? -edge : edge;
}

/// Points projected along L onto z = 0 (p − L·p.z/L.z), as a hull.
inline Hull projected(const std::vector<glm::dvec3>& points, const glm::dvec3& L) {
    std::vector<glm::dvec2> p;
    for (const glm::dvec3& q : points)
        p.push_back(glm::dvec2(q - L * (q.z / L.z)));
    return convexHull(p);
}

/// What points cover of the plane seen from straight above.
inline Hull footprint(const std::vector<glm::dvec3>& points) {
    std::vector<glm::dvec2> p;
    for (const glm::dvec3& q : points)
        p.emplace_back(q.x, q.y);
    return convexHull(p);
}

/// The corners of a box of `size` centred at the origin of `m`'s frame.
inline std::vector<glm::dvec3> boxCorners(const glm::dmat4& m, const glm::dvec3& size) {
    std::vector<glm::dvec3> c;
    for (int k = 0; k < 8; ++k)
        c.push_back(glm::dvec3(m * glm::dvec4((k & 1 ? 0.5 : -0.5) * size.x, (k & 2 ? 0.5 : -0.5) * size.y,
                                              (k & 4 ? 0.5 : -0.5) * size.z, 1.0)));
    return c;
}

/// The corners of the axis-aligned box lo..hi.
inline std::vector<glm::dvec3> boxCorners(const glm::dvec3& lo, const glm::dvec3& hi) {
    return boxCorners(glm::translate(glm::dmat4(1.0), (lo + hi) * 0.5), hi - lo);
}

} // namespace sgfx::test::shadows

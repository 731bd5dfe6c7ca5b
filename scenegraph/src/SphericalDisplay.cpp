#include "sgfx/SphericalDisplay.h"

#include <glm/gtc/constants.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace sgfx {

namespace {

void require(bool ok, const std::string& what) {
    if (!ok) throw std::invalid_argument("SphericalDisplayParams: " + what);
}

void checkSize(int width, int height) {
    if (width < 1 || width > 16384 || height < 1 || height > 16384)
        throw std::invalid_argument("spherical display: image size must be in 1..16384, got " +
                                    std::to_string(width) + "x" + std::to_string(height));
}

// osg::Vec3 * osg::Matrix (Matrixd::preMult(Vec3)): the full 4×4 with w = 1, divided by w.
glm::dvec3 applyProjector(const glm::dmat4& p, const glm::dvec3& d) {
    const glm::dvec4 h = p * glm::dvec4(d, 1.0);
    return glm::dvec3(h) / h.w;
}

double projectorDistance(const SphericalDisplayParams& p) {
    return std::sqrt(p.radius * p.radius - p.collar * p.collar);
}

// createParoramicSphericalDisplayDistortionMesh (OSG src/osgViewer/config/PanoramicSphericalDisplay.cpp):
// a (theta, phi) grid over the sphere of directions; each direction, turned by the projector matrix,
// lands at azimuth alpha and at a radius proportional to gamma, its angle seen from the projector.
WarpMesh panoramicMesh(const SphericalDisplayParams& p, int width, int height, int n) {
    const double pi = glm::pi<double>(), distance = projectorDistance(p);
    const glm::dvec2 centre(width * 0.5, height * 0.5);
    const double screenRadius = height * 0.5;
    WarpMesh m;
    m.vertices.reserve(std::size_t(n) * n);
    for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
            const double theta = double(i) / (n - 1) * 2.0 * pi, phi = (1.0 - double(j) / (n - 1)) * pi;
            const glm::dvec3 dir(std::sin(phi) * std::sin(theta), std::sin(phi) * std::cos(theta),
                                 std::cos(phi));
            const glm::dvec3 pos = applyProjector(p.projector, dir);
            double alpha = std::atan2(pos.x, pos.y);
            if (alpha < 0.0) alpha += 2.0 * pi;
            const double rho = std::sqrt(pos.x * pos.x + pos.y * pos.y);
            const double beta = std::atan2(rho, pos.z), gamma = std::atan2(rho, pos.z + distance);
            const glm::dvec2 v =
                centre + glm::dvec2(std::sin(alpha), -std::cos(alpha)) * (gamma * 2.0 / pi) * screenRadius;
            m.vertices.push_back({glm::vec2(v), glm::vec3(dir), float(glm::degrees(beta))});
        }
    }
    auto inside = [&](std::uint32_t k) {
        return glm::length(glm::dvec2(m.vertices[k].pixel) - centre) <= screenRadius;
    };
    for (int i = 0; i + 1 < n; ++i) {
        for (int j = 0; j + 1 < n; ++j) {
            const std::uint32_t i1 = j + (i + 1) * n, i2 = j + i * n, i3 = j + 1 + i * n,
                                i4 = j + 1 + (i + 1) * n;
            // OSG drops every quad with a corner outside the image's circle.
            if (!inside(i1) || !inside(i2) || !inside(i3) || !inside(i4)) continue;
            m.indices.insert(m.indices.end(), {i1, i2, i3, i1, i3, i4});
        }
    }
    return m;
}

// create3DSphericalDisplayDistortionMesh (OSG src/osgViewer/config/SphericalDisplay.cpp): a pixel grid;
// each pixel's projector ray (angle phi from the axis, azimuth theta) is followed from the projector
// to the mirror, and the point it hits, seen from the sphere's centre, is the direction shown.
WarpMesh threeDMesh(const SphericalDisplayParams& p, int width, int height, int n) {
    WarpMesh m;
    m.vertices.reserve(std::size_t(n) * n);
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j)
            m.vertices.push_back(sphericalThreeDAt(
                p, width, height, glm::vec2(float(width) * j / (n - 1), float(height) * i / (n - 1))));
    for (int i = 0; i + 1 < n; ++i) {
        for (int j = 0; j + 1 < n; ++j) {
            const std::uint32_t a = j + i * n, b = j + 1 + i * n, c = j + (i + 1) * n,
                                d = j + 1 + (i + 1) * n;
            m.indices.insert(m.indices.end(), {c, a, b, c, b, d});
        }
    }
    return m;
}

} // namespace

void SphericalDisplayParams::validate() const {
    require(std::isfinite(radius) && radius > 0.0,
            "radius must be finite and > 0, got " + std::to_string(radius));
    require(std::isfinite(collar) && collar >= 0.0 && collar < radius,
            "collar must be in [0, radius), got " + std::to_string(collar));
    require(intensityMap.size() <= std::size_t(kMaxIntensityPoints),
            "intensityMap: at most " + std::to_string(kMaxIntensityPoints) + " points, got " +
                std::to_string(intensityMap.size()));
    for (std::size_t i = 0; i < intensityMap.size(); ++i) {
        const IntensityPoint& q = intensityMap[i];
        const std::string at = "intensityMap point " + std::to_string(i) + ": ";
        require(std::isfinite(q.angleDeg) && q.angleDeg >= 0.0f && q.angleDeg <= 180.0f,
                at + "angle must be in [0, 180], got " + std::to_string(q.angleDeg));
        require(std::isfinite(q.percent) && q.percent >= 0.0f,
                at + "percent must be finite and >= 0, got " + std::to_string(q.percent));
        require(i == 0 || q.angleDeg > intensityMap[i - 1].angleDeg, at + "angles must increase");
    }
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            require(std::isfinite(projector[c][r]), "projectorMatrix: not finite");
}

double intensityAt(const std::vector<IntensityPoint>& map, double angleDeg) {
    constexpr double kPercent = 0.01;
    if (map.empty()) return 1.0;
    if (angleDeg <= map.front().angleDeg) return map.front().percent * kPercent;
    if (angleDeg >= map.back().angleDeg) return map.back().percent * kPercent;
    const auto above = std::lower_bound(map.begin(), map.end(), angleDeg,
                                        [](const IntensityPoint& q, double a) { return q.angleDeg < a; });
    const auto below = above - 1;
    const double r = (angleDeg - below->angleDeg) / (above->angleDeg - below->angleDeg);
    return (below->percent + (above->percent - below->percent) * r) * kPercent;
}

WarpVertex sphericalThreeDAt(const SphericalDisplayParams& p, int width, int height, glm::vec2 pixel) {
    const double pi = glm::pi<double>(), distance = projectorDistance(p), r = p.radius;
    const glm::dvec2 delta = glm::dvec2(pixel) - glm::dvec2(width * 0.5, height * 0.5);
    const double screenRadius = height * 0.5;
    double theta = std::atan2(-delta.y, delta.x);
    if (theta < 0.0) theta += 2.0 * pi;
    const double phi = std::min(pi * 0.5 * glm::length(delta) / screenRadius, pi * 0.5);
    // The ray from the projector at (0, 0, −distance) meets the sphere of radius r after e.
    const double f = distance * std::sin(phi);
    const double e = distance * std::cos(phi) + std::sqrt(r * r - f * f);
    const double h = e * std::sin(phi), z = e * std::cos(phi) - distance;
    const glm::dvec3 dir(h * std::cos(theta) / r, h * std::sin(theta) / r, z / r);
    // The intensity map is read at 1 − phi/(π/2) of its 0..180° image (texcoord1 in OSG).
    return {pixel, glm::vec3(applyProjector(p.projector, dir)), float(phi * 360.0 / pi)};
}

WarpMesh sphericalWarpMesh(const SphericalDisplayParams& p, int width, int height, int steps) {
    p.validate();
    checkSize(width, height);
    if (steps != 0 && (steps < 2 || steps > 1024))
        throw std::invalid_argument("spherical display: steps must be 0 or in 2..1024, got " +
                                    std::to_string(steps));
    if (p.kind == SphericalDisplayKind::Panoramic)
        return panoramicMesh(p, width, height, steps ? steps : 160);
    return threeDMesh(p, width, height, steps ? steps : 50);
}

} // namespace sgfx

#include <sgfx/nodes/shadow/ShadowMath.h>

#include "ParameterChecks.h"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <string>

namespace sgfx::shadow {

namespace {

constexpr const char* kOwner = "ShadowMath";

// The message form of ParameterChecks.h, in double: "sgfx: ShadowMath: far = 0.1 is outside (near, inf)".
void require(bool ok, const char* name, double v, const char* range) {
    if (!std::isfinite(v))
        nodes::refuse(kOwner, std::string(name) + " is " + nodes::number(v) + "; it must be finite");
    if (!ok) nodes::refuse(kOwner, std::string(name) + " = " + nodes::number(v) + " is outside " + range);
}

void requireSlice(double a, double b) {
    require(true, "a", a, "");
    require(b > a, "b", b, "(a, inf)");
}

// Up vector for a light or spot looking along `forward`: +Z, or +X when nearly vertical.
glm::dvec3 upFor(const glm::dvec3& forward) {
    return std::abs(forward.z) > 0.99 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 0, 1);
}

} // namespace

std::vector<double> practicalSplits(double near, double far, int cascades, double lambda) {
    require(near > 0.0, "near", near, "(0, inf)");
    require(far > near, "far", far, "(near, inf)");
    require(cascades >= 1 && cascades <= kMaxCascades, "cascades", cascades, "[1, 4]");
    require(lambda >= 0.0 && lambda <= 1.0, "lambda", lambda, "[0, 1]");
    std::vector<double> c(static_cast<size_t>(cascades) + 1);
    for (int i = 0; i <= cascades; ++i) {
        const double s = double(i) / cascades;
        c[size_t(i)] = lambda * near * std::pow(far / near, s) + (1.0 - lambda) * (near + (far - near) * s);
    }
    // Exact ends: pow's rounding must not move the far split off f.
    c.front() = near;
    c.back() = far;
    return c;
}

double sliceStart(const std::vector<double>& splits, int cascade, double blendBand) {
    if (cascade <= 0) return splits.front();
    const auto k = size_t(cascade);
    return splits[k] - blendBand * (splits[k] - splits[k - 1]);
}

SliceSphere perspectiveSliceSphere(double fovy, double aspect, double a, double b) {
    require(fovy > 0.0 && fovy < std::numbers::pi, "fovy", fovy, "(0, pi)");
    require(aspect > 0.0, "aspect", aspect, "(0, inf)");
    require(a >= 0.0, "a", a, "[0, inf)");
    requireSlice(a, b);
    const double ty = std::tan(fovy / 2.0), tx = aspect * ty;
    const double k2 = tx * tx + ty * ty;
    // Equidistant from the corners at a (a²k² + (z − a)²) and at b (b²k² + (b − z)²).
    const double z = std::min(b, (a + b) * (1.0 + k2) / 2.0);
    return {z, std::sqrt((b - z) * (b - z) + b * b * k2)};
}

SliceSphere orthoSliceSphere(double halfWidth, double halfHeight, double a, double b) {
    require(halfWidth > 0.0, "halfWidth", halfWidth, "(0, inf)");
    require(halfHeight > 0.0, "halfHeight", halfHeight, "(0, inf)");
    requireSlice(a, b);
    const double h = (b - a) / 2.0;
    return {(a + b) / 2.0, std::sqrt(halfWidth * halfWidth + halfHeight * halfHeight + h * h)};
}

glm::dmat3 lightRotation(const glm::dvec3& towardsLight) {
    const double len = glm::length(towardsLight);
    require(len > 0.0, "|towardsLight|", len, "(0, inf)");
    const glm::dvec3 l = towardsLight / len, forward = -l;
    const glm::dvec3 right = glm::normalize(glm::cross(forward, upFor(forward)));
    const glm::dvec3 up = glm::cross(right, forward);
    // Rows right, up, L (glm is column-major, so build the columns and transpose).
    return glm::transpose(glm::dmat3(right, up, l));
}

int marginTexels(double kernelRadiusTexels) {
    return int(std::ceil(kernelRadiusTexels + 1.0));
}

int pcssMarginTexels(double maxPenumbraTexels) {
    return int(std::ceil(maxPenumbraTexels / 2.0)) + 1;
}

double marginRadius(double radius, int mapSize, int margin) {
    require(mapSize > 2 * margin, "mapSize", mapSize, "(2*margin, inf)");
    return radius * mapSize / double(mapSize - 2 * margin);
}

double texelSize(double halfExtent, int mapSize) {
    return 2.0 * halfExtent / mapSize;
}

glm::dvec2 snapToTexels(const glm::dvec2& c, double texel) {
    return texel * glm::floor(c / texel + 0.5);
}

CascadeFit fitCascade(const glm::dmat3& rotation, const glm::dvec3& worldCentre, double radius, int mapSize,
                      int margin, bool snap) {
    CascadeFit fit;
    fit.halfExtent = marginRadius(radius, mapSize, margin);
    fit.texel = texelSize(fit.halfExtent, mapSize);
    const glm::dvec2 c = glm::dvec2(rotation * worldCentre);
    fit.centre = snap ? snapToTexels(c, fit.texel) : c;
    return fit;
}

glm::dmat4 cascadeProjection(const CascadeFit& fit, double zMin, double zMax) {
    requireSlice(zMin, zMax);
    const double r = fit.halfExtent;
    // View space looks down −Z: distance −z runs from −zMax (nearest the light) to −zMin.
    return glm::ortho(fit.centre.x - r, fit.centre.x + r, fit.centre.y - r, fit.centre.y + r, -zMax, -zMin);
}

AtlasLayout atlasLayout(int count, int tileSize, int maxSize) {
    require(count >= 1, "count", count, "[1, inf)");
    require(tileSize >= 1 && tileSize <= maxSize, "tileSize", tileSize, "[1, maxSize]");
    const int columns = std::min(count, maxSize / tileSize);
    const int rows = (count + columns - 1) / columns;
    require(rows * tileSize <= maxSize, "count", count, "(tiles beyond maxSize)");
    AtlasLayout a;
    a.size = {columns * tileSize, rows * tileSize};
    for (int i = 0; i < count; ++i)
        a.tiles.emplace_back((i % columns) * tileSize, (i / columns) * tileSize, tileSize, tileSize);
    return a;
}

glm::dmat4 atlasMatrix(const glm::ivec4& tile, const glm::ivec2& atlasSize, const glm::dmat4& projection,
                       const glm::dmat3& rotation) {
    // Clip xy in [−1, 1] to the tile's atlas coordinates; z in [−1, 1] to [0, 1].
    const glm::dvec2 scale = glm::dvec2(tile.z, tile.w) / glm::dvec2(atlasSize) * 0.5;
    const glm::dvec2 origin = glm::dvec2(tile.x, tile.y) / glm::dvec2(atlasSize) + scale;
    glm::dmat4 toTile(1.0);
    toTile[0][0] = scale.x;
    toTile[1][1] = scale.y;
    toTile[2][2] = 0.5;
    toTile[3] = glm::dvec4(origin, 0.5, 1.0);
    return toTile * projection * glm::dmat4(rotation);
}

const std::array<glm::dvec2, kPoissonTaps>& poissonDisc() {
    static const std::array<glm::dvec2, kPoissonTaps> disc = [] {
        std::array<glm::dvec2, kPoissonTaps> p{};
        const double d = 0.95 / std::numbers::sqrt2;
        p[0] = {d, d}, p[1] = {-d, d}, p[2] = {-d, -d}, p[3] = {d, -d};
        std::mt19937 rng(20061u); // fixed: the table is part of the filter's definition
        std::uniform_real_distribution<double> u(-1.0, 1.0);
        for (int k = 4; k < kPoissonTaps; ++k) {
            double best = -1.0;
            for (int c = 0; c < 64; ++c) { // best of 64 candidates in the disc
                glm::dvec2 q(u(rng), u(rng));
                if (glm::dot(q, q) > 1.0) {
                    --c;
                    continue;
                }
                double nearest = 4.0;
                for (int j = 0; j < k; ++j)
                    nearest = std::min(nearest, glm::distance(q, p[size_t(j)]));
                if (nearest > best) best = nearest, p[size_t(k)] = q;
            }
        }
        return p;
    }();
    return disc;
}

double smoothstep(double e0, double e1, double x) {
    if (!(e1 > e0)) return x < e0 ? 0.0 : 1.0;
    const double t = std::clamp((x - e0) / (e1 - e0), 0.0, 1.0);
    return t * t * (3.0 - 2.0 * t);
}

CascadeSelection selectCascade(const std::vector<double>& splits, double z, double blendBand,
                               double fadeBand) {
    const int n = int(splits.size()) - 1;
    const double far = splits.back();
    CascadeSelection s;
    if (z > far) return {n, 0.0, 1.0};
    while (s.cascade < n - 1 && z > splits[size_t(s.cascade) + 1])
        ++s.cascade;
    const auto i = size_t(s.cascade);
    // The blend band ends at the split, where cascade i + 1 takes over with blend 0: continuous.
    if (s.cascade < n - 1)
        s.blend = smoothstep(splits[i + 1] - blendBand * (splits[i + 1] - splits[i]), splits[i + 1], z);
    const double last = splits[size_t(n) - 1];
    s.fade = smoothstep(far - fadeBand * (far - last), far, z);
    return s;
}

std::array<double, kMaxCascades + 1> cascadeWeights(const std::vector<double>& splits, double z,
                                                    double blendBand, double fadeBand) {
    const int n = int(splits.size()) - 1;
    const CascadeSelection s = selectCascade(splits, z, blendBand, fadeBand);
    std::array<double, kMaxCascades + 1> w{};
    if (s.cascade < n) {
        w[size_t(s.cascade)] += (1.0 - s.blend) * (1.0 - s.fade);
        w[size_t(s.cascade) + 1] += s.blend * (1.0 - s.fade);
    }
    // "Lit" sits at index N, whatever N is.
    w[size_t(n)] += s.cascade < n ? s.fade : 1.0;
    return w;
}

double receiverBias(double texel, double cosTheta, double constantBias, double slopeBias,
                    double kernelRadiusTexels, double maxSlope) {
    const double c = std::clamp(cosTheta, -1.0, 1.0);
    const double tanTheta = c > 0.0 ? std::sqrt(1.0 - c * c) / c : maxSlope;
    const double r = std::max(kernelRadiusTexels, 1.0);
    return texel * (constantBias + slopeBias * r * std::min(tanTheta, maxSlope));
}

double normalOffset(double texel, double cosTheta, double normalOffsetScale, double kernelRadiusTexels) {
    const double c = std::clamp(cosTheta, -1.0, 1.0);
    const double r = std::max(kernelRadiusTexels, 1.0);
    return normalOffsetScale * texel * (r + 0.5) * std::sqrt(1.0 - c * c);
}

double sunSearchWidth(double receiverDepth, double nearDepth, double angularRadius, double maxPenumbraTexels,
                      double texel) {
    return std::min((receiverDepth - nearDepth) * std::tan(angularRadius), maxPenumbraTexels * texel);
}

double sunPenumbraWidth(double receiverDepth, double blockerDepth, double angularRadius) {
    return 2.0 * std::max(receiverDepth - blockerDepth, 0.0) * std::tan(angularRadius);
}

double pcssFilterRadius(double penumbraWidth, double kernelRadiusTexels, double texel) {
    return std::max(penumbraWidth / 2.0, kernelRadiusTexels * texel);
}

double spotSearchWidth(double sourceRadius, double receiverDepth, double nearDepth) {
    return sourceRadius * (receiverDepth - nearDepth) / receiverDepth;
}

double spotPenumbraWidth(double sourceRadius, double receiverDepth, double blockerDepth) {
    return 2.0 * std::max(receiverDepth - blockerDepth, 0.0) * sourceRadius / blockerDepth;
}

double spotFovy(double outerAngle, double marginAngle) {
    return 2.0 * outerAngle + marginAngle;
}

glm::dmat4 spotView(const glm::dvec3& position, const glm::dvec3& axis) {
    const glm::dvec3 forward = glm::normalize(axis);
    return glm::lookAt(position, position + forward, upFor(forward));
}

glm::dmat4 spotProjection(double fovy, double near, double far) {
    require(fovy > 0.0 && fovy < std::numbers::pi, "fovy", fovy, "(0, pi)");
    require(near > 0.0, "near", near, "(0, inf)");
    require(far > near, "far", far, "(near, inf)");
    return glm::perspective(fovy, 1.0, near, far);
}

double spotTexelSize(double depth, double fovy, int mapSize) {
    return 2.0 * depth * std::tan(fovy / 2.0) / mapSize;
}

} // namespace sgfx::shadow

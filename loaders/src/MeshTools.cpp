#include "sgfx/MeshTools.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <stdexcept>
#include <string>
#include <tuple>
#include <unordered_map>

namespace sgfx {

namespace {

// The geometry as a triangle list of vertex indices.
std::vector<std::uint32_t> triangleList(const Geometry& g) {
    const std::size_t n = g.elementCount();
    auto vertex = [&](std::size_t k) { return g.indices.empty() ? std::uint32_t(k) : g.indices[k]; };
    std::vector<std::uint32_t> tris;
    switch (g.mode) {
    case PrimitiveMode::Triangles:
        for (std::size_t k = 0; k + 2 < n; k += 3)
            tris.insert(tris.end(), {vertex(k), vertex(k + 1), vertex(k + 2)});
        break;
    case PrimitiveMode::TriangleStrip:
        for (std::size_t k = 0; k + 2 < n; ++k)
            tris.insert(tris.end(),
                        k % 2
                            ? std::initializer_list<std::uint32_t>{vertex(k + 1), vertex(k), vertex(k + 2)}
                            : std::initializer_list<std::uint32_t>{vertex(k), vertex(k + 1), vertex(k + 2)});
        break;
    case PrimitiveMode::TriangleFan:
        for (std::size_t k = 1; k + 1 < n; ++k)
            tris.insert(tris.end(), {vertex(0), vertex(k), vertex(k + 1)});
        break;
    default:
        throw std::invalid_argument("sgfx: geometry '" + g.name + "' is not made of triangles");
    }
    return tris;
}

float cornerAngle(glm::vec3 p, glm::vec3 a, glm::vec3 b) {
    const glm::vec3 u = a - p, v = b - p;
    const float lu = glm::length(u), lv = glm::length(v);
    if (lu == 0.0f || lv == 0.0f) return 0.0f;
    return std::acos(std::clamp(glm::dot(u, v) / (lu * lv), -1.0f, 1.0f));
}

struct Vec3Less {
    bool operator()(const glm::vec3& a, const glm::vec3& b) const {
        return std::tie(a.x, a.y, a.z) < std::tie(b.x, b.y, b.z);
    }
};

// Rebuilds `g` from corners: corner k of `tris` takes vertex tris[k] and the given extras;
// corners with equal (source vertex, extras) become one vertex.
template <class Extra, class Apply>
void rebuild(Geometry& g, const std::vector<std::uint32_t>& tris, const std::vector<Extra>& extra,
             Apply apply) {
    Geometry out;
    // Source vertices with identical attributes are one vertex (unindexed files repeat them).
    std::vector<std::uint32_t> canonical(g.positions.size());
    {
        std::map<std::vector<float>, std::uint32_t> ids;
        std::vector<float> key;
        auto push = [&key](const auto& v, std::size_t i) {
            if (v.empty()) return;
            const float* f = reinterpret_cast<const float*>(&v[i]);
            key.insert(key.end(), f, f + sizeof(v[i]) / sizeof(float));
        };
        for (std::size_t i = 0; i < g.positions.size(); ++i) {
            key.clear();
            push(g.positions, i);
            push(g.normals, i);
            push(g.tangents, i);
            push(g.texcoords, i);
            push(g.texcoords1, i);
            push(g.colors, i);
            canonical[i] = ids.try_emplace(key, std::uint32_t(i)).first->second;
        }
    }
    std::map<std::pair<std::uint32_t, std::array<std::uint32_t, sizeof(Extra) / 4>>, std::uint32_t> seen;
    for (std::size_t k = 0; k < tris.size(); ++k) {
        // Keys quantised to 2^-16, so rounding differences between faces do not split vertices.
        std::array<std::uint32_t, sizeof(Extra) / 4> bits;
        const float* values = reinterpret_cast<const float*>(&extra[k]);
        for (std::size_t c = 0; c < bits.size(); ++c)
            bits[c] = std::uint32_t(std::int32_t(std::lround(values[c] * 65536.0f)));
        const auto [it, fresh] =
            seen.try_emplace({canonical[tris[k]], bits}, std::uint32_t(out.positions.size()));
        if (fresh) {
            const std::uint32_t v = tris[k];
            out.positions.push_back(g.positions[v]);
            if (!g.normals.empty()) out.normals.push_back(g.normals[v]);
            if (!g.tangents.empty()) out.tangents.push_back(g.tangents[v]);
            if (!g.texcoords.empty()) out.texcoords.push_back(g.texcoords[v]);
            if (!g.texcoords1.empty()) out.texcoords1.push_back(g.texcoords1[v]);
            if (!g.colors.empty()) out.colors.push_back(g.colors[v]);
            apply(out, extra[k]);
        }
        out.indices.push_back(it->second);
    }
    g.positions = std::move(out.positions);
    g.normals = std::move(out.normals);
    g.tangents = std::move(out.tangents);
    g.texcoords = std::move(out.texcoords);
    g.texcoords1 = std::move(out.texcoords1);
    g.colors = std::move(out.colors);
    g.indices = std::move(out.indices);
    g.mode = PrimitiveMode::Triangles;
    g.dirty();
}

} // namespace

void computeNormals(Geometry& g, float creaseAngle) {
    if (!(creaseAngle >= 0.0f) || !std::isfinite(creaseAngle))
        throw std::invalid_argument("sgfx: computeNormals: crease angle " + std::to_string(creaseAngle) +
                                    " must be finite and >= 0");
    g.validate();
    const std::vector<std::uint32_t> tris = triangleList(g);
    const std::size_t faces = tris.size() / 3;
    std::vector<glm::vec3> faceNormal(faces);
    for (std::size_t f = 0; f < faces; ++f) {
        const glm::vec3 e1 = g.positions[tris[3 * f + 1]] - g.positions[tris[3 * f]],
                        e2 = g.positions[tris[3 * f + 2]] - g.positions[tris[3 * f]];
        const glm::vec3 n = glm::cross(e1, e2);
        const float l = glm::length(n);
        // Slivers (a sphere's pole, rounding in the file) have a noise direction: none at all.
        faceNormal[f] = l > 1e-5f * glm::length(e1) * glm::length(e2) ? n / l : glm::vec3(0.0f);
    }
    std::vector<glm::vec3> cornerNormal(tris.size());
    if (creaseAngle == 0.0f) {
        for (std::size_t k = 0; k < tris.size(); ++k)
            cornerNormal[k] = faceNormal[k / 3];
    } else {
        // Corners grouped by position, so seams of split vertices (UV seams) still smooth.
        std::map<glm::vec3, std::vector<std::size_t>, Vec3Less> byPosition;
        for (std::size_t k = 0; k < tris.size(); ++k)
            byPosition[g.positions[tris[k]]].push_back(k);
        std::vector<float> weight(tris.size());
        for (std::size_t k = 0; k < tris.size(); ++k) {
            const std::size_t f = k / 3, i = k % 3;
            weight[k] = cornerAngle(g.positions[tris[k]], g.positions[tris[3 * f + (i + 1) % 3]],
                                    g.positions[tris[3 * f + (i + 2) % 3]]);
        }
        const float cosCrease = std::cos(std::min(creaseAngle, 3.14159265f));
        for (const auto& [position, corners] : byPosition)
            for (std::size_t k : corners) {
                glm::vec3 sum(0.0f);
                // A degenerate face (no normal of its own) takes its neighbours' average.
                const bool degenerate = faceNormal[k / 3] == glm::vec3(0.0f);
                for (std::size_t o : corners)
                    if (degenerate || glm::dot(faceNormal[k / 3], faceNormal[o / 3]) >= cosCrease - 1e-6f)
                        sum += weight[o] * faceNormal[o / 3];
                const float l = glm::length(sum);
                cornerNormal[k] = l > 0.0f ? sum / l : faceNormal[k / 3];
            }
    }
    // Corners only slivers touch: their face's other corners' normals, else any unit vector.
    for (std::size_t k = 0; k < tris.size(); ++k)
        if (cornerNormal[k] == glm::vec3(0.0f)) {
            const std::size_t f = k / 3;
            const glm::vec3 sum = cornerNormal[3 * f] + cornerNormal[3 * f + 1] + cornerNormal[3 * f + 2];
            cornerNormal[k] = glm::length(sum) > 0.0f ? glm::normalize(sum) : glm::vec3(0, 0, 1);
        }
    g.normals.clear();
    rebuild(g, tris, cornerNormal, [](Geometry& out, const glm::vec3& n) { out.normals.push_back(n); });
}

void computeTangents(Geometry& g) {
    g.validate();
    if (g.normals.empty() || g.texcoords.empty())
        throw std::invalid_argument("sgfx: computeTangents: geometry '" + g.name +
                                    "' needs normals and texcoords");
    const std::vector<std::uint32_t> tris = triangleList(g);
    const std::size_t faces = tris.size() / 3;
    // Per face: tangent from dP = T·du + B·dv.
    std::vector<glm::vec3> faceT(faces);
    std::vector<float> faceSign(faces);
    for (std::size_t f = 0; f < faces; ++f) {
        const glm::vec3 p0 = g.positions[tris[3 * f]], p1 = g.positions[tris[3 * f + 1]],
                        p2 = g.positions[tris[3 * f + 2]];
        const glm::vec2 t0 = g.texcoords[tris[3 * f]], t1 = g.texcoords[tris[3 * f + 1]],
                        t2 = g.texcoords[tris[3 * f + 2]];
        const glm::vec3 e1 = p1 - p0, e2 = p2 - p0;
        const glm::vec2 d1 = t1 - t0, d2 = t2 - t0;
        const float det = d1.x * d2.y - d2.x * d1.y;
        if (std::abs(det) < 1e-20f) {
            faceT[f] = glm::vec3(0.0f);
            faceSign[f] = 1.0f;
            continue;
        }
        faceT[f] = (e1 * d2.y - e2 * d1.y) / det;
        // glTF's v runs down the image and its bitangent up it (B = -dP/dv), as MikkTSpace
        // gives for the v-flipped coordinates exporters feed it: det < 0 is the unmirrored case.
        faceSign[f] = det < 0.0f ? 1.0f : -1.0f;
    }
    // Corners at one vertex with one handedness share a tangent (angle-weighted sum).
    std::map<std::pair<std::uint32_t, bool>, glm::vec3> sums;
    std::vector<float> weight(tris.size());
    for (std::size_t k = 0; k < tris.size(); ++k) {
        const std::size_t f = k / 3, i = k % 3;
        weight[k] = cornerAngle(g.positions[tris[k]], g.positions[tris[3 * f + (i + 1) % 3]],
                                g.positions[tris[3 * f + (i + 2) % 3]]);
        const glm::vec3 n = g.normals[tris[k]];
        const glm::vec3 t = faceT[f] - n * glm::dot(n, faceT[f]);
        const float l = glm::length(t);
        if (l > 0.0f)
            sums[{tris[k], faceSign[f] < 0.0f}] += weight[k] * t / l;
        else
            sums[{tris[k], faceSign[f] < 0.0f}];
    }
    std::vector<glm::vec4> cornerTangent(tris.size());
    for (std::size_t k = 0; k < tris.size(); ++k) {
        const bool mirrored = faceSign[k / 3] < 0.0f;
        const glm::vec3 n = glm::normalize(g.normals[tris[k]]);
        glm::vec3 t = sums[{tris[k], mirrored}];
        t -= n * glm::dot(n, t);
        if (glm::length(t) < 1e-12f) {
            // No usable UV gradient: any tangent perpendicular to the normal.
            t = std::abs(n.x) < 0.9f ? glm::cross(n, glm::vec3(1, 0, 0)) : glm::cross(n, glm::vec3(0, 1, 0));
        }
        cornerTangent[k] = glm::vec4(glm::normalize(t), mirrored ? -1.0f : 1.0f);
    }
    g.tangents.clear();
    rebuild(g, tris, cornerTangent, [](Geometry& out, const glm::vec4& t) { out.tangents.push_back(t); });
}

} // namespace sgfx

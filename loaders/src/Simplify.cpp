#include "sgfx/Simplify.h"

// OpenMesh wants its IO header before the kernel headers.
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Decimater/DecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModNormalFlippingT.hh>
#include <OpenMesh/Tools/Decimater/ModQuadricT.hh>

#include <algorithm>
#include <array>
#include <cmath>
#include <iterator>
#include <limits>
#include <map>
#include <numeric>
#include <stdexcept>
#include <string>

namespace sgfx {

namespace {

using Mesh = OpenMesh::TriMesh_ArrayKernelT<>;

std::string label(const Geometry& g) {
    return g.name.empty() ? std::string("<unnamed>") : "'" + g.name + "'";
}

[[noreturn]] void refuse(const Geometry& g, const std::string& why) {
    throw std::invalid_argument("sgfx: simplify: geometry " + label(g) + " " + why);
}

void checkRatio(const Geometry& g, float ratio) {
    if (!(ratio > 0.0f && ratio <= 1.0f))
        refuse(g, "given triangle ratio " + std::to_string(ratio) + ": it must be in (0, 1]");
}

// Area-weighted face normals summed over every vertex at (nearly) the same position, so the
// normal is smooth across texture seams, where the mesh keeps separate vertices, and at poles
// whose vertices differ by rounding only (sin(pi) is not 0 in float).
void smoothNormals(Geometry& g) {
    const double cell = std::max(double(g.bound().radius), 1e-30) * 1e-6;
    auto keyOf = [&](const glm::vec3& p) {
        return std::array<long long, 3>{std::llround(p.x / cell), std::llround(p.y / cell),
                                        std::llround(p.z / cell)};
    };
    std::map<std::array<long long, 3>, glm::vec3> sum;
    for (std::size_t k = 0; k + 2 < g.indices.size(); k += 3) {
        const glm::vec3& a = g.positions[g.indices[k]];
        const glm::vec3& b = g.positions[g.indices[k + 1]];
        const glm::vec3& c = g.positions[g.indices[k + 2]];
        const glm::vec3 n = glm::cross(b - a, c - a); // length = twice the area
        for (const glm::vec3* p : {&a, &b, &c})
            sum[keyOf(*p)] += n;
    }
    g.normals.resize(g.positions.size());
    for (std::size_t i = 0; i < g.positions.size(); ++i) {
        const glm::vec3 n = sum[keyOf(g.positions[i])];
        const float len = glm::length(n);
        g.normals[i] = len > 0.0f && std::isfinite(len) ? n / len : glm::vec3(0, 0, 1);
    }
}

// Everything a decimation run needs: the welded mesh with its attributes, and the triangles
// OpenMesh refused (non-manifold), which are kept unchanged.
class Decimation {
public:
    explicit Decimation(const Geometry& g)
        : g_(g) {
        mesh_.request_vertex_status();
        mesh_.request_face_normals();
        hasUv_ = !g.texcoords.empty();
        hasColor_ = !g.colors.empty();
        if (hasUv_) mesh_.add_property(uv_);
        if (hasColor_) mesh_.add_property(color_);
        // Weld equal vertices (position and carried attributes) so the mesh is connected;
        // vertices split by a texcoord or colour seam stay apart, as mesh boundaries.
        std::map<std::array<float, 9>, Mesh::VertexHandle> welded;
        std::vector<Mesh::VertexHandle> handle(g.positions.size());
        for (std::size_t i = 0; i < g.positions.size(); ++i) {
            const glm::vec3& p = g.positions[i];
            const glm::vec2 uv = hasUv_ ? g.texcoords[i] : glm::vec2(0);
            const glm::vec4 c = hasColor_ ? g.colors[i] : glm::vec4(0);
            const std::array<float, 9> key{p.x, p.y, p.z, uv.x, uv.y, c.r, c.g, c.b, c.a};
            auto [it, added] = welded.emplace(key, Mesh::VertexHandle());
            if (added) {
                it->second = mesh_.add_vertex(Mesh::Point(p.x, p.y, p.z));
                if (hasUv_) mesh_.property(uv_, it->second) = uv;
                if (hasColor_) mesh_.property(color_, it->second) = c;
            }
            handle[i] = it->second;
        }
        const std::size_t n = g.elementCount() / 3 * 3;
        auto index = [&](std::size_t k) { return g.indices.empty() ? std::uint32_t(k) : g.indices[k]; };
        for (std::size_t k = 0; k < n; k += 3) {
            const Mesh::VertexHandle a = handle[index(k)], b = handle[index(k + 1)], c = handle[index(k + 2)];
            if (a == b || b == c || a == c) continue; // no area and no edge to collapse
            if (!mesh_.add_face(a, b, c).is_valid())
                for (std::size_t j = 0; j < 3; ++j)
                    kept_.push_back(index(k + j));
        }
        // Boundary vertices (open edges, texture and colour seams) stay where they are, so seams
        // and tile borders never open up.
        for (const auto v : mesh_.vertices())
            if (mesh_.is_boundary(v)) mesh_.status(v).set_locked(true);
        mesh_.update_face_normals();
        decimater_.add(quadric_);
        decimater_.module(quadric_).unset_max_err(); // rank collapses by error, never refuse
        decimater_.add(flipping_);                   // refuses collapses that fold a face over
        decimater_.initialize();
    }

    // Collapses until about `triangles` triangles are left in all (the run continues from the
    // previous, coarser targets reuse its work).
    std::shared_ptr<Geometry> reduceTo(std::size_t triangles) {
        const std::size_t live = liveFaces();
        const std::size_t keptTriangles = kept_.size() / 3;
        const std::size_t target = triangles > keptTriangles ? triangles - keptTriangles : 0;
        if (live > target) decimater_.decimate_to_faces(0, mesh_.n_faces() - (live - target));
        return extract();
    }

private:
    std::size_t liveFaces() const {
        return std::size_t(std::distance(mesh_.faces_sbegin(), mesh_.faces_end()));
    }

    std::shared_ptr<Geometry> extract() const {
        auto out = Geometry::create();
        std::vector<std::int64_t> slot(mesh_.n_vertices(), -1);
        auto vertex = [&](Mesh::VertexHandle v) {
            std::int64_t& s = slot[std::size_t(v.idx())];
            if (s < 0) {
                s = std::int64_t(out->positions.size());
                const auto p = mesh_.point(v);
                out->positions.emplace_back(p[0], p[1], p[2]);
                if (hasUv_) out->texcoords.push_back(mesh_.property(uv_, v));
                if (hasColor_) out->colors.push_back(mesh_.property(color_, v));
            }
            return std::uint32_t(s);
        };
        for (const auto f : mesh_.faces())
            for (const auto v : mesh_.fv_range(f))
                out->indices.push_back(vertex(v));
        for (std::uint32_t i : kept_) {
            out->indices.push_back(std::uint32_t(out->positions.size()));
            out->positions.push_back(g_.positions[i]);
            if (hasUv_) out->texcoords.push_back(g_.texcoords[i]);
            if (hasColor_) out->colors.push_back(g_.colors[i]);
        }
        smoothNormals(*out);
        return out;
    }

    const Geometry& g_;
    Mesh mesh_;
    bool hasUv_ = false, hasColor_ = false;
    OpenMesh::VPropHandleT<glm::vec2> uv_;
    OpenMesh::VPropHandleT<glm::vec4> color_;
    std::vector<std::uint32_t> kept_;
    OpenMesh::Decimater::DecimaterT<Mesh> decimater_{mesh_};
    OpenMesh::Decimater::ModQuadricT<Mesh>::Handle quadric_;
    OpenMesh::Decimater::ModNormalFlippingT<Mesh>::Handle flipping_;
};

} // namespace

std::vector<std::shared_ptr<Geometry>> simplify(const Geometry& g, std::span<const float> ratios) {
    if (g.mode != PrimitiveMode::Triangles)
        refuse(g, "is not PrimitiveMode::Triangles (strips, fans, lines and points are not decimated)");
    try {
        g.validate();
    } catch (const std::invalid_argument& e) {
        refuse(g, std::string("is invalid: ") + e.what());
    }
    if (g.triangleCount() == 0) refuse(g, "has no triangles");
    for (float r : ratios)
        checkRatio(g, r);

    std::vector<std::shared_ptr<Geometry>> out(ratios.size());
    // Finest first, so every coarser level continues the collapses of the one before.
    std::vector<std::size_t> order(ratios.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t a, std::size_t b) { return ratios[a] > ratios[b]; });
    std::unique_ptr<Decimation> run;
    const std::size_t total = g.triangleCount();
    for (std::size_t i : order) {
        std::shared_ptr<Geometry> level;
        if (ratios[i] == 1.0f) {
            level = Geometry::create();
            level->positions = g.positions;
            level->normals = g.normals;
            level->tangents = g.tangents;
            level->texcoords = g.texcoords;
            level->colors = g.colors;
            level->indices = g.indices;
        } else {
            if (!run) run = std::make_unique<Decimation>(g);
            level = run->reduceTo(std::size_t(std::lround(double(ratios[i]) * double(total))));
        }
        level->name =
            g.name + (g.name.empty() ? "" : " ") + std::to_string(int(std::lround(ratios[i] * 100))) + "%";
        out[i] = std::move(level);
    }
    return out;
}

std::shared_ptr<Geometry> simplify(const Geometry& geometry, float triangleRatio) {
    return simplify(geometry, std::span<const float>(&triangleRatio, 1)).front();
}

std::span<const LodLevel> defaultLodLevels() {
    static constexpr LodLevel levels[] = {{1.0f, 300.0f}, {0.5f, 100.0f}, {0.12f, 0.0f}};
    return levels;
}

std::shared_ptr<LOD> makeLod(std::shared_ptr<Geometry> full, std::span<const LodLevel> levels) {
    if (!full) throw std::invalid_argument("sgfx: makeLod: null geometry");
    if (levels.empty()) throw std::invalid_argument("sgfx: makeLod: no levels for geometry " + label(*full));
    for (std::size_t i = 0; i < levels.size(); ++i) {
        const float px = levels[i].minPixels;
        if (!(px >= 0.0f) || (i > 0 && !(px < levels[i - 1].minPixels)))
            throw std::invalid_argument("sgfx: makeLod: geometry " + label(*full) + " level " +
                                        std::to_string(i) + ": minPixels " + std::to_string(px) +
                                        " must be >= 0 and below the previous level's");
    }
    std::vector<float> ratios;
    for (const LodLevel& l : levels)
        ratios.push_back(l.triangleRatio);
    // Decimate only what is not the full geometry itself.
    std::vector<float> reduced;
    for (float r : ratios)
        if (r != 1.0f) reduced.push_back(r);
    for (float r : ratios)
        checkRatio(*full, r);
    const auto copies = simplify(*full, reduced);

    auto lod = LOD::create();
    lod->name = full->name.empty() ? "LOD" : full->name + " LOD";
    // Sized by the full geometry, so the switches do not move with the decimated levels' bounds.
    const BoundingSphere& b = full->bound();
    if (b.radius > 0.0f) lod->setUserSphere(b.center, b.radius);
    float maxPixels = std::numeric_limits<float>::infinity();
    std::size_t next = 0;
    for (const LodLevel& l : levels) {
        std::shared_ptr<Geometry> g = l.triangleRatio == 1.0f ? full : copies[next++];
        if (g != full) g->setStateSet(full->stateSet());
        lod->addChild(g, l.minPixels, maxPixels);
        maxPixels = l.minPixels;
    }
    return lod;
}

} // namespace sgfx

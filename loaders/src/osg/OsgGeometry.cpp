// osg::Geometry → sgfx Geometry: arrays with their bindings (per vertex, overall, per primitive
// set), primitive sets of every mode decomposed into triangle, line and point lists.
#include "OsgConvert.h"

#include <osg/PrimitiveSet>

#include <glm/glm.hpp>

#include <cmath>
#include <stdexcept>

namespace sgfx::osgbridge {

namespace {

/// One element of an osg::Array as four floats (missing components 0, w 1; normalised bytes).
glm::vec4 element(const osg::Array& a, unsigned i) {
    glm::vec4 v(0.0f, 0.0f, 0.0f, 1.0f);
    const unsigned n = std::min(unsigned(std::max(a.getDataSize(), 0)), 4u);
    const auto* p =
        static_cast<const unsigned char*>(a.getDataPointer()) + std::size_t(i) * a.getElementSize();
    for (unsigned c = 0; c < n; ++c) {
        switch (a.getDataType()) {
        case GL_FLOAT:
            v[int(c)] = reinterpret_cast<const float*>(p)[c];
            break;
        case GL_DOUBLE:
            v[int(c)] = float(reinterpret_cast<const double*>(p)[c]);
            break;
        case GL_UNSIGNED_BYTE:
            v[int(c)] = float(p[c]) / 255.0f;
            break;
        case GL_UNSIGNED_SHORT:
            v[int(c)] = float(reinterpret_cast<const std::uint16_t*>(p)[c]) / 65535.0f;
            break;
        default:
            break; // unsupported types are refused in usable()
        }
    }
    return v;
}

bool usable(Context& cx, const osg::Array* a, const char* what) {
    if (!a) return false;
    // The binding as the file had it: a corrupt file can hold any number there.
    const int binding = int(a->getBinding());
    if (binding != osg::Array::BIND_OFF && binding != osg::Array::BIND_OVERALL &&
        binding != osg::Array::BIND_PER_PRIMITIVE_SET && binding != osg::Array::BIND_PER_VERTEX &&
        binding != osg::Array::BIND_UNDEFINED)
        throw LoadError("sgfx: model '" + cx.file.string() + "': osg::Geometry " + what + " array at " +
                        cx.where() + ": binding " + std::to_string(binding) + " is not one of OSG's");
    if (a->getNumElements() == 0 || binding == osg::Array::BIND_OFF) return false;
    const auto t = a->getDataType();
    if (t == GL_FLOAT || t == GL_DOUBLE || t == GL_UNSIGNED_BYTE || t == GL_UNSIGNED_SHORT) return true;
    cx.warn(std::string("osg::Geometry ") + what + " array of " + a->className() + ": not converted");
    return false;
}

/// A run of vertex indices drawn with one mode (a DrawArrayLengths gives one run per length).
struct Run {
    GLenum mode;
    std::vector<std::uint32_t> indices;
    unsigned set; ///< primitive set number, for BIND_PER_PRIMITIVE_SET arrays
};

std::vector<Run> runsOf(const osg::Geometry& g) {
    std::vector<Run> runs;
    for (unsigned p = 0; p < g.getNumPrimitiveSets(); ++p) {
        const osg::PrimitiveSet* set = g.getPrimitiveSet(p);
        if (const auto* l = dynamic_cast<const osg::DrawArrayLengths*>(set)) {
            std::uint32_t first = std::uint32_t(l->getFirst());
            for (auto len : *l) {
                Run r{set->getMode(), {}, p};
                for (int i = 0; i < len; ++i)
                    r.indices.push_back(first + std::uint32_t(i));
                first += std::uint32_t(std::max(len, 0));
                runs.push_back(std::move(r));
            }
            continue;
        }
        Run r{set->getMode(), {}, p};
        r.indices.reserve(set->getNumIndices());
        for (unsigned i = 0; i < set->getNumIndices(); ++i)
            r.indices.push_back(set->index(i));
        runs.push_back(std::move(r));
    }
    return runs;
}

enum Kind { Triangles, Lines, Points };

/// Per triangle: the vertex whose normal and colour flat shading uses (OpenGL's provoking vertex
/// of the primitive it came from) and which of its edges (ab, bc, ca: bits 0, 1, 2) are the
/// primitive's outline (PolygonMode LINE draws those, not a quad's or polygon's diagonals).
struct TriangleInfo {
    std::uint32_t provoking;
    std::uint8_t edges;
};

/// Appends the run's primitives, as lists, to out[kind]; strips keep OSG's winding, degenerate
/// triangles are kept (OSG counts them too). Returns false for a mode sgfx cannot draw.
bool decompose(const Run& r, std::vector<std::uint32_t> (&out)[3], std::vector<TriangleInfo>& info) {
    const auto& x = r.indices;
    const std::size_t n = x.size();
    auto tri = [&](std::size_t a, std::size_t b, std::size_t c, std::size_t provoking = ~std::size_t{0},
                   std::uint8_t edges = 7) {
        out[Triangles].insert(out[Triangles].end(), {x[a], x[b], x[c]});
        info.push_back({x[provoking == ~std::size_t{0} ? c : provoking], edges});
    };
    auto line = [&](std::size_t a, std::size_t b) { out[Lines].insert(out[Lines].end(), {x[a], x[b]}); };
    switch (r.mode) {
    case GL_POINTS:
        out[Points].insert(out[Points].end(), x.begin(), x.end());
        return true;
    case GL_LINES:
        for (std::size_t i = 0; i + 1 < n; i += 2)
            line(i, i + 1);
        return true;
    case GL_LINE_STRIP:
        for (std::size_t i = 0; i + 1 < n; ++i)
            line(i, i + 1);
        return true;
    case GL_LINE_LOOP:
        for (std::size_t i = 0; i + 1 < n; ++i)
            line(i, i + 1);
        if (n > 2) line(n - 1, 0);
        return true;
    case GL_TRIANGLES:
        for (std::size_t i = 0; i + 2 < n; i += 3)
            tri(i, i + 1, i + 2);
        return true;
    case GL_TRIANGLE_STRIP:
        for (std::size_t i = 2; i < n; ++i)
            (i % 2) ? tri(i - 2, i, i - 1, i) : tri(i - 2, i - 1, i);
        return true;
    case GL_TRIANGLE_FAN:
        for (std::size_t i = 2; i < n; ++i)
            tri(0, i - 1, i);
        return true;
    case GL_POLYGON: // flat-shaded by its first vertex; outlined without its fan's diagonals
        for (std::size_t i = 2; i < n; ++i)
            tri(0, i - 1, i, 0, std::uint8_t((i == 2 ? 1 : 0) | 2 | (i + 1 == n ? 4 : 0)));
        return true;
    case GL_QUADS: // provoking vertex: the quad's last
        for (std::size_t i = 0; i + 3 < n; i += 4)
            tri(i, i + 1, i + 2, i + 3, 3), tri(i, i + 2, i + 3, i + 3, 6);
        return true;
    case GL_QUAD_STRIP:
        for (std::size_t i = 0; i + 3 < n; i += 2)
            tri(i, i + 1, i + 3, i + 3, 3), tri(i, i + 3, i + 2, i + 3, 6);
        return true;
    default:
        return false;
    }
}

/// The per-vertex value of an array at source vertex `v` of primitive set `set`.
glm::vec4 valueAt(const osg::Array& a, std::uint32_t v, unsigned set) {
    switch (a.getBinding()) {
    case osg::Array::BIND_OVERALL:
        return element(a, 0);
    case osg::Array::BIND_PER_PRIMITIVE_SET:
        return element(a, std::min(set, a.getNumElements() - 1));
    default:
        return element(a, std::min(v, a.getNumElements() - 1));
    }
}

struct Arrays {
    const osg::Array* vertices;
    const osg::Array* normals;
    const osg::Array* colors;
    const osg::Array* tex0;
    const osg::Array* tex1;
};

/// One vertex to make: its source vertex, the one whose normal and colour it takes (itself, or
/// its triangle's provoking vertex under flat shading), and its primitive set.
struct Corner {
    std::uint32_t vertex, shade;
    unsigned set;
};

/// Fills the attributes for the corners in order.
void fill(Geometry& out, const Arrays& a, const std::vector<Corner>& order) {
    for (auto [v, shade, set] : order) {
        const glm::vec3 p(element(*a.vertices, v));
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
            throw std::invalid_argument("osg::Geometry vertex " + std::to_string(v) + " is not finite");
        out.positions.push_back(p);
        if (a.normals) {
            glm::vec3 n(valueAt(*a.normals, shade, set));
            const float len = glm::length(n);
            out.normals.push_back(len > 1e-12f && std::isfinite(len) ? n / len : glm::vec3(0.0f, 0.0f, 1.0f));
        }
        if (a.colors) {
            const glm::vec4 c = valueAt(*a.colors, shade, set);
            out.colors.push_back(linearColor(osg::Vec4(c.r, c.g, c.b, c.a)));
        }
        const auto finite2 = [](glm::vec2 t) {
            return std::isfinite(t.x) && std::isfinite(t.y) ? t : glm::vec2(0.0f);
        };
        if (a.tex0) out.texcoords.push_back(finite2(glm::vec2(valueAt(*a.tex0, v, set))));
        if (a.tex1) out.texcoords1.push_back(finite2(glm::vec2(valueAt(*a.tex1, v, set))));
    }
}

} // namespace

/// PolygonMode LINE and POINT: the triangles' outline edges, or their vertices, instead of them.
void outline(int polygonMode, std::vector<std::uint32_t> (&lists)[3], std::vector<unsigned> (&sets)[3],
             const std::vector<TriangleInfo>& info) {
    auto& t = lists[Triangles];
    for (std::size_t i = 0; i + 2 < t.size(); i += 3) {
        const unsigned set = sets[Triangles][i];
        for (int e = 0; e < 3; ++e) {
            if (polygonMode == GL_POINT) {
                lists[Points].push_back(t[i + std::size_t(e)]), sets[Points].push_back(set);
            } else if (info[i / 3].edges & (1 << e)) {
                lists[Lines].insert(lists[Lines].end(),
                                    {t[i + std::size_t(e)], t[i + std::size_t(e + 1) % 3]});
                sets[Lines].insert(sets[Lines].end(), {set, set});
            }
        }
    }
    t.clear(), sets[Triangles].clear();
}

std::vector<std::shared_ptr<Geometry>> convertGeometry(Context& cx, const osg::Geometry& g,
                                                       const GeometryShape& shape) {
    const bool keepColors = shape.colors;
    const osg::Array* vertices = g.getVertexArray();
    if (!usable(cx, vertices, "vertex")) return {};
    Arrays a{vertices, usable(cx, g.getNormalArray(), "normal") ? g.getNormalArray() : nullptr,
             keepColors && usable(cx, g.getColorArray(), "colour") ? g.getColorArray() : nullptr,
             usable(cx, g.getTexCoordArray(0), "texture coordinate") ? g.getTexCoordArray(0) : nullptr,
             usable(cx, g.getTexCoordArray(1), "texture coordinate") ? g.getTexCoordArray(1) : nullptr};
    for (unsigned unit = 2; unit < g.getNumTexCoordArrays(); ++unit)
        if (g.getTexCoordArray(unit)) cx.warn("osg::Geometry texture coordinate sets above 1: not converted");
    const unsigned count = vertices->getNumElements();
    // Arrays bound per primitive set give a vertex one value per set: such geometries are
    // unshared (each drawn vertex its own); everything else keeps OSG's vertices and counts.
    bool perSet = false;
    for (const osg::Array* x : {a.normals, a.colors, a.tex0, a.tex1})
        perSet |= x && x->getBinding() == osg::Array::BIND_PER_PRIMITIVE_SET;

    std::vector<std::uint32_t> lists[3];
    std::vector<unsigned> sets[3]; // primitive set of each listed index
    std::vector<TriangleInfo> info;
    bool badMode = false;
    for (const Run& r : runsOf(g)) {
        badMode |= !decompose(r, lists, info);
        for (int k = 0; k < 3; ++k)
            sets[k].resize(lists[k].size(), r.set);
    }
    if (shape.polygonMode == GL_LINE || shape.polygonMode == GL_POINT)
        outline(shape.polygonMode, lists, sets, info);
    // Flat shading takes each triangle's normal and colour from its provoking vertex: such
    // triangles get vertices of their own.
    const bool flat = shape.flat && !lists[Triangles].empty();
    if (badMode)
        cx.warn("osg::Geometry primitive mode (adjacency or patches): those primitive sets not converted");
    cx.charge(std::size_t(count) * 64 + (lists[0].size() + lists[1].size() + lists[2].size()) * 4,
              "osg::Geometry");

    std::vector<std::shared_ptr<Geometry>> out;
    const PrimitiveMode modes[3] = {PrimitiveMode::Triangles, PrimitiveMode::Lines, PrimitiveMode::Points};
    for (int k = 0; k < 3; ++k) {
        if (lists[k].empty()) continue;
        for (auto i : lists[k])
            if (i >= count)
                throw LoadError("sgfx: model '" + cx.file.string() + "': osg::Geometry '" + g.getName() +
                                "' at " + cx.where() + ": index " + std::to_string(i) + " past its " +
                                std::to_string(count) + " vertices");
        auto geometry = Geometry::create();
        geometry->name = g.getName();
        geometry->mode = modes[k];
        std::vector<Corner> order;
        if (perSet || (flat && k == Triangles)) {
            for (std::size_t i = 0; i < lists[k].size(); ++i) {
                const std::uint32_t v = lists[k][i];
                order.push_back({v, flat && k == Triangles ? info[i / 3].provoking : v, sets[k][i]});
                geometry->indices.push_back(std::uint32_t(i));
            }
        } else {
            for (std::uint32_t v = 0; v < count; ++v)
                order.push_back({v, v, 0u});
            geometry->indices = lists[k];
        }
        fill(*geometry, a, order);
        geometry->validate();
        out.push_back(std::move(geometry));
    }
    return out;
}

} // namespace sgfx::osgbridge

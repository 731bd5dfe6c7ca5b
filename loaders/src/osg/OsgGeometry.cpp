// osg::Geometry → sgfx Geometry: arrays with their bindings (per vertex, overall, per primitive
// set), primitive sets of every mode decomposed into triangle, line and point lists.
#include "OsgConvert.h"

#include <osg/PrimitiveSet>

#include <glm/glm.hpp>

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

bool usable(const osg::Array* a) {
    if (!a || a->getNumElements() == 0 || a->getBinding() == osg::Array::BIND_OFF) return false;
    const auto t = a->getDataType();
    return t == GL_FLOAT || t == GL_DOUBLE || t == GL_UNSIGNED_BYTE || t == GL_UNSIGNED_SHORT;
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

/// Appends the run's primitives, as lists, to out[kind]; strips keep OSG's winding, degenerate
/// triangles are kept (OSG counts them too). Returns false for a mode sgfx cannot draw.
bool decompose(const Run& r, std::vector<std::uint32_t> (&out)[3]) {
    const auto& x = r.indices;
    const std::size_t n = x.size();
    auto tri = [&](std::size_t a, std::size_t b, std::size_t c) {
        out[Triangles].insert(out[Triangles].end(), {x[a], x[b], x[c]});
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
            (i % 2) ? tri(i - 2, i, i - 1) : tri(i - 2, i - 1, i);
        return true;
    case GL_TRIANGLE_FAN:
    case GL_POLYGON:
        for (std::size_t i = 2; i < n; ++i)
            tri(0, i - 1, i);
        return true;
    case GL_QUADS:
        for (std::size_t i = 0; i + 3 < n; i += 4)
            tri(i, i + 1, i + 2), tri(i, i + 2, i + 3);
        return true;
    case GL_QUAD_STRIP:
        for (std::size_t i = 0; i + 3 < n; i += 2)
            tri(i, i + 1, i + 3), tri(i, i + 3, i + 2);
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

/// Fills the attributes for the vertices `order` (source vertex, primitive set) in order.
void fill(Geometry& out, const Arrays& a, const std::vector<std::pair<std::uint32_t, unsigned>>& order) {
    for (auto [v, set] : order) {
        out.positions.push_back(glm::vec3(element(*a.vertices, v)));
        if (a.normals) {
            glm::vec3 n(valueAt(*a.normals, v, set));
            const float len = glm::length(n);
            out.normals.push_back(len > 1e-12f && std::isfinite(len) ? n / len : glm::vec3(0.0f, 0.0f, 1.0f));
        }
        if (a.colors) {
            const glm::vec4 c = valueAt(*a.colors, v, set);
            out.colors.push_back(linearColor(osg::Vec4(c.r, c.g, c.b, c.a)));
        }
        if (a.tex0) out.texcoords.push_back(glm::vec2(valueAt(*a.tex0, v, set)));
        if (a.tex1) out.texcoords1.push_back(glm::vec2(valueAt(*a.tex1, v, set)));
    }
}

} // namespace

std::vector<std::shared_ptr<Geometry>> convertGeometry(Context& cx, const osg::Geometry& g, bool keepColors) {
    const osg::Array* vertices = g.getVertexArray();
    if (!usable(vertices)) return {};
    Arrays a{vertices, usable(g.getNormalArray()) ? g.getNormalArray() : nullptr,
             keepColors && usable(g.getColorArray()) ? g.getColorArray() : nullptr,
             usable(g.getTexCoordArray(0)) ? g.getTexCoordArray(0) : nullptr,
             usable(g.getTexCoordArray(1)) ? g.getTexCoordArray(1) : nullptr};
    const unsigned count = vertices->getNumElements();
    // Arrays bound per primitive set give a vertex one value per set: such geometries are
    // unshared (each drawn vertex its own); everything else keeps OSG's vertices and counts.
    bool perSet = false;
    for (const osg::Array* x : {a.normals, a.colors, a.tex0, a.tex1})
        perSet |= x && x->getBinding() == osg::Array::BIND_PER_PRIMITIVE_SET;

    std::vector<std::uint32_t> lists[3];
    std::vector<unsigned> sets[3]; // primitive set of each listed index (perSet only)
    bool badMode = false;
    for (const Run& r : runsOf(g)) {
        badMode |= !decompose(r, lists);
        for (int k = 0; k < 3; ++k)
            sets[k].resize(lists[k].size(), r.set);
    }
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
        std::vector<std::pair<std::uint32_t, unsigned>> order;
        if (perSet) {
            for (std::size_t i = 0; i < lists[k].size(); ++i)
                order.emplace_back(lists[k][i], sets[k][i]);
            for (std::size_t i = 0; i < lists[k].size(); ++i)
                geometry->indices.push_back(std::uint32_t(i));
        } else {
            for (std::uint32_t v = 0; v < count; ++v)
                order.emplace_back(v, 0u);
            geometry->indices = lists[k];
        }
        fill(*geometry, a, order);
        geometry->validate();
        out.push_back(std::move(geometry));
    }
    return out;
}

} // namespace sgfx::osgbridge

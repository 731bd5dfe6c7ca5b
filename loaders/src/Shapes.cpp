#include "sgfx/Shapes.h"

#include <glm/gtc/constants.hpp>

#include <stdexcept>
#include <string>

namespace sgfx::shapes {

namespace {
void addQuad(Geometry& g, glm::vec3 o, glm::vec3 u, glm::vec3 v, glm::vec2 uvScale = {1, 1}) {
    const auto base = std::uint32_t(g.positions.size());
    const glm::vec3 n = glm::normalize(glm::cross(u, v));
    const glm::vec4 t(glm::normalize(u), 1.0f);
    const glm::vec3 p[4] = {o, o + u, o + u + v, o + v};
    // glTF convention: v = 0 is the image's top row, so v grows down the face.
    const glm::vec2 uv[4] = {{0, uvScale.y}, {uvScale.x, uvScale.y}, {uvScale.x, 0}, {0, 0}};
    for (int i = 0; i < 4; ++i) {
        g.positions.push_back(p[i]);
        g.normals.push_back(n);
        g.tangents.push_back(t);
        g.texcoords.push_back(uv[i]);
    }
    for (std::uint32_t i : {0u, 1u, 2u, 0u, 2u, 3u})
        g.indices.push_back(base + i);
}
void requirePositive(float v, const char* what) {
    if (!(v > 0.0f) || !std::isfinite(v))
        throw std::invalid_argument(std::string("sgfx::shapes: ") + what + " must be finite and > 0 (got " +
                                    std::to_string(v) + ")");
}
// Tessellation counts: enough for any real use, small enough that no allocation explodes.
void requireCount(int v, int min, int max, const char* what) {
    if (v < min || v > max)
        throw std::invalid_argument(std::string("sgfx::shapes: ") + what + " must be in " +
                                    std::to_string(min) + ".." + std::to_string(max) + " (got " +
                                    std::to_string(v) + ")");
}
} // namespace

std::shared_ptr<Geometry> box(const glm::vec3& s) {
    requirePositive(s.x, "box size x");
    requirePositive(s.y, "box size y");
    requirePositive(s.z, "box size z");
    auto g = Geometry::create();
    const glm::vec3 h = s * 0.5f;
    addQuad(*g, {-h.x, -h.y, h.z}, {s.x, 0, 0}, {0, s.y, 0});  // +Z
    addQuad(*g, {-h.x, h.y, -h.z}, {s.x, 0, 0}, {0, -s.y, 0}); // -Z
    addQuad(*g, {h.x, -h.y, -h.z}, {0, s.y, 0}, {0, 0, s.z});  // +X
    addQuad(*g, {-h.x, h.y, -h.z}, {0, -s.y, 0}, {0, 0, s.z}); // -X
    addQuad(*g, {h.x, h.y, -h.z}, {-s.x, 0, 0}, {0, 0, s.z});  // +Y
    addQuad(*g, {-h.x, -h.y, -h.z}, {s.x, 0, 0}, {0, 0, s.z}); // -Y
    return g;
}

std::shared_ptr<Geometry> quad(float w, float h) {
    requirePositive(w, "quad width");
    requirePositive(h, "quad height");
    auto g = Geometry::create();
    addQuad(*g, {-w / 2, -h / 2, 0}, {w, 0, 0}, {0, h, 0});
    return g;
}

std::shared_ptr<Geometry> cylinder(float r, float height, int seg, bool caps) {
    requirePositive(r, "cylinder radius");
    requirePositive(height, "cylinder height");
    requireCount(seg, 3, 1 << 16, "cylinder segments");
    auto g = Geometry::create();
    for (int i = 0; i <= seg; ++i) {
        const float a = glm::two_pi<float>() * float(i) / float(seg);
        const glm::vec3 n(std::cos(a), std::sin(a), 0);
        for (float z : {0.0f, height}) {
            g->positions.push_back(n * r + glm::vec3(0, 0, z));
            g->normals.push_back(n);
            g->tangents.push_back({-n.y, n.x, 0, 1});
            g->texcoords.push_back({float(i) / float(seg), 1.0f - z / height});
        }
    }
    for (int i = 0; i < seg; ++i) {
        const auto b = std::uint32_t(2 * i);
        for (std::uint32_t k : {0u, 2u, 3u, 0u, 3u, 1u})
            g->indices.push_back(b + k);
    }
    if (caps) {
        for (float z : {0.0f, height}) {
            const glm::vec3 n(0, 0, z > 0 ? 1 : -1);
            const auto c = std::uint32_t(g->positions.size());
            g->positions.push_back({0, 0, z});
            // u runs along +X and v along +Y on both caps; glTF's bitangent (-dP/dv) is -Y, which
            // is cross(N, T) on the bottom cap and its opposite on the top one.
            const float w = z > 0 ? -1.0f : 1.0f;
            g->normals.push_back(n);
            g->tangents.push_back({1, 0, 0, w});
            g->texcoords.push_back({0.5f, 0.5f});
            for (int i = 0; i <= seg; ++i) {
                const float a = glm::two_pi<float>() * float(i) / float(seg);
                g->positions.push_back({r * std::cos(a), r * std::sin(a), z});
                g->normals.push_back(n);
                g->tangents.push_back({1, 0, 0, w});
                g->texcoords.push_back({0.5f + 0.5f * std::cos(a), 0.5f + 0.5f * std::sin(a)});
            }
            for (int i = 0; i < seg; ++i) {
                const auto a = c + 1 + std::uint32_t(i), b = a + 1;
                if (z > 0)
                    g->indices.insert(g->indices.end(), {c, a, b});
                else
                    g->indices.insert(g->indices.end(), {c, b, a});
            }
        }
    }
    return g;
}

std::shared_ptr<Geometry> cone(float r, float height, int seg) {
    requirePositive(r, "cone radius");
    requirePositive(height, "cone height");
    requireCount(seg, 3, 1 << 16, "cone segments");
    auto g = Geometry::create();
    const float slope = r / height;
    for (int i = 0; i < seg; ++i) {
        const float a0 = glm::two_pi<float>() * float(i) / float(seg);
        const float a1 = glm::two_pi<float>() * float(i + 1) / float(seg);
        const float am = 0.5f * (a0 + a1);
        const auto b = std::uint32_t(g->positions.size());
        for (float a : {a0, a1}) {
            g->positions.push_back({r * std::cos(a), r * std::sin(a), 0});
            g->normals.push_back(glm::normalize(glm::vec3(std::cos(a), std::sin(a), slope)));
        }
        g->positions.push_back({0, 0, height});
        g->normals.push_back(glm::normalize(glm::vec3(std::cos(am), std::sin(am), slope)));
        g->indices.insert(g->indices.end(), {b, b + 1, b + 2});
    }
    g->texcoords.assign(g->positions.size(), glm::vec2(0.5f));
    return g;
}

std::shared_ptr<Geometry> sphere(float r, int seg, int rings) {
    requirePositive(r, "sphere radius");
    requireCount(seg, 3, 1 << 12, "sphere segments");
    requireCount(rings, 2, 1 << 12, "sphere rings");
    auto g = Geometry::create();
    for (int j = 0; j <= rings; ++j) {
        const float v = float(j) / float(rings);
        const float theta = glm::pi<float>() * v;
        for (int i = 0; i <= seg; ++i) {
            const float u = float(i) / float(seg);
            const float phi = glm::two_pi<float>() * u;
            const glm::vec3 n(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                              std::cos(theta));
            g->positions.push_back(n * r);
            g->normals.push_back(n);
            g->tangents.push_back({-std::sin(phi), std::cos(phi), 0, 1});
            g->texcoords.push_back({u, v}); // v = 0 at the top pole (image top row)
        }
    }
    for (int j = 0; j < rings; ++j)
        for (int i = 0; i < seg; ++i) {
            const auto a = std::uint32_t(j * (seg + 1) + i), b = a + std::uint32_t(seg + 1);
            g->indices.insert(g->indices.end(), {a, b, a + 1, a + 1, b, b + 1});
        }
    return g;
}

std::shared_ptr<Geometry> heightfield(float x0, float y0, float sx, float sy, int nx, int ny,
                                      const std::function<float(float, float)>& height) {
    requirePositive(sx, "heightfield size x");
    requirePositive(sy, "heightfield size y");
    requireCount(nx, 1, 1 << 13, "heightfield cells along x");
    requireCount(ny, 1, 1 << 13, "heightfield cells along y");
    if (!std::isfinite(x0) || !std::isfinite(y0))
        throw std::invalid_argument("sgfx::shapes: heightfield origin must be finite");
    if (!height) throw std::invalid_argument("sgfx::shapes: heightfield needs a height function");
    auto g = Geometry::create();
    const float dx = sx / float(nx), dy = sy / float(ny);
    g->positions.reserve(std::size_t(nx + 1) * (ny + 1));
    for (int j = 0; j <= ny; ++j)
        for (int i = 0; i <= nx; ++i) {
            const float x = x0 + dx * float(i), y = y0 + dy * float(j);
            const float z = height(x, y);
            if (!std::isfinite(z))
                throw std::invalid_argument("sgfx::shapes: heightfield height(" + std::to_string(x) + ", " +
                                            std::to_string(y) + ") is not finite");
            g->positions.push_back({x, y, z});
            const float hx = height(x + dx, y) - height(x - dx, y);
            const float hy = height(x, y + dy) - height(x, y - dy);
            g->normals.push_back(glm::normalize(glm::vec3(-hx / (2 * dx), -hy / (2 * dy), 1.0f)));
            g->texcoords.push_back({x / 8.0f, y / 8.0f});
        }
    g->indices.reserve(std::size_t(nx) * ny * 6);
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
            const auto a = std::uint32_t(j * (nx + 1) + i), b = a + 1, c = a + std::uint32_t(nx + 1),
                       d = c + 1;
            g->indices.insert(g->indices.end(), {a, b, d, a, d, c});
        }
    return g;
}

void append(Geometry& dst, const Geometry& src, const glm::mat4& m) {
    const auto base = std::uint32_t(dst.positions.size());
    const glm::mat3 nm = glm::transpose(glm::inverse(glm::mat3(m)));
    for (const auto& p : src.positions)
        dst.positions.push_back(glm::vec3(m * glm::vec4(p, 1)));
    for (const auto& n : src.normals)
        dst.normals.push_back(glm::normalize(nm * n));
    for (const auto& t : src.tangents)
        dst.tangents.push_back(glm::vec4(glm::normalize(glm::mat3(m) * glm::vec3(t)), t.w));
    dst.texcoords.insert(dst.texcoords.end(), src.texcoords.begin(), src.texcoords.end());
    dst.colors.insert(dst.colors.end(), src.colors.begin(), src.colors.end());
    if (src.indices.empty())
        for (std::uint32_t i = 0; i < src.positions.size(); ++i)
            dst.indices.push_back(base + i);
    else
        for (auto i : src.indices)
            dst.indices.push_back(base + i);
    dst.dirty();
}

} // namespace sgfx::shapes

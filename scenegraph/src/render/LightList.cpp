#include "render/LightList.h"

#include <algorithm>
#include <cmath>

namespace sgfx::render {

GpuLight packLight(const LightInfo& l, int index) {
    GpuLight g;
    g.vector = l.vector;
    g.color = glm::vec4(l.color, l.range > 0.0f ? 1.0f / l.range : 0.0f);
    g.spot = glm::vec4(l.spotAxis, l.angleScale);
    g.params = glm::vec4(l.angleOffset, l.inverseSquare ? 1.0f : 0.0f, float(index), 0.0f);
    return g;
}

bool sphereScreenRect(const glm::vec3& c, float r, const glm::mat4& p, int width, int height,
                      glm::ivec4& rect) {
    float zNear = c.z + r, zFar = c.z - r; // view space looks down -Z: near is the larger z
    if (p[2][3] != 0.0f) {
        // Perspective (glm's): near n = P32 / (P22 - 1), far f = P32 / (P22 + 1).
        const float n = p[3][2] / (p[2][2] - 1.0f), f = p[3][2] / (p[2][2] + 1.0f);
        zNear = std::min(zNear, -n);
        zFar = std::max(zFar, -f);
        if (!(zFar <= zNear)) return false;
    }
    glm::vec2 lo(INFINITY), hi(-INFINITY);
    for (int k = 0; k < 8; ++k) {
        const glm::vec4 corner(c.x + ((k & 1) ? r : -r), c.y + ((k & 2) ? r : -r), (k & 4) ? zNear : zFar,
                               1.0f);
        const glm::vec4 clip = p * corner;
        const glm::vec2 ndc = glm::vec2(clip) / clip.w;
        lo = glm::min(lo, ndc);
        hi = glm::max(hi, ndc);
    }
    const glm::vec2 size{float(width), float(height)};
    const glm::vec2 a = (lo * 0.5f + 0.5f) * size - 1.0f, b = (hi * 0.5f + 0.5f) * size + 1.0f;
    if (!(b.x >= 0.0f && b.y >= 0.0f && a.x < size.x && a.y < size.y)) return false; // NaN: out too
    rect = glm::ivec4(int(std::max(a.x, 0.0f)), int(std::max(a.y, 0.0f)), int(std::min(b.x, size.x - 1.0f)),
                      int(std::min(b.y, size.y - 1.0f)));
    return true;
}

void LightList::build(std::span<const LightInfo> all, const glm::mat4& view, const glm::mat4& projection,
                      int width, int height) {
    tilesX = (width + kTileSize - 1) / kTileSize;
    tilesY = (height + kTileSize - 1) / kTileSize;
    lights.clear();
    rects_.clear();
    for (std::size_t i = 0; i < all.size(); ++i)
        if (!(all[i].range > 0.0f)) lights.push_back(packLight(all[i], int(i)));
    global = int(lights.size());
    for (std::size_t i = 0; i < all.size(); ++i) {
        const LightInfo& l = all[i];
        glm::ivec4 px;
        if (!(l.range > 0.0f) ||
            !sphereScreenRect(glm::vec3(view * l.vector), l.range, projection, width, height, px))
            continue;
        lights.push_back(packLight(l, int(i)));
        rects_.push_back(px / kTileSize);
    }
    // Counts, then each tile's start, then the lists.
    const std::size_t tileCount = std::size_t(tilesX) * std::size_t(tilesY);
    tiles.assign(2 * tileCount, 0u);
    for (const glm::ivec4& t : rects_)
        for (int y = t.y; y <= t.w; ++y)
            for (int x = t.x; x <= t.z; ++x)
                ++tiles[2 * (std::size_t(y) * std::size_t(tilesX) + std::size_t(x)) + 1];
    std::uint32_t next = std::uint32_t(2 * tileCount);
    for (std::size_t t = 0; t < tileCount; ++t) {
        tiles[2 * t] = next;
        next += tiles[2 * t + 1];
        tiles[2 * t + 1] = 0;
    }
    tiles.resize(next);
    for (std::size_t i = 0; i < rects_.size(); ++i) {
        const glm::ivec4& t = rects_[i];
        for (int y = t.y; y <= t.w; ++y)
            for (int x = t.x; x <= t.z; ++x) {
                const std::size_t tile = std::size_t(y) * std::size_t(tilesX) + std::size_t(x);
                tiles[tiles[2 * tile] + tiles[2 * tile + 1]++] = std::uint32_t(global) + std::uint32_t(i);
            }
    }
}

} // namespace sgfx::render

// Conservative occlusion culling's CPU half: depth pyramid, screen rectangles, the test.
#include "render/Occlusion.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>

namespace sgfx::render {

void DepthPyramid::build(std::span<const float> depth, int width, int height) {
    if (width <= 0 || height <= 0 || depth.size() != std::size_t(width) * std::size_t(height))
        throw std::invalid_argument("sgfx: DepthPyramid::build: " + std::to_string(depth.size()) +
                                    " depths for " + std::to_string(width) + " x " + std::to_string(height));
    levels_.resize(1);
    levels_[0].width = width;
    levels_[0].height = height;
    levels_[0].depth.assign(depth.begin(), depth.end());
    for (std::size_t k = 1; levels_[k - 1].width > 1 || levels_[k - 1].height > 1; ++k) {
        levels_.resize(k + 1);
        const Level& src = levels_[k - 1];
        Level& dst = levels_[k];
        dst.width = (src.width + 1) / 2;
        dst.height = (src.height + 1) / 2;
        dst.depth.resize(std::size_t(dst.width) * std::size_t(dst.height));
        for (int y = 0; y < dst.height; ++y) {
            const float* r0 = &src.depth[std::size_t(2 * y) * std::size_t(src.width)];
            const float* r1 = 2 * y + 1 < src.height ? r0 + src.width : r0; // odd heights: repeat
            float* out = &dst.depth[std::size_t(y) * std::size_t(dst.width)];
            for (int x = 0; x < dst.width; ++x) {
                const int x1 = std::min(2 * x + 1, src.width - 1);
                out[x] = std::max(std::max(r0[2 * x], r0[x1]), std::max(r1[2 * x], r1[x1]));
            }
        }
    }
}

float DepthPyramid::maxOver(int x0, int y0, int x1, int y1) const {
    int k = 0;
    while ((x1 >> k) - (x0 >> k) > 1 || (y1 >> k) - (y0 >> k) > 1)
        ++k;
    float m = 0.0f;
    for (int y = y0 >> k; y <= y1 >> k; ++y)
        for (int x = x0 >> k; x <= x1 >> k; ++x)
            m = std::max(m, at(k, x, y));
    return m;
}

ScreenRect screenRect(const glm::mat4& viewProjection, const BoundingSphere& world, int width, int height) {
    ScreenRect r;
    if (!world.valid() || !(world.radius < 1e30f)) return r;
    glm::vec2 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
    float nearDepth = 1.0f;
    for (int i = 0; i < 8; ++i) {
        const glm::vec3 sign((i & 1) ? 1.0f : -1.0f, (i & 2) ? 1.0f : -1.0f, (i & 4) ? 1.0f : -1.0f);
        const glm::vec4 clip = viewProjection * glm::vec4(world.center + sign * world.radius, 1.0f);
        // Behind (or on) the near plane: the projection folds over, so the bound may cover anything.
        if (!(clip.w > 0.0f) || !(clip.z >= -clip.w)) return r;
        const glm::vec3 ndc = glm::vec3(clip) / clip.w;
        const glm::vec2 px((ndc.x * 0.5f + 0.5f) * float(width), (ndc.y * 0.5f + 0.5f) * float(height));
        lo = glm::min(lo, px);
        hi = glm::max(hi, px);
        nearDepth = std::min(nearDepth, ndc.z * 0.5f + 0.5f);
    }
    if (!(lo.x < float(width) + 1.0f && lo.y < float(height) + 1.0f && hi.x > -1.0f && hi.y > -1.0f))
        return r; // off screen (the frustum cull kept it): left alone
    r.x0 = std::max(0, int(std::floor(lo.x)) - 1);
    r.y0 = std::max(0, int(std::floor(lo.y)) - 1);
    r.x1 = std::min(width - 1, int(std::floor(hi.x)) + 1);
    r.y1 = std::min(height - 1, int(std::floor(hi.y)) + 1);
    r.nearDepth = nearDepth;
    r.mayBeVisible = false;
    return r;
}

bool occluded(const DepthPyramid& pyramid, const ScreenRect& rect, std::span<const float> level0,
              bool unsafeMinDepth) {
    if (rect.mayBeVisible || pyramid.levels() == 0) return false;
    if (unsafeMinDepth) {
        float m = 1.0f;
        const int w = pyramid.width(0);
        for (int y = rect.y0; y <= rect.y1; ++y)
            for (int x = rect.x0; x <= rect.x1; ++x)
                m = std::min(m, level0[std::size_t(y) * std::size_t(w) + std::size_t(x)]);
        return rect.nearDepth > m + kOcclusionDepthMargin;
    }
    return rect.nearDepth > pyramid.maxOver(rect.x0, rect.y0, rect.x1, rect.y1) + kOcclusionDepthMargin;
}

std::uint64_t occlusionKey(const RenderItem& item) {
    // The node's address, the matrix and the faces mixed 64 bits at a time (splitmix64's
    // finaliser, Steele et al. 2014): a collision only changes which items are drawn first,
    // never what is culled.
    const auto mix = [](std::uint64_t h, std::uint64_t v) {
        h ^= v + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2);
        h = (h ^ (h >> 30)) * 0xbf58476d1ce4e5b9ull;
        return (h ^ (h >> 27)) * 0x94d049bb133111ebull;
    };
    const void* node = item.drawable ? static_cast<const void*>(item.drawable) : item.geometry;
    std::uint64_t h = mix(0, std::uint64_t(reinterpret_cast<std::uintptr_t>(node)));
    std::uint64_t words[8];
    static_assert(sizeof words == sizeof item.model);
    std::memcpy(words, &item.model, sizeof words);
    for (const std::uint64_t w : words)
        h = mix(h, w);
    return mix(h, std::uint64_t(item.faces));
}

} // namespace sgfx::render

namespace sgfx::render {

bool depthIsMonotone(std::span<const RenderItem> opaque) {
    return std::all_of(opaque.begin(), opaque.end(), [](const RenderItem& it) {
        const DepthState d = it.state ? it.state->depth.value.value_or(DepthState{}) : DepthState{};
        return !d.write || (d.test && (d.func == CompareFunc::Less || d.func == CompareFunc::LessEqual ||
                                       d.func == CompareFunc::Equal || d.func == CompareFunc::Never));
    });
}

bool occlusionCandidate(const RenderItem& item) {
    if (!item.geometry || item.drawable) return false;
    const DepthState d = item.state ? item.state->depth.value.value_or(DepthState{}) : DepthState{};
    return d.test && (d.func == CompareFunc::Less || d.func == CompareFunc::LessEqual);
}

} // namespace sgfx::render

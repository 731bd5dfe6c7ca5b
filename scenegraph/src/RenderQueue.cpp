#include "sgfx/RenderQueue.h"

#include "sgfx/Drawable.h"
#include "sgfx/Geometry.h"

#include "sgfx/Effect.h"

#include <algorithm>
#include <bit>
#include <utility>

namespace sgfx {

const ShaderProgram* RenderItem::program() const {
    // A drawable brings its own base shader; a StateSet's program applies to geometry only.
    return !drawable && state && state->program.value ? state->program.value->get() : nullptr;
}

BoundingSphere RenderItem::worldBound() const {
    return drawable ? drawable->worldBound(model) : geometry->bound().transformed(model);
}

const Node& RenderItem::node() const {
    if (drawable) return *drawable;
    return *geometry;
}

void RenderQueue::clear() {
    opaque.clear();
    transparent.clear();
    claimed.clear();
    effectSets.resize(1);
    lights.clear();
    ambientLight = glm::vec3(0.0f);
    states.clear();
    subCameras.clear();
}

std::uint32_t RenderQueue::internEffectSet(std::vector<const EffectNode*> effects) {
    for (std::uint32_t i = 0; i < effectSets.size(); ++i)
        if (effectSets[i].effects == effects) return i;
    std::string sig;
    for (const EffectNode* e : effects)
        sig += e->snippet().name + '\n';
    auto it = std::find(signatures_.begin(), signatures_.end(), sig);
    const auto sigId = std::uint32_t(it - signatures_.begin());
    if (it == signatures_.end()) signatures_.push_back(std::move(sig));
    effectSets.push_back({std::move(effects), sigId});
    return std::uint32_t(effectSets.size() - 1);
}

void RenderQueue::sort() {
    // Opaque: near to far by octave of distance (software rasterizers pay for every covered
    // fragment, GPUs for every one that passes), then fewest program and material switches
    // within an octave, then front to back.
    std::sort(opaque.begin(), opaque.end(), [](const RenderItem& a, const RenderItem& b) {
        if (a.depthBucket != b.depthBucket) return a.depthBucket < b.depthBucket;
        if (a.programKey != b.programKey) return a.programKey < b.programKey;
        const Material* ma = a.state->material.value ? a.state->material.value->get() : nullptr;
        const Material* mb = b.state->material.value ? b.state->material.value->get() : nullptr;
        if (ma != mb) return ma < mb;
        if (a.depth != b.depth) return a.depth < b.depth;
        return a.sequence < b.sequence;
    });
    // Transparent: explicit order first, then back to front; equal depths keep cull order (a
    // total order, so nothing flickers and the two faces of a double-sided item stay together).
    // Items are large (a matrix each) and arrive in cull order: a stable LSD radix sort of
    // (order, depth) keys, then each item moved once.
    const std::size_t n = transparent.size();
    sortKeys_.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        const RenderItem& it = transparent[i];
        std::uint32_t d = std::bit_cast<std::uint32_t>(it.depth + 0.0f); // -0 sorts as +0
        d ^= (d & 0x80000000u) ? 0xffffffffu : 0x80000000u;              // monotone in depth
        sortKeys_[i] = {(std::uint64_t(std::uint32_t(it.order) ^ 0x80000000u) << 32) | ~d, std::uint32_t(i)};
    }
    constexpr int kBits = 11;
    constexpr std::uint32_t kMask = (1u << kBits) - 1;
    sortScratchKeys_.resize(n);
    for (int shift = 0; shift < 64; shift += kBits) {
        std::uint32_t count[1u << kBits] = {};
        for (const SortKey& k : sortKeys_)
            ++count[(k.primary >> shift) & kMask];
        if (count[(sortKeys_.empty() ? 0 : sortKeys_[0].primary >> shift) & kMask] == n)
            continue; // one digit
        std::uint32_t sum = 0;
        for (std::uint32_t& c : count)
            sum += std::exchange(c, sum);
        for (const SortKey& k : sortKeys_)
            sortScratchKeys_[count[(k.primary >> shift) & kMask]++] = k;
        sortKeys_.swap(sortScratchKeys_);
    }
    sortScratch_.clear();
    sortScratch_.reserve(n);
    for (const SortKey& k : sortKeys_)
        sortScratch_.push_back(transparent[k.index]);
    transparent.swap(sortScratch_);
}

} // namespace sgfx

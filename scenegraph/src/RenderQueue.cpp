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
    transmissive.clear();
    transparent.clear();
    claimed.clear();
    effectSets.resize(1);
    lights.clear();
    ambientLight = glm::vec3(0.0f);
    states.clear();
    stateIndex_.clear();
    subCameras.clear();
    programKeys.clear();
}

const ResolvedState* RenderQueue::internState(ResolvedState&& state) {
    // A cheap hash of what usually differs; equality decides.
    auto mix = [](std::size_t h, std::size_t v) { return (h ^ v) * 0x100000001b3ull; };
    std::size_t h = 0xcbf29ce484222325ull;
    h = mix(h, std::hash<const void*>{}(state.material.value ? state.material.value->get() : nullptr));
    h = mix(h, std::hash<const void*>{}(state.program.value ? state.program.value->get() : nullptr));
    h = mix(h, std::size_t(state.blend.value.value_or(BlendMode(255))));
    h = mix(h, std::size_t(state.cullFace.value.value_or(CullFace(255))));
    h = mix(h, state.uniforms.size() * 131 + state.textures.size());
    const auto [first, last] = stateIndex_.equal_range(h);
    for (auto it = first; it != last; ++it)
        if (*it->second == state) return it->second;
    const ResolvedState* kept = &states.emplace_back(std::move(state));
    stateIndex_.emplace(h, kept);
    return kept;
}

std::uint32_t RenderQueue::internEffectSet(std::vector<const EffectNode*> effects) {
    for (std::uint32_t i = 0; i < effectSets.size(); ++i)
        if (effectSets[i].effects == effects) return i;
    std::string sig;
    for (const EffectNode* e : effects)
        sig += e->snippet().name + '\n';
    const std::uint32_t sigId = programKeys.effects(sig);
    effectSets.push_back({std::move(effects), sigId});
    return std::uint32_t(effectSets.size() - 1);
}

void RenderQueue::radixSort(std::vector<SortKey>& keys) {
    // Stable LSD radix sort on the 64-bit primary key, 11 bits a pass; passes whose digit is the
    // same for every key are skipped.
    constexpr int kBits = 11;
    constexpr std::uint32_t kMask = (1u << kBits) - 1;
    const std::size_t n = keys.size();
    sortScratchKeys_.resize(n);
    for (int shift = 0; shift < 64; shift += kBits) {
        std::uint32_t count[1u << kBits] = {};
        for (const SortKey& k : keys)
            ++count[(k.primary >> shift) & kMask];
        if (n == 0 || count[(keys[0].primary >> shift) & kMask] == n) continue; // one digit
        std::uint32_t sum = 0;
        for (std::uint32_t& c : count)
            sum += std::exchange(c, sum);
        for (const SortKey& k : keys)
            sortScratchKeys_[count[(k.primary >> shift) & kMask]++] = k;
        keys.swap(sortScratchKeys_);
    }
}

void RenderQueue::sort() {
    // Opaque: near to far by octave of distance (software rasterizers pay for every covered
    // fragment, GPUs for every one that passes), then fewest program and material switches
    // within an octave, then the same mesh together (so repeated meshes follow each other and
    // the renderer can draw them as one instanced batch), then front to back.
    // Items are 128 bytes and arrive in cull order (sequence order): rank the programs,
    // materials and meshes, pack (bucket, program rank, material rank, mesh rank, depth) into
    // one 64-bit key and radix sort it stably (ties keep cull order), then move each item once.
    // Depth keeps its top 20 bits (1/2048 relative) to make room for the mesh. Over 4096
    // distinct programs or materials in a view, fall back to comparing items; over 4096
    // distinct meshes, meshes are not grouped (both paths alike).
    const std::size_t no = opaque.size();
    auto materialOf = [](const RenderItem& it) {
        return reinterpret_cast<std::uintptr_t>(it.state->material.value ? it.state->material.value->get()
                                                                         : nullptr);
    };
    // Mirrored copies of a mesh group apart from the plain ones (the other winding is another
    // batch): the flag takes the pointer's low bit, free by alignment.
    auto meshOf = [](const RenderItem& it) {
        return (it.geometry ? reinterpret_cast<std::uintptr_t>(it.geometry)
                            : reinterpret_cast<std::uintptr_t>(it.drawable)) |
               std::uintptr_t(it.mirrored);
    };
    auto depthKey = [](float depth) {
        std::uint32_t d = std::bit_cast<std::uint32_t>(depth + 0.0f); // -0 sorts as +0
        d ^= (d & 0x80000000u) ? 0xffffffffu : 0x80000000u;           // monotone in depth
        return d >> 12;
    };
    // Rank = position among the distinct values, so ranks order as the values do. Neighbours in
    // cull order mostly share them: look up only where the value changes.
    auto ranks = [no, &distinct = rankScratch_](auto value, std::vector<std::uint64_t>& ids) {
        ids.resize(no);
        distinct.clear();
        for (std::size_t i = 0; i < no; ++i) {
            ids[i] = value(i);
            if (i == 0 || ids[i] != ids[i - 1]) distinct.push_back(ids[i]);
        }
        std::sort(distinct.begin(), distinct.end());
        distinct.erase(std::unique(distinct.begin(), distinct.end()), distinct.end());
        if (distinct.size() > 4096) return false;
        std::uint64_t previous = 0, rank = 0;
        for (std::size_t i = 0; i < no; ++i) {
            if (i == 0 || ids[i] != previous) {
                previous = ids[i];
                rank = std::uint64_t(std::lower_bound(distinct.begin(), distinct.end(), previous) -
                                     distinct.begin());
            }
            ids[i] = rank;
        }
        return true;
    };
    // Meshes that occur more than once get ranks 1..n; one-off meshes share rank 0 and stay
    // front to back among themselves.
    bool groupMeshes = ranks([&](std::size_t i) { return std::uint64_t(meshOf(opaque[i])); }, meshRanks_) &&
                       rankScratch_.size() < 4096;
    if (groupMeshes) {
        meshCounts_.assign(rankScratch_.size(), 0);
        for (std::size_t i = 0; i < no; ++i)
            ++meshCounts_[meshRanks_[i]];
        for (std::size_t i = 0; i < no; ++i)
            meshRanks_[i] = meshCounts_[meshRanks_[i]] > 1 ? meshRanks_[i] + 1 : 0;
    }
    const bool packed =
        ranks([&](std::size_t i) { return opaque[i].programKey.bits(); }, programRanks_) &&
        ranks([&](std::size_t i) { return std::uint64_t(materialOf(opaque[i])); }, materialRanks_);
    sortKeys_.resize(no);
    for (std::size_t i = 0; i < no; ++i) {
        const RenderItem& it = opaque[i];
        const std::uint64_t high = packed ? (std::uint64_t(std::uint8_t(it.depthBucket ^ 0x80)) << 24) |
                                                (programRanks_[i] << 12) | materialRanks_[i]
                                          : 0;
        const std::uint64_t low = ((groupMeshes ? meshRanks_[i] : 0u) << 20) | depthKey(it.depth);
        sortKeys_[i] = {(high << 32) | low, std::uint32_t(i)};
    }
    if (packed) {
        radixSort(sortKeys_);
    } else {
        // The same order, comparing the fields the packed key could not hold.
        std::sort(sortKeys_.begin(), sortKeys_.end(), [&](const SortKey& ka, const SortKey& kb) {
            const RenderItem &a = opaque[ka.index], &b = opaque[kb.index];
            if (a.depthBucket != b.depthBucket) return a.depthBucket < b.depthBucket;
            if (a.programKey != b.programKey) return a.programKey < b.programKey;
            if (materialOf(a) != materialOf(b)) return materialOf(a) < materialOf(b);
            if (ka.primary != kb.primary) return ka.primary < kb.primary; // mesh rank, depth
            return a.sequence < b.sequence;
        });
    }
    sortScratch_.clear();
    sortScratch_.reserve(no);
    for (const SortKey& k : sortKeys_)
        sortScratch_.push_back(opaque[k.index]);
    opaque.swap(sortScratch_);
    sortBackToFront(transmissive);
    sortBackToFront(transparent);
}

// Transparent and transmissive: explicit order first, then back to front; equal depths keep cull
// order (a total order, so nothing flickers and the two faces of a double-sided item stay
// together). Items are large (a matrix each) and arrive in cull order: a stable LSD radix sort
// of (order, depth) keys, then each item moved once.
void RenderQueue::sortBackToFront(std::vector<RenderItem>& items) {
    const std::size_t n = items.size();
    sortKeys_.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        const RenderItem& it = items[i];
        std::uint32_t d = std::bit_cast<std::uint32_t>(it.depth + 0.0f); // -0 sorts as +0
        d ^= (d & 0x80000000u) ? 0xffffffffu : 0x80000000u;              // monotone in depth
        sortKeys_[i] = {(std::uint64_t(std::uint32_t(it.order) ^ 0x80000000u) << 32) | ~d, std::uint32_t(i)};
    }
    radixSort(sortKeys_);
    sortScratch_.clear();
    sortScratch_.reserve(n);
    for (const SortKey& k : sortKeys_)
        sortScratch_.push_back(items[k.index]);
    items.swap(sortScratch_);
}

} // namespace sgfx

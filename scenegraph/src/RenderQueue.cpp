#include "sgfx/RenderQueue.h"

#include "sgfx/Effect.h"

#include <algorithm>

namespace sgfx {

const ShaderProgram* RenderItem::program() const {
    return state && state->program.value ? state->program.value->get() : nullptr;
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
    std::sort(transparent.begin(), transparent.end(), [](const RenderItem& a, const RenderItem& b) {
        if (a.order != b.order) return a.order < b.order;
        if (a.depth != b.depth) return a.depth > b.depth;
        return a.sequence < b.sequence;
    });
}

} // namespace sgfx

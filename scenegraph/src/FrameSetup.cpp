#include "sgfx/FrameSetup.h"

#include "sgfx/CullVisitor.h"
#include "sgfx/Effect.h"
#include "sgfx/Renderer.h"

#include <algorithm>
#include <cmath>

#include <stdexcept>
#include <string>

namespace sgfx {

std::string_view phaseName(PassPhase phase) {
    switch (phase) {
    case PassPhase::Compute:
        return "compute";
    case PassPhase::BeforeMain:
        return "before main";
    case PassPhase::AfterOpaque:
        return "after opaque";
    case PassPhase::Transparent:
        return "transparent";
    case PassPhase::AfterResolve:
        return "after resolve";
    }
    return "?";
}

void FrameSetup::cullForLight(const EffectNode& effect, const LightCull& light, RenderQueue& into) const {
    if (!plan_) throw std::logic_error("sgfx: FrameSetup::cullForLight needs the view's frame plan");
    CullVisitor visitor(CullView{light.view, light.projection, view_.viewSize.y, true}, into);
    visitor.traversalMask = light.traversalMask;
    visitor.setReferenceView(view_.view, view_.projection, view_.viewSize.y);
    for (const FramePlan::Place& place : plan_->places)
        if (place.node == &effect)
            // The cull reads the scene; the node is the application's, reached through the plan.
            visitor.runFrom(const_cast<EffectNode&>(effect), place.model, *place.state);
    into.sort();
}

BoundingSphere FrameSetup::worldBound(const EffectNode& effect) const {
    BoundingSphere b;
    if (plan_)
        for (const FramePlan::Place& place : plan_->places)
            if (place.node == &effect) b.expandBy(effect.bound().transformed(place.model));
    return b;
}

const RenderQueue& PassBuilder::queue() const {
    if (!queue_) throw std::logic_error("sgfx: this PassBuilder has no render queue");
    return *queue_;
}

void PassBuilder::sampleMaterials(std::span<const RenderItem> items) {
    const RenderQueue& q = queue();
    std::vector<bool> used(q.effectSets.size(), false);
    for (const RenderItem& item : items)
        used[item.effectSet] = true;
    std::vector<std::pair<std::string_view, std::string_view>> done;
    for (std::size_t i = 0; i < used.size(); ++i) {
        if (!used[i]) continue;
        for (const EffectNode* e : q.effectSets[i].effects)
            for (const SnippetSampler& s : e->snippet().samplers) {
                if (s.nodeTexture) continue; // the node's own, not the frame graph's
                const std::pair<std::string_view, std::string_view> key(s.uniform, s.resource);
                if (std::find(done.begin(), done.end(), key) != done.end()) continue;
                if (!board_.has(s.resource))
                    throw std::logic_error("sgfx: effect '" + std::string(e->kind()) + "' samples '" +
                                           s.resource + "', which no pass of the frame makes");
                done.push_back(key);
                b_.sample(board_.get(s.resource), s.uniform);
            }
    }
}

ResourceId PassBuilder::write(std::string_view name, bool keep) {
    const ResourceId old = board_.get(name);
    const bool depth = name == resources::DrawDepth || name == resources::ViewDepth;
    const ResourceId next = depth ? b_.depth(old, keep) : b_.colour(old, 0, keep);
    // Without multisampling or supersampling the draw and view surfaces are one resource under
    // two names: both follow the write.
    std::vector<std::string> same;
    for (const auto& [n, id] : board_.entries())
        if (id == old) same.push_back(n);
    for (std::string& n : same)
        board_.put(std::move(n), next);
    return next;
}

void FrameSetup::requestSceneDepth(const SceneDepthRequest& r) {
    if (r.when != PassPhase::BeforeMain && r.when != PassPhase::AfterOpaque)
        throw std::invalid_argument("sgfx: the scene depth is made before the main pass or after its opaque "
                                    "items; a request for phase '" +
                                    std::string(phaseName(r.when)) + "' cannot be served");
    depth_.any = true;
    depth_.beforeMain = depth_.beforeMain || r.when == PassPhase::BeforeMain || r.normals || r.linearDepth ||
                        r.positions; // G-buffer outputs only come from the pre-pass
    depth_.normals = depth_.normals || r.normals;
    depth_.linearDepth = depth_.linearDepth || r.linearDepth;
    depth_.positions = depth_.positions || r.positions;
}

void FrameSetup::offscreenTargetInMainPass(std::string name, const TextureDesc& desc) {
    for (const auto& [n, d] : mainTargets_)
        if (n == name) {
            if (d == desc) return;
            throw std::logic_error("sgfx: the main pass's offscreen target '" + name +
                                   "' is asked for twice with different descriptions");
        }
    mainTargets_.emplace_back(std::move(name), desc);
}

void FrameSetup::setClearColour(const glm::vec4& colour) {
    if (!view_.clearsColour)
        throw std::logic_error("sgfx: FrameSetup::setClearColour: this view does not clear its colour");
    for (int i = 0; i < 4; ++i)
        if (!std::isfinite(colour[i]))
            throw std::logic_error("sgfx: FrameSetup::setClearColour: the colour is not finite");
    clearColour_ = colour;
}

void FrameSetup::addPass(std::string name, PassPhase phase, Setup setup, FrameGraph::Execute execute) {
    if (std::uint8_t(phase) > std::uint8_t(PassPhase::AfterResolve))
        throw std::invalid_argument("sgfx: pass '" + name + "' has an invalid PassPhase " +
                                    std::to_string(int(phase)));
    passes_.push_back({std::move(name), phase, std::move(setup), std::move(execute)});
}

} // namespace sgfx

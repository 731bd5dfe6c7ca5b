#include "sgfx/CullVisitor.h"

#include "sgfx/Billboard.h"
#include "sgfx/Camera.h"
#include "sgfx/DatabasePager.h"
#include "sgfx/Drawable.h"
#include "sgfx/Effect.h"
#include "sgfx/Geometry.h"
#include "sgfx/Group.h"
#include "sgfx/LOD.h"
#include "sgfx/PagedLOD.h"
#include "sgfx/Renderer.h"
#include "sgfx/ShaderComposer.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>

namespace sgfx {

namespace {
constexpr std::uint8_t kAllPlanes = 0x3f;

// std::ilogb for finite or infinite x > 1 (the exponent field), without the libm call.
int exponentOf(float x) {
    return int((std::bit_cast<std::uint32_t>(x) >> 23) & 0xffu) - 127;
}
} // namespace

CullVisitor::CullVisitor(const Camera& camera, RenderQueue& queue, FramePlan* plan)
    : CullVisitor(
          CullView{camera.viewMatrix, camera.projectionMatrix, camera.viewport.height, camera.cullingEnabled},
          queue, plan) {}

CullVisitor::CullVisitor(const CullView& view, RenderQueue& queue, FramePlan* plan)
    : NodeVisitor(Mode::ActiveChildren)
    , queue_(queue)
    , plan_(plan)
    , view_(view.view)
    , projection_(view.projection)
    , viewportHeight_(view.viewportHeight)
    , viewFrustum_(Frustum::fromMatrix(view.projection))
    , culling_(view.culling) {
    modelView_.push_back(view_);
    scale_.push_back(maxAxisScale(view_));
    similar_.push_back(isSimilarity(view_));
    model_.push_back(glm::mat4(1.0f));
    queue_.states.push_back(ResolvedState::defaults());
    state_.push_back(&queue_.states.back());
    effectSet_.push_back(0);
    planeMask_.push_back(culling_ ? kAllPlanes : 0);
}

void CullVisitor::run(Camera& camera) {
    pushState(camera);
    traverse(camera);
    popState(camera);
}

void CullVisitor::runFrom(Node& node, const glm::mat4& model, const ResolvedState& state) {
    enterFrame(model, maxAxisScale(model), isSimilarity(model));
    state_.push_back(&state);
    if (accepts(node) && cullTest(node)) {
        traverseWithState(node);
        planeMask_.pop_back();
    }
    state_.pop_back();
    leaveFrame();
}

void CullVisitor::setReferenceView(const glm::mat4& view, const glm::mat4& projection, int viewportHeight) {
    hasReference_ = true;
    referenceView_ = view;
    referenceProjection_ = projection;
    referenceHeight_ = viewportHeight;
}

BoundingSphere CullVisitor::toView(const BoundingSphere& local) const {
    if (!local.valid()) return local;
    BoundingSphere out;
    out.center = glm::vec3(modelView_.back() * glm::vec4(local.center, 1.0f));
    out.radius = local.radius * scale_.back();
    return out;
}

bool CullVisitor::cullTest(const Node& n, BoundingSphere* viewBound) {
    const std::uint8_t mask = planeMask_.back();
    if (mask == 0) {
        planeMask_.push_back(0);
        return true;
    }
    if (n.cullingDisabledInSubtree()) {
        planeMask_.push_back(mask); // children are tested on their own
        return true;
    }
    const BoundingSphere& local = n.bound();
    if (!local.valid()) {
        ++culledNodes;
        return false;
    }
    const BoundingSphere s = toView(local);
    if (viewBound) *viewBound = s;
    std::uint8_t out = mask;
    for (int i = 0; i < 6; ++i) {
        if (!(mask & (1u << i))) continue;
        const float d = viewFrustum_.planes[std::size_t(i)].distance(s.center);
        if (d < -s.radius) {
            ++culledNodes;
            return false;
        }
        if (d >= s.radius) out &= std::uint8_t(~(1u << i)); // wholly inside this plane
    }
    planeMask_.push_back(out);
    return true;
}

// A restricting effect (EffectNode::subtreeMask) whose mask shares no bit with the node's mask
// leaves the node's subtree: the rest of the set is interned as the subtree's effects.
void CullVisitor::dropRestrictedEffects(const Node& n) {
    const auto dropped = [&](const Restriction& r) { return (n.nodeMask & r.mask) == 0; };
    if (std::none_of(restricting_.begin(), restricting_.end(), dropped)) return;
    drops_.push_back({&n, restricting_});
    std::vector<const EffectNode*> set;
    for (const EffectNode* e : queue_.effectSets[effectSet_.back()].effects)
        if (std::none_of(restricting_.begin(), restricting_.end(),
                         [&](const Restriction& r) { return r.effect == e && dropped(r); }))
            set.push_back(e);
    std::erase_if(restricting_, dropped);
    effectSet_.push_back(queue_.internEffectSet(std::move(set)));
}

void CullVisitor::pushState(const Node& n) {
    if (!restricting_.empty()) dropRestrictedEffects(n);
    const StateSet* set = n.stateSet().get();
    if (!set) return;
    const ResolvedState* inherited = state_.back();
    const auto key = (reinterpret_cast<std::uintptr_t>(inherited) >> 4) * 31u +
                     (reinterpret_cast<std::uintptr_t>(set) >> 4);
    MergedState& slot = mergedStates_[key % mergedStates_.size()];
    if (slot.inherited != inherited || slot.set != set) {
        slot = {inherited, set, queue_.internState(inherited->merged(*set))};
    }
    state_.push_back(slot.merged);
}

void CullVisitor::popState(const Node& n) {
    if (n.stateSet()) state_.pop_back();
    if (!drops_.empty() && drops_.back().node == &n) {
        restricting_ = std::move(drops_.back().restricting);
        drops_.pop_back();
        effectSet_.pop_back();
    }
}

void CullVisitor::traverseWithState(Node& n) {
    pushState(n);
    traverse(n);
    popState(n);
}

void CullVisitor::apply(Node& node) {
    if (!cullTest(node)) return;
    traverseWithState(node);
    planeMask_.pop_back();
}

void CullVisitor::enterFrame(const glm::mat4& local, float localScale, bool localSimilar) {
    model_.push_back(model_.back() * local);
    modelView_.push_back(view_ * model_.back());
    // Under a rotation-and-uniform-scale chain the scale multiplies: no square root per node.
    const bool similar = similar_.back();
    scale_.push_back(similar ? scale_.back() * localScale : maxAxisScale(modelView_.back()));
    similar_.push_back(similar && localSimilar);
}

void CullVisitor::leaveFrame() {
    similar_.pop_back();
    scale_.pop_back();
    modelView_.pop_back();
    model_.pop_back();
}

void CullVisitor::apply(Transform& t) {
    if (!cullTest(t)) return;
    enterFrame(t.matrix(), t.maxScale(), t.similarity());
    traverseWithState(t);
    leaveFrame();
    planeMask_.pop_back();
}

void CullVisitor::apply(Billboard& b) {
    if (!cullTest(b)) return;
    // The eye and the view's up in the billboard's frame; the turn is a rotation.
    const glm::mat4 toLocal =
        glm::inverse(hasReference_ ? referenceView_ * model_.back() : modelView_.back());
    enterFrame(b.orientation(glm::vec3(toLocal[3]), glm::vec3(toLocal[1])), 1.0f, true);
    traverseWithState(b);
    leaveFrame();
    planeMask_.pop_back();
}

float CullVisitor::lodMeasure(const LOD& lod) const {
    const BoundingSphere local = lod.selectionSphere();
    if (!local.valid()) return 0.0f;
    // Measured in the reference view when there is one (a cull from a light).
    const glm::mat4& viewOf = hasReference_ ? referenceView_ : view_;
    if (lod.rangeMode() == LOD::RangeMode::DistanceFromEye) {
        // The eye in the LOD's frame, as OSG measures: ranges scale with the LOD's transforms.
        const glm::vec3 eye(glm::inverse(viewOf * model_.back())[3]);
        return glm::length(eye - local.center);
    }
    const BoundingSphere s =
        hasReference_ ? local.transformed(referenceView_ * model_.back()) : toView(local);
    return hasReference_ ? pixelSize(s.center, s.radius, referenceProjection_, referenceHeight_)
                         : pixelSize(s.center, s.radius, projection_, viewportHeight_);
}

void CullVisitor::visitLodChildren(LOD& lod, const std::vector<std::size_t>& which) {
    if (mode == Mode::None) return;
    pushState(lod);
    nodePath.push_back(&lod);
    for (std::size_t i : which) {
        Node& child = *lod.child(i);
        if (accepts(child)) child.accept(*this);
    }
    nodePath.pop_back();
    popState(lod);
}

void CullVisitor::apply(LOD& lod) {
    if (!cullTest(lod)) return;
    const float measure = lodMeasure(lod);
    if (mode != Mode::None) { // no list of chosen children: LODs are common
        pushState(lod);
        nodePath.push_back(&lod);
        for (std::size_t i = 0; i < lod.numChildren(); ++i) {
            Node& child = *lod.child(i);
            if (lod.range(i).contains(measure) && accepts(child)) child.accept(*this);
        }
        nodePath.pop_back();
        popState(lod);
    }
    planeMask_.pop_back();
}

void CullVisitor::apply(PagedLOD& lod) {
    if (!cullTest(lod)) return;
    const float measure = lodMeasure(lod);
    std::vector<std::size_t> which;
    for (std::size_t i = 0; i < lod.numChildren(); ++i) {
        if (!lod.range(i).contains(measure)) continue;
        std::size_t shown = i;
        if (!lod.loaded(i)) {
            if (pager_) pager_->request(lod, i); // queued only: the load runs on the pager's thread
            shown = lod.coarserLoaded(i);
            if (shown == PagedLOD::npos) continue;
        }
        if (std::find(which.begin(), which.end(), shown) == which.end()) which.push_back(shown);
    }
    std::sort(which.begin(), which.end());
    if (pager_)
        for (std::size_t i : which)
            pager_->markUsed(lod, i);
    visitLodChildren(lod, which);
    planeMask_.pop_back();
}

void CullVisitor::apply(Camera& c) {
    // A render-to-texture camera draws its own subgraph in its own pass; one without a target
    // is traversed as a plain group.
    if (c.renderTarget) {
        if (std::find(queue_.subCameras.begin(), queue_.subCameras.end(), &c) == queue_.subCameras.end())
            queue_.subCameras.push_back(&c);
        return;
    }
    apply(static_cast<Node&>(c));
}

void CullVisitor::apply(Light& l) {
    const glm::mat4& m = model_.back();
    const glm::vec3 color = l.color * l.intensity;
    // A light with non-finite or negative colour, or no direction, would put NaN or negative
    // light into every pixel: it is left out. Other bad values (cones, range) throw.
    auto finite3 = [](const glm::vec3& v) {
        return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
    };
    const bool finite = finite3(color) && finite3(l.direction) && finite3(l.position) &&
                        glm::all(glm::greaterThanEqual(color, glm::vec3(0.0f)));
    const bool directed = l.type == LightType::Directional || l.type == LightType::Spot;
    if (!finite || (directed && !(glm::length(l.direction) > 0.0f))) {
        ++rejectedLights;
        return;
    }
    l.validate();
    if (l.type == LightType::Ambient) {
        queue_.ambientLight += color;
        return;
    }
    if (l.type == LightType::Directional) {
        const glm::vec3 d = glm::normalize(glm::mat3(m) * l.direction);
        LightInfo info{glm::vec4(-d, 0.0f), color};
        info.source = &l;
        queue_.lights.push_back(info);
        return;
    }
    LightInfo info{glm::vec4(glm::vec3(m * glm::vec4(l.position, 1.0f)), 1.0f), color};
    info.range = l.range;
    info.source = &l;
    info.inverseSquare = l.falloff == LightFalloff::InverseSquare;
    // A light whose range sphere is outside the view lights nothing that is drawn.
    if (l.range > 0.0f) {
        const glm::vec3 c = glm::vec3(view_ * info.vector);
        for (const Plane& p : viewFrustum_.planes)
            if (p.distance(c) < -l.range) {
                ++culledNodes;
                return;
            }
    }
    if (l.type == LightType::Spot) {
        const glm::vec3 axis = glm::mat3(m) * l.direction;
        if (!(glm::length(axis) > 0.0f)) {
            ++rejectedLights;
            return;
        }
        info.spotAxis = glm::normalize(axis);
        // KHR_lights_punctual's reference code.
        const float cosInner = std::cos(l.innerConeAngle), cosOuter = std::cos(l.outerConeAngle);
        info.angleScale = 1.0f / std::max(0.001f, cosInner - cosOuter);
        info.angleOffset = -cosOuter * info.angleScale;
    }
    queue_.lights.push_back(info);
}

void CullVisitor::apply(EffectNode& e) {
    if (!e.enabled) {
        apply(static_cast<Node&>(e));
        return;
    }
    if (!cullTest(e)) return;
    // Inner effect of the same kind replaces the outer one for this subtree.
    std::vector<const EffectNode*> set;
    for (const EffectNode* a : queue_.effectSets[effectSet_.back()].effects)
        if (a->kind() != e.kind()) set.push_back(a);
    set.push_back(&e);
    std::stable_sort(set.begin(), set.end(),
                     [](const EffectNode* a, const EffectNode* b) { return a->order() < b->order(); });
    effectSet_.push_back(queue_.internEffectSet(std::move(set)));
    if (plan_ && planned_.insert(&e).second) {
        plan_->effects.push_back(&e);
    }
    if (plan_) plan_->places.push_back({&e, model_.back(), state_.back()});
    // The restrictions of the effects this node replaces end here.
    const NodeMask mask = e.subtreeMask();
    const bool restricts = mask != ~NodeMask{0} ||
                           std::any_of(restricting_.begin(), restricting_.end(),
                                       [&](const Restriction& r) { return r.effect->kind() == e.kind(); });
    std::vector<Restriction> outer;
    if (restricts) {
        outer = restricting_;
        std::erase_if(restricting_, [&](const Restriction& r) { return r.effect->kind() == e.kind(); });
        if (mask != ~NodeMask{0}) restricting_.push_back({&e, mask});
    }
    traverseWithState(e);
    if (restricts) restricting_ = std::move(outer);
    effectSet_.pop_back();
    planeMask_.pop_back();
}

void CullVisitor::apply(Geometry& g) {
    BoundingSphere viewBound;
    if (!cullTest(g, &viewBound)) return;
    planeMask_.pop_back();
    if (g.positions.empty()) return;
    pushState(g);
    const ResolvedState* state = state_.back();
    const ShaderProgram* foreign = state->program.value ? state->program.value->get() : nullptr;
    // The features follow from (state, geometry) alone: instanced leaves ask for the same pair.
    if (state != featuresState_ || &g != featuresGeometry_) {
        const bool transparent = state->transparent();
        features_ = foreign
                        ? ShaderComposer::blendFeatures(transparent, state->blendMode()) |
                              (transparent ? FeatureMask(FeatureBlend) : 0u) | ShaderComposer::poseFeatures(g)
                        : ShaderComposer::featuresFor(state->materialOrNull().get(), g, transparent,
                                                      state->blendMode());
        foreignBase_ = queue_.programKeys.base(foreign);
        featuresState_ = state;
        featuresGeometry_ = &g;
    }
    const bool triangles = g.mode == PrimitiveMode::Triangles || g.mode == PrimitiveMode::TriangleStrip ||
                           g.mode == PrimitiveMode::TriangleFan;
    queueItem(&g, nullptr, features_, *state, viewBound.valid() ? viewBound : toView(g.bound()),
              foreign ? ProgramSource::Foreign : ProgramSource::Builtin, foreignBase_, triangles);
    popState(g);
}

void CullVisitor::apply(Drawable& d) {
    if (d.background()) {
        pushState(d);
        RenderItem item;
        item.drawable = &d;
        item.features = d.features(*state_.back());
        item.model = model_.back();
        item.mirrored = RenderItem::isMirroring(item.model);
        item.state = state_.back();
        item.effectSet = effectSet_.back();
        item.depth = std::numeric_limits<float>::max();
        item.depthBucket = 127; // after every other opaque item
        item.sequence = sequence_++;
        item.programKey = ProgramKey::make(ProgramSource::Drawable, queue_.programKeys.base(&d.baseShader()),
                                           queue_.effectSets[item.effectSet].signature, item.features);
        if (plan_ && plannedDrawables_.insert(&d).second) {
            plan_->drawables.push_back(&d);
        }
        queue_.opaque.push_back(item);
        popState(d);
        return;
    }
    // Its own world bound (content in world space may lie far from its parent's frame).
    const BoundingSphere world = d.worldBound(model_.back());
    if (!world.valid()) {
        ++culledNodes;
        return;
    }
    const BoundingSphere vs = world.transformed(view_);
    for (int i = 0; i < 6; ++i)
        if ((planeMask_.back() & (1u << i)) &&
            viewFrustum_.planes[std::size_t(i)].distance(vs.center) < -vs.radius) {
            ++culledNodes;
            return;
        }
    pushState(d);
    const ResolvedState* state = state_.back();
    const bool transparent = state->transparent();
    const FeatureMask features = d.features(*state) |
                                 ShaderComposer::blendFeatures(transparent, state->blendMode()) |
                                 (transparent ? FeatureMask(FeatureBlend) : 0u);
    if (plan_ && plannedDrawables_.insert(&d).second) {
        plan_->drawables.push_back(&d);
    }
    queueItem(nullptr, &d, features, *state, vs, ProgramSource::Drawable,
              queue_.programKeys.base(&d.baseShader()), false);
    popState(d);
}

void CullVisitor::queueItem(const Geometry* geometry, const Drawable* drawable, FeatureMask features,
                            const ResolvedState& state, const BoundingSphere& vs, ProgramSource source,
                            std::uint32_t base, bool twoPassable) {
    const std::uint32_t effectSet = effectSet_.back();
    const float depth = -vs.center.z;
    const std::int8_t bucket = depth > 1.0f ? std::int8_t(std::min(exponentOf(depth), 127)) : 0;
    // Equal keys mean one program: (foreign shader, drawable base or built-in variant, snippets).
    const ProgramKey programKey =
        ProgramKey::make(source, base, queue_.effectSets[effectSet].signature, features);
    computedNear = std::min(computedNear, depth - vs.radius);
    computedFar = std::max(computedFar, depth + vs.radius);
    // Opaque items are built in place, each of their 128 bytes written once (a default-
    // constructed item filled afterwards wrote them twice).
    if (!state.transparent()) {
        // Transmissive surfaces sample the opaque scene drawn before them: a stage of their own.
        (features & FeatureTransmission ? queue_.transmissive : queue_.opaque)
            .emplace_back(geometry, drawable, model_.back(), &state, effectSet, depth, bucket, sequence_++,
                          programKey, features);
        return;
    }
    RenderItem item(geometry, drawable, model_.back(), &state, effectSet, depth, bucket, sequence_++,
                    programKey, features);
    const BlendMode blend = state.blendMode();
    const auto& effects = queue_.effectSets[item.effectSet].effects;
    if (std::any_of(effects.begin(), effects.end(),
                    [&](const EffectNode* e) { return e->drawsBlended(blend); })) {
        queue_.claimed.push_back(item);
        return;
    }
    const TransparencyDetails details = state.transparency.value.value_or(TransparencyDetails{});
    details.validate();
    item.order = details.order;
    item.depth += details.depthBias;
    if (details.twoPass && twoPassable && state.cullFace.value.value_or(CullFace::Back) == CullFace::None) {
        // A closed double-sided object blends its far side first.
        item.faces = RenderItem::Faces::Back;
        queue_.transparent.push_back(item);
        item.faces = RenderItem::Faces::Front;
        item.sequence = sequence_++;
    }
    queue_.transparent.push_back(item);
}

} // namespace sgfx

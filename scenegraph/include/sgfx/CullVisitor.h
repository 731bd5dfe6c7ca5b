#pragma once
#include "sgfx/Export.h"
#include "sgfx/Math.h"
#include "sgfx/NodeVisitor.h"
#include "sgfx/RenderQueue.h"

#include <array>
#include <unordered_set>

namespace sgfx {

class Camera;
class DatabasePager;
class FramePlan;

/// What a cull sees from: world to view, the projection whose frustum culls, and the viewport
/// height LODs measure pixels in. A camera's, or a light's (FrameSetup::cullForLight).
struct SGFX_API CullView {
    glm::mat4 view{1.0f};
    glm::mat4 projection{1.0f};
    int viewportHeight = 1;
    bool culling = true; ///< false: nothing is frustum-culled
};

/// Walks the scene under a camera: frustum-culls bounding spheres, honours node masks,
/// accumulates transforms, state and active effects, and fills a RenderQueue.
class SGFX_API CullVisitor : public NodeVisitor {
public:
    CullVisitor(const Camera& camera, RenderQueue& queue, FramePlan* plan = nullptr);
    CullVisitor(const CullView& view, RenderQueue& queue, FramePlan* plan = nullptr);

    void apply(Node& node) override;
    void apply(Transform& t) override;
    /// Visits the children whose range holds the LOD's size on screen or distance from the eye.
    void apply(LOD& lod) override;
    /// As a LOD; a slot not loaded is asked of the pager (if any) and its nearest coarser loaded
    /// child drawn meanwhile.
    void apply(PagedLOD& lod) override;
    /// Turns the children towards this view's eye.
    void apply(Billboard& b) override;
    void apply(Geometry& g) override;
    void apply(Drawable& d) override;
    void apply(Camera& c) override;
    void apply(Light& l) override;
    void apply(EffectNode& e) override;

    /// Visits the camera's children.
    void run(Camera& camera);
    /// Visits `node` as if reached with world matrix `model` and inherited state `state` (a
    /// place FramePlan::places recorded in the camera's cull), e.g. from a light.
    void runFrom(Node& node, const glm::mat4& model, const ResolvedState& state);
    /// LODs measure their size, and billboards turn, in this view instead of the cull's own, so
    /// a cull from a light keeps what the camera draws (OSG ViewDependentShadowMap's reference
    /// view point).
    void setReferenceView(const glm::mat4& view, const glm::mat4& projection, int viewportHeight);
    /// Where PagedLODs ask for files and note what they draw (null: no paging; slots not loaded
    /// show their coarser level).
    void setDatabasePager(DatabasePager* pager) { pager_ = pager; }

    /// Nearest/farthest view depth of what was drawn (valid after traversal when anything was).
    float computedNear = std::numeric_limits<float>::max();
    float computedFar = 0.0f;
    std::size_t culledNodes = 0;
    std::size_t rejectedLights = 0; ///< non-finite or negative colour, zero direction

private:
    /// Returns false when the node's bound is outside the frustum; narrows the plane mask. Sets
    /// *viewBound to the view-space bound when it had to compute it (else leaves it invalid).
    bool cullTest(const Node& n, BoundingSphere* viewBound = nullptr);
    /// local.transformed(modelView_.back()), with the matrix's scale taken from scale_.
    BoundingSphere toView(const BoundingSphere& local) const;
    /// Pushes the model, modelView, radius scale and similarity of a child frame `local` (whose
    /// largest axis scale and similarity are given); leaveFrame pops them.
    void enterFrame(const glm::mat4& local, float localScale, bool localSimilar);
    void leaveFrame();
    /// What selects an LOD's children: its selection sphere's size on screen, or the distance
    /// from the eye in the LOD's frame (measured in the reference view when there is one).
    float lodMeasure(const LOD& lod) const;
    /// Visits lod's children `which` (indices, ascending) with its state.
    void visitLodChildren(LOD& lod, const std::vector<std::size_t>& which);
    void pushState(const Node& n);
    void popState(const Node& n);
    void traverseWithState(Node& n);
    /// Fills the item's common fields and puts it in the opaque, claimed or transparent list.
    /// `base` is the program source's id in the queue's programKeys (0 = built-in).
    void queueItem(const Geometry* geometry, const Drawable* drawable, FeatureMask features,
                   const ResolvedState& state, const BoundingSphere& viewBound, ProgramSource source,
                   std::uint32_t base, bool twoPassable);

    RenderQueue& queue_;
    FramePlan* plan_;
    glm::mat4 view_;
    glm::mat4 projection_;
    int viewportHeight_;
    Frustum viewFrustum_; ///< in view space
    bool culling_;
    std::vector<glm::mat4> modelView_;
    std::vector<float> scale_;          ///< largest axis scale of each modelView_ entry, computed once
    std::vector<std::uint8_t> similar_; ///< whether each modelView_ entry is a similarity
    std::vector<glm::mat4> model_;
    std::vector<const ResolvedState*> state_;
    std::vector<const EffectNode*> effects_;
    std::vector<std::uint32_t> effectSet_;
    std::vector<std::uint8_t> planeMask_;
    /// Active effects whose EffectNode::subtreeMask() is not ~0: a node sharing no bit with one
    /// drops that effect for its subtree. `drops_` remembers the nodes that dropped some.
    struct Restriction {
        const EffectNode* effect;
        NodeMask mask;
    };
    std::vector<Restriction> restricting_;
    struct Drop {
        const Node* node;
        std::vector<Restriction> restricting; ///< what was active before the node
    };
    std::vector<Drop> drops_;
    void dropRestrictedEffects(const Node& n);
    DatabasePager* pager_ = nullptr;
    bool hasReference_ = false;
    glm::mat4 referenceView_{1.0f}, referenceProjection_{1.0f};
    int referenceHeight_ = 1;
    std::unordered_set<const EffectNode*> planned_;
    std::unordered_set<const Drawable*> plannedDrawables_;
    /// This frame's merges by (inherited state, StateSet), direct-mapped: nodes that share a
    /// StateSet under the same state (instanced leaves) share one ResolvedState instead of each
    /// copying one into the queue. Stable within a cull: nothing edits StateSets during it.
    struct MergedState {
        const ResolvedState* inherited = nullptr;
        const StateSet* set = nullptr;
        const ResolvedState* merged = nullptr;
    };
    std::array<MergedState, 64> mergedStates_{};
    /// The last Geometry's material features and what they were computed from.
    const ResolvedState* featuresState_ = nullptr;
    const Geometry* featuresGeometry_ = nullptr;
    FeatureMask features_ = 0;
    std::uint32_t foreignBase_ = 0; ///< its foreign program's ProgramKey::Base id (0 = built-in)
    std::uint32_t sequence_ = 0;
};

} // namespace sgfx

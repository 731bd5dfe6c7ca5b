#pragma once
// What an effect sees while a view's frame is set up (EffectNode::setupFrame): it requests the
// scene's depth (and normals), declares passes with what they read and write, and names the
// resources its material snippet samples. Nothing here touches GL or changes a node; the
// renderer builds the view's FrameGraph from these declarations, culls what nobody reads, makes
// the textures and binds every sampler to a unit it chooses.
#include "sgfx/Export.h"
#include "sgfx/FrameGraph.h"
#include "sgfx/Math.h"

#include <glm/glm.hpp>

#include <algorithm>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <set>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace sgfx {

class RenderQueue;
struct RenderItem;
class EffectNode;
class FramePlan;
using NodeMask = std::uint32_t;

/// Where a pass runs in the view's frame. Compute and BeforeMain come before the main pass;
/// AfterOpaque between its opaque and transparent items (the background is final); Transparent
/// for passes that draw blended items themselves (RenderQueue::claimed) before the sorted
/// transparent items; AfterResolve on the view's single-sample colour, before anti-aliasing.
enum class PassPhase : std::uint8_t { Compute, BeforeMain, AfterOpaque, Transparent, AfterResolve };
SGFX_API std::string_view phaseName(PassPhase phase);

/// What an effect needs of the opaque scene's depth, and by when. Every request of a view is
/// served by one producer: a pre-pass over the opaque items when any request is BeforeMain (with
/// the G-buffer outputs when any request asks for them), else one copy of the main pass's depth
/// after the opaque items.
struct SGFX_API SceneDepthRequest {
    bool normals = false;     ///< "scene.normals": view-space normal (RGBA16F, xyz)
    bool linearDepth = false; ///< "scene.linearDepth": view-space distance along -Z (R32F)
    bool positions = false;   ///< "scene.positions": view-space position (RGBA16F)
    PassPhase when = PassPhase::BeforeMain;
};

/// Blackboard names of the resources every view has.
namespace resources {
inline constexpr std::string_view SceneDepth = "scene.depth"; ///< D32F, draw size, one sample
inline constexpr std::string_view SceneNormals = "scene.normals";
inline constexpr std::string_view SceneLinearDepth = "scene.linearDepth";
inline constexpr std::string_view ScenePositions = "scene.positions";
inline constexpr std::string_view DrawColour = "draw.colour"; ///< what the main pass draws into
inline constexpr std::string_view DrawDepth = "draw.depth";
inline constexpr std::string_view ViewColour = "view.colour"; ///< the view's single-sample target
inline constexpr std::string_view ViewDepth = "view.depth";
/// The opaque scene as the transmissive stage sees it: draw size, mip-mapped, one sample.
inline constexpr std::string_view TransmissionColour = "transmission.colour";
} // namespace resources

/// A pass's setup: FrameGraph::Builder plus the view's named resources. Writing the draw or view
/// surfaces through it keeps their current versions for the passes declared after it.
class SGFX_API PassBuilder {
public:
    PassBuilder(FrameGraph::Builder& builder, Blackboard& board, const RenderQueue* queue = nullptr)
        : b_(builder)
        , board_(board)
        , queue_(queue) {}
    /// The resource published under `name` (throws naming it when nothing was).
    ResourceId get(std::string_view name) const { return board_.get(name); }
    bool has(std::string_view name) const { return board_.has(name); }
    ResourceId create(std::string name, const TextureDesc& desc) { return b_.create(std::move(name), desc); }
    ResourceId sample(ResourceId id, std::string_view sampler = {}) { return b_.sample(id, sampler); }
    ResourceId sample(std::string_view name) { return b_.sample(get(name), name); }
    ResourceId colour(ResourceId id, int attachment = 0, bool keep = true) {
        return b_.colour(id, attachment, keep);
    }
    ResourceId depth(ResourceId id, bool keep = true) { return b_.depth(id, keep); }
    ResourceId depthTest(ResourceId id) { return b_.depthTest(id); }
    /// Writes the named surface (draw.colour, view.depth...) and publishes its new version.
    ResourceId write(std::string_view name, bool keep = true);
    /// Publishes a resource for later passes and for material samplers (ShaderSnippet::samplers).
    void publish(std::string name, ResourceId id) { board_.put(std::move(name), id); }
    void sideEffect() { b_.sideEffect(); }
    /// The view's queue (throws when the builder has none).
    const RenderQueue& queue() const;
    /// The pass draws `items` with their materials: it samples every frame resource their effects'
    /// snippets sample (ShaderSnippet::samplers), so those stay alive and their producers run.
    /// Only effect sets some item uses count. Throws naming the effect and resource when no pass
    /// of the frame makes one.
    void sampleMaterials(std::span<const RenderItem> items);

private:
    FrameGraph::Builder& b_;
    Blackboard& board_;
    const RenderQueue* queue_;
};

/// The view a frame is being set up for.
struct SGFX_API ViewInfo {
    glm::ivec2 drawSize{0}; ///< the target the scene is drawn into (multisample or supersampled)
    glm::ivec2 viewSize{0}; ///< the view's own single-sample target
    int samples = 1;        ///< of the draw target
    std::uint64_t frameNumber = 0;
    int depth = 0; ///< 0: the main view; 1..: nested render-to-texture cameras
    /// The camera's view and projection, without anti-aliasing's jitter (what it draws with,
    /// computed near and far planes included).
    glm::mat4 view{1.0f}, projection{1.0f};
    /// The camera's own (setPerspective) planes and angles, not the ones fitted to what was culled
    /// this frame: what depends on them (shadow cascades) then depends on the camera alone.
    float nominalNear = 0.1f, nominalFar = 1000.0f;
    float fovy = 45.0f;      ///< degrees; of the nominal perspective (perspective == true)
    float aspect = 1.0f;     ///< width / height of the view
    bool perspective = true; ///< false: `projection` is some other (orthographic) matrix
    /// Whether the main pass clears the colour, and to what (linear RGBA): what pixels no opaque
    /// item covers hold after the opaque items.
    bool clearsColour = true;
    glm::vec4 clearColour{0.0f};
    bool clearsDepth = true; ///< whether the main pass clears the depth (to 1)
};

/// A cull from a light (FrameSetup::cullForLight): the light's view and projection, and the node
/// masks it keeps.
struct SGFX_API LightCull {
    glm::mat4 view{1.0f}, projection{1.0f};
    NodeMask traversalMask = ~NodeMask{0};
};

/// One view's frame being set up (see the file comment).
class SGFX_API FrameSetup {
public:
    using Setup = std::function<void(PassBuilder&)>;
    struct DeclaredPass {
        std::string name;
        PassPhase phase;
        Setup setup;
        FrameGraph::Execute execute;
    };

    FrameSetup(const ViewInfo& view, const RenderQueue& queue, const FramePlan* plan = nullptr)
        : view_(view)
        , queue_(queue)
        , plan_(plan) {}
    const ViewInfo& view() const { return view_; }
    const RenderQueue& queue() const { return queue_; }
    /// Fills `into` with what lies below `effect` (from every place the camera's cull reached it)
    /// inside the light's frustum: the casters of a shadow map, say. LODs pick, and billboards
    /// turn, as in the camera's view, so they cast what is drawn; items are sorted front to back
    /// from the light. Items' states may point into the view's queue: `into` is good for this
    /// frame.
    void cullForLight(const EffectNode& effect, const LightCull& light, RenderQueue& into) const;
    /// The effect node's bound in world space over every place the cull reached it (invalid when
    /// it was not reached).
    BoundingSphere worldBound(const EffectNode& effect) const;
    /// True the first time `key` is asked this frame: nested nodes of one kind call it so that
    /// the outermost node's view-wide pass wins (cull visits outer nodes first).
    bool once(std::string_view key) { return once_.emplace(key).second; }
    void requestSceneDepth(const SceneDepthRequest& request);
    /// The main pass samples this resource (a drawable that binds it in its draw with
    /// Renderer::bindFrameResource): its producer is kept and it stays alive through the main pass.
    void sampleInMainPass(std::string resource) {
        if (std::find(mainReads_.begin(), mainReads_.end(), resource) == mainReads_.end())
            mainReads_.push_back(std::move(resource));
    }
    const std::vector<std::string>& mainPassReads() const { return mainReads_; }
    /// A transient target a drawable draws into during its draw in the main pass (a
    /// half-resolution step: Renderer::beginOffscreen with resource names): the main pass's
    /// transparent half creates and writes it, so the renderer's pool makes it for that pass and
    /// takes it back after; it is published as `name` (Renderer::frameResourceTexture). Asking
    /// twice for one name with the same description is one target; a different one throws.
    void offscreenTargetInMainPass(std::string name, const TextureDesc& desc);
    const std::vector<std::pair<std::string, TextureDesc>>& mainPassTargets() const { return mainTargets_; }
    /// The main pass clears the colour to `colour` (linear RGBA) this frame instead of the
    /// camera's clear colour: an effect that knows what every uncovered pixel will show (fog over
    /// a uniform sky) paints it with the clear instead of a pass. Throws std::logic_error when the
    /// view does not clear its colour (ViewInfo::clearsColour) or `colour` is not finite.
    void setClearColour(const glm::vec4& colour);
    const std::optional<glm::vec4>& clearColourOverride() const { return clearColour_; }
    /// Declares a pass. Passes run by phase, and in the order they were added within a phase;
    /// `setup` runs when the renderer builds the graph, `execute` when the pass is not culled.
    void addPass(std::string name, PassPhase phase, Setup setup, FrameGraph::Execute execute);
    /// The same with data the setup fills (resource ids) and the execute reads, as Filament's
    /// addPass<Data>: the execute gets what its own setup declared.
    template <class Data, class SetupFn, class ExecuteFn>
    void addPass(std::string name, PassPhase phase, SetupFn setup, ExecuteFn execute) {
        auto data = std::make_shared<Data>();
        addPass(
            std::move(name), phase, [data, setup](PassBuilder& b) { setup(b, *data); },
            [data, execute](PassCommands& c) { execute(c, std::as_const(*data)); });
    }

    // ---- for the renderer
    const std::vector<DeclaredPass>& passes() const { return passes_; }
    /// The merged scene-depth request; `any` is false when nobody asked.
    struct DepthNeeds {
        bool any = false, beforeMain = false, normals = false, linearDepth = false, positions = false;
    };
    const DepthNeeds& depthNeeds() const { return depth_; }

private:
    ViewInfo view_;
    const RenderQueue& queue_;
    const FramePlan* plan_;
    std::set<std::string, std::less<>> once_;
    std::vector<DeclaredPass> passes_;
    std::vector<std::string> mainReads_;
    std::vector<std::pair<std::string, TextureDesc>> mainTargets_;
    DepthNeeds depth_;
    std::optional<glm::vec4> clearColour_;
};

} // namespace sgfx

#pragma once
#include "sgfx/Export.h"
#include "sgfx/Image.h"
#include "sgfx/RenderQueue.h"
#include "sgfx/ShaderComposer.h"

#include <glm/glm.hpp>

#include <functional>
#include <initializer_list>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace sgfx {

class Camera;
class DatabasePager;
class PassCommands;
class Drawable;
class EffectNode;
class GraphicsContext;
class Renderer;
namespace gl {
struct GeometryBuffers;
struct RenderTarget;
class StateCache;
} // namespace gl

/// Per-frame data every pass and effect can read.
struct SGFX_API FrameData {
    glm::mat4 view{1.0f}, projection{1.0f}, viewProjection{1.0f}, inverseViewProjection{1.0f};
    glm::vec3 eye{0.0f};
    int width = 0, height = 0;
    double time = 0.0;
    std::uint64_t frameNumber = 0;
};

/// What an effect's applyUniforms sees for one draw.
struct SGFX_API DrawContext {
    const FrameData& frame;
    const RenderItem& item;
};

enum class DrawMode : std::uint8_t {
    Main,      ///< the item's blend, depth and faces (blended items: depth writes off unless asked)
    DepthOnly, ///< no colour writes, no blending, depth test and write on for every item
    PassBlend, ///< blend and depth state as the calling pass set them; the item's faces
    GBuffer,   ///< like DepthOnly, but writing the G-buffer variant's outputs (FeatureGBuffer); items
               // with foreign shaders use the `override` program (Renderer::gbufferProgram())
};
static_assert(ProgramKey::Mode.fits(std::uint64_t(DrawMode::GBuffer)), "DrawMode outgrew ProgramKey::Mode");

/// The visible effects and drawables of a view, each once, in cull order (outer first): the
/// renderer calls their setupFrame for the view (EffectNode::setupFrame, FrameSetup.h).
class SGFX_API FramePlan {
public:
    void clear() {
        effects.clear();
        drawables.clear();
        places.clear();
    }
    std::vector<const EffectNode*> effects;
    std::vector<const Drawable*> drawables;
    /// Every place the cull reached an effect node (a node with two parents has two): its world
    /// matrix and the state inherited there, so a cull from a light can start at the node
    /// (FrameSetup::cullForLight). `state` lives as long as the view's queue.
    struct Place {
        const EffectNode* node = nullptr;
        glm::mat4 model{1.0f};
        const ResolvedState* state = nullptr;
    };
    std::vector<Place> places;
};

/// What the last frame drew and how long the CPU and (with timePasses) the GPU took.
struct SGFX_API FrameStats {
    std::size_t drawCalls = 0;
    std::size_t triangles = 0;
    std::size_t programChanges = 0;
    std::size_t stateChanges = 0; ///< program, material, blend/depth/cull and texture binds
    std::size_t culledNodes = 0;
    std::size_t items = 0;
    std::size_t triangleSorts = 0;   ///< per-triangle re-sorts (TransparencyDetails::sortTriangles)
    std::size_t instanceBatches = 0; ///< draws that drew several items (RendererOptions::autoInstancing)
    /// GPU time of each pass and of the main pass's item drawing, in frame order, from timer
    /// queries (RendererOptions::timePasses).
    struct PassTime {
        std::string name;
        double gpuMs = 0.0;
    };
    std::vector<PassTime> passTimes;
    std::uint64_t fragments = 0; ///< with RendererOptions::countFragments
    /// Passes that drew the opaque items (the scene's geometry), over every view: the main pass,
    /// plus the scene-depth pre-pass when an effect needs the depth before the main pass.
    std::size_t geometryPasses = 0;
    /// RendererOptions::occlusionCulling: opaque items tested against the depth of the items drawn
    /// first, and those found hidden and not drawn (every view).
    std::size_t occlusionTested = 0, occlusionCulled = 0;
    /// Submissions (glFlush) while drawing: RendererOptions::submitTriangles and submitsPerFrame.
    std::size_t submissions = 0;
    double cullMs = 0.0, drawMs = 0.0;
};

/// Quality/speed choices of a Renderer.
struct SGFX_API RendererOptions {
    /// Per-pixel Blinn-Phong (default) or per-vertex (Gouraud, the fixed-function look and
    /// cost of OpenSceneGraph's default path; normal maps are ignored).
    enum class Lighting : std::uint8_t { PerPixel, PerVertex } lighting = Lighting::PerPixel;
    /// Views with up to this many lights (0..8) shade them in a loop compiled for their number;
    /// views with more use the light list (FeatureLightList): every light in a shader storage
    /// buffer, and per 16×16-pixel screen tile the ranged lights whose range sphere covers it.
    int maxUnrolledLights = 8;
    /// Count the fragments that pass the depth test in the main pass (FrameStats::fragments);
    /// an occlusion query per view, so off unless profiling.
    bool countFragments = false;
    /// Scene colour target: 8-bit sRGB (default), or linear float for HDR work and diagnostics
    /// (NaN/Inf checks); captures are sRGB-encoded either way. Unorm8Debug is for profiling only
    /// and changes the image: linear colour stored in 8 bits without the sRGB encode (what
    /// OpenSceneGraph's default window stores), to measure what the encode costs.
    enum class ColorTarget : std::uint8_t {
        Srgb8,
        Rgba16F,
        Rgba32F,
        Unorm8Debug
    } colorTarget = ColorTarget::Srgb8;
    /// GL errors and high-severity debug messages are collected for takeGlErrors() (Collect), or
    /// make render() throw at the end of the frame with every message and its call site (Throw).
    /// Unset: Throw when the environment has SGFX_GL_ERRORS=throw (the test suite sets it),
    /// otherwise Collect; the environment is read once, by the constructor, which sets it.
    enum class GlErrorPolicy : std::uint8_t { Collect, Throw };
    std::optional<GlErrorPolicy> glErrors;
    /// Time every pass on the GPU (FrameStats::passTimes); the results are waited for at the end
    /// of the frame, so off unless profiling.
    bool timePasses = false;
    /// Neighbours in the sorted queue that share mesh, state and effects and differ only in their
    /// matrix (a mesh placed many times) are drawn with one instanced call when at least
    /// minInstanceBatch of them follow each other. Built-in materials only; blended items are
    /// always drawn one by one.
    bool autoInstancing = true;
    std::size_t minInstanceBatch = 2;
    /// Submit the queued draws (glFlush) whenever this many triangles have been drawn since the
    /// last submission; 0 never does. A driver that bins a whole submission before rasterising
    /// it (llvmpipe) then rasterises on its threads while this thread keeps drawing instead of
    /// after it: the proving ground's frame about 10 % faster on 2 cores. Desktop GPUs are
    /// unaffected; on tile-based mobile GPUs a flush can force tiles out, so set 0 there.
    std::uint64_t submitTriangles = 20000;
    /// At most about this many of those submissions a frame (0: no limit): the interval grows to
    /// the camera's last frame's triangles over this number when that is longer (a camera's first
    /// frame is not capped; each display channel counts its own). Each submission has a
    /// fixed cost on llvmpipe (its scene is set up again: every state, in every bin); the foreign
    /// city's 590,000 triangles in 4,300 draws paid it 30 times a frame, about 10 ms at 320×180
    /// (docs/performance.md, "Submissions").
    std::uint32_t submitsPerFrame = 4;
    /// Profiling only, changes the image: every built-in material writes its diffuse colour and
    /// nothing else (no lighting, no maps, no varyings read), the floor of rasterising, depth
    /// testing and storing a fragment (bench/pixel_cost.cpp).
    bool debugConstantShading = false;
    /// Conservative occlusion culling of opaque items, in two phases per view: the items seen in
    /// the view's last frame are drawn first, the depth is read back into a max pyramid, and the
    /// other opaque items whose bound lies wholly behind it are not drawn (the image is unchanged:
    /// that depth is of items this frame draws anyway). Pays off where much is hidden (inside a
    /// dense city); the read-back waits for the rasteriser. Off for multisampled draw targets
    /// (MSAA, SSAA's are single-sample) and in views with items whose depth writes can raise the
    /// depth (depth test off or Greater...). DebugUnsafeMinDepth is for tests only: it compares
    /// with the smallest depth under the bound, which drops partly visible items.
    enum class OcclusionCulling : std::uint8_t {
        Off,
        On,
        DebugUnsafeMinDepth
    } occlusionCulling = OcclusionCulling::Off;
};

/// Owns GL-side resources for one context: composed programs, the scene target, the state cache.
class SGFX_API Renderer {
public:
    using Options = RendererOptions;

    explicit Renderer(GraphicsContext& context, Options options = {});
    ~Renderer();
    Renderer(const Renderer&) = delete;
    Renderer& operator=(const Renderer&) = delete;

    /// Culls and draws the camera's scene into the scene target.
    void render(Camera& camera, double time = 0.0, std::uint64_t frameNumber = 0);
    /// The last frame as 8-bit sRGB RGBA, top row first.
    Image readPixels();
    /// The last frame as linear RGBA floats, top row first (exact with a float colour target).
    FloatImage readPixelsLinear();
    /// A target as readPixels() reads the scene target (a multi-channel display's composite).
    Image readPixels(const gl::RenderTarget& target);
    FloatImage readPixelsLinear(const gl::RenderTarget& target);
    /// Ends the frame: copies the scene target to the window's back buffer and swaps (windows),
    /// or submits the queued work (headless).
    void present();
    void blitToWindow(); ///< the copy alone, without the swap
    /// As present() and blitToWindow(), showing `shown` (scaled to the window) instead.
    void present(const gl::RenderTarget& shown);
    void blitToWindow(const gl::RenderTarget& shown);
    /// Multi-channel displays (Viewer::setChannels): copies the scene target (the view rendered
    /// last) pixel for pixel into `region` (x, y, width, height; origin bottom left) of
    /// `composite`, which is (re)made at `size` in the scene target's colour format when it
    /// differs, and then cleared to opaque black. The region must have the scene target's size and
    /// lie inside `size` (std::invalid_argument).
    void copySceneInto(gl::RenderTarget& composite, glm::ivec2 size, const glm::ivec4& region);

    /// Draws the queue's items with each item's composed program (the main pass), or with
    /// `override` for geometry-only passes (depth pre-pass, G-buffer).
    void drawItems(std::span<const RenderItem> items, gl::Program* override = nullptr,
                   DrawMode mode = DrawMode::Main);
    /// Draws one full-screen triangle with `program` into whatever framebuffer is bound (vertex
    /// stage: ShaderComposer::fullscreenVertex(), v_uv in [0, 1]); depth test and writes off
    /// unless `depth` says otherwise. No culling.
    void drawFullscreen(gl::Program& program, const DepthState& depth = {.test = false,
                                                                         .write = false,
                                                                         .func = CompareFunc::Always});
    /// For a Drawable's draw: binds the frame resource published as `resource` (FrameSetup.h; the
    /// drawable's setupFrame asked for it with sampleInMainPass) to `program`'s sampler `uniform`
    /// on a unit the renderer picks. Returns false, binding nothing, when the frame has no such
    /// resource or it is not alive in the pass being drawn (a depth pre-pass before its producer).
    bool bindFrameResource(gl::Program& program, std::string_view uniform, std::string_view resource);
    /// Runs `commands` outside a frame, as a pass with no frame resources (tools and benchmarks
    /// that time one step alone, such as a particle simulation).
    void runCommands(std::string_view name, const std::function<void(PassCommands&)>& commands);
    /// The texture of the frame resource published as `resource` while it is alive in the pass
    /// being drawn (for a drawable to sample on a unit of its own, kFirstDrawableUnit..+15), else 0.
    unsigned frameResourceTexture(std::string_view resource) const;
    /// Positions only, transformed by sgfx_model and the frame block; an empty fragment stage.
    gl::Program& depthOnlyProgram();
    /// G-buffer outputs (see FeatureGBuffer) with flat normals, for items the composer cannot vary.
    gl::Program& gbufferProgram();
    /// Binds a texture to a unit through the renderer's state cache (effect units: see above), read
    /// with the texture's own sampling state (a sampler object left on the unit is unbound).
    /// Units kFirstDrawableUnit..+15 are a drawable's own (buffer textures, volume data): the
    /// renderer never hands them out, the cache tracks them all the same.
    void bindTexture(unsigned unit, unsigned texture);
    /// The first of a drawable's own 16 texture units; units below are the renderer's (material
    /// maps, StateSet textures, frame resources). The context must offer 48 combined units.
    static constexpr unsigned kFirstDrawableUnit = 32;
    /// Sets the blend state through the cache (full-screen passes that blend onto the target).
    void setBlend(BlendMode mode);
    /// For a Drawable's draw: which faces are culled, through the cache (the renderer sets each
    /// item's faces before its draw, so nothing needs restoring).
    void setCull(CullFace face);
    /// Makes `program` current through the cache (an older RenderPass that draws with its own
    /// vertex arrays, transform feedback).
    void useProgram(gl::Program& program);
    /// For a Drawable's draw that renders into a framebuffer of its own first (a half-resolution
    /// step): draws into `fbo` over (0, 0, size) with blending off; endOffscreen() returns to the
    /// framebuffer, viewport and blending the draw began with. Not nested.
    void beginOffscreen(unsigned fbo, glm::ivec2 size);
    /// The same into frame resources the drawable asked for with
    /// FrameSetup::offscreenTargetInMainPass, as colour attachments 0, 1... in this order (a
    /// framebuffer the renderer's pool makes), over their size. Returns false, binding nothing,
    /// when one of them is not alive in the pass being drawn (the item drawn by another pass).
    bool beginOffscreen(std::initializer_list<std::string_view> colourResources);
    /// Clears a colour attachment of the bound framebuffer (the colour mask applies).
    void clearColour(int attachment, const glm::vec4& value);
    void endOffscreen();
    /// Forgets the cached GL state: a pass that set blend, depth or program state directly calls
    /// it before using the renderer's draw functions again.
    void resetStateCache();

    ShaderComposer& composer() { return composer_; }
    /// The queue of the view being drawn (a render-to-texture camera's inside its passes), else the
    /// main view's.
    const RenderQueue& queue() const { return *current_; }
    const FrameData& frame() const { return frame_; }
    const FrameStats& stats() const { return stats_; }
    gl::RenderTarget& sceneTarget();
    /// The target of the view being drawn (the scene target, or a render-to-texture camera's).
    gl::RenderTarget& currentTarget();
    GraphicsContext& context() { return context_; }
    Options& options() { return options_; }
    /// The pager the camera culls ask for PagedLOD files (Viewer sets its own; null: none).
    void setDatabasePager(DatabasePager* pager) { pager_ = pager; }
    DatabasePager* databasePager() const { return pager_; }

    /// The last frame's graphs (one cluster per view: passes with their GPU time when
    /// RendererOptions::timePasses is on, resources with format and size, read and write edges)
    /// in Graphviz DOT; culled passes are dashed.
    /// Written when asked (not every frame) from the graphs the last frame kept.
    std::string lastFrameGraphDot() const;
    /// Bytes of GPU memory the frame-graph textures hold now (every view, in use or pooled).
    std::size_t renderTargetBytes() const;

    /// GL errors and high-severity KHR_debug messages seen since the last call.
    std::vector<std::string> takeGlErrors();
    /// Settings the renderer had to change (an MSAA sample count above the driver's limit), each
    /// once, since the last call.
    std::vector<std::string> takeWarnings();
    /// The opaque items occlusion culling did not draw in the last frame (every view), for checks;
    /// their state pointers live as long as the view's queue.
    const std::vector<RenderItem>& occlusionCulledItems() const;
    /// Adds a warning for takeWarnings() (an effect that refused a setting and kept its last one).
    void warn(std::string message);

private:
    // Defined in scenegraph/src/render/: the private state (RendererImpl.h), one drawItems call
    // (DrawList.cpp), one view of a frame (ViewRenderer.cpp).
    struct Impl;
    class DrawList;
    class View;
    friend class PassCommands;
    void renderView(Camera& camera, gl::RenderTarget& target, RenderQueue& queue, FramePlan& plan, int depth);
    GraphicsContext& context_;
    Options options_;
    FeatureMask viewFeatures_ = 0; ///< variant bits that hold for the whole view (lights, depth test)
    ShaderComposer composer_;
    RenderQueue queue_;
    FramePlan plan_;
    FrameData frame_;
    FrameStats stats_;
    const RenderQueue* current_ = &queue_; ///< the queue being drawn (sub-cameras have their own)
    DatabasePager* pager_ = nullptr;
    std::unique_ptr<Impl> impl_;
};

} // namespace sgfx

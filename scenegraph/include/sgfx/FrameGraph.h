#pragma once
// A per-view frame graph, after Filament's fg/FrameGraph.h: passes declare the resources they
// create, read and write while the frame is set up (no GL there); compile() culls the passes whose
// outputs nobody reads, works out each transient resource's first and last use and which of them
// can share one texture; execute() makes the textures through a ResourceAllocator just before
// their first use, runs the live passes in declaration order and gives the textures back after
// their last use, so a later resource with the same description reuses them (the aliasing).
#include "sgfx/Export.h"
#include "sgfx/Texture.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace sgfx {

class PassCommands;

/// The size of a render target relative to the view: the draw target (multisample or supersampled),
/// the view's own target, or fixed. `num/den` scale it; `round` says which way an odd side goes
/// (ambient occlusion's half resolution rounds up, the volume's down).
struct SGFX_API SizeRule {
    enum class Base : std::uint8_t { Draw, View, Fixed };
    enum class Round : std::uint8_t { Up, Down };
    Base base = Base::Draw;
    int num = 1, den = 1;
    Round round = Round::Up;
    glm::ivec2 fixed{0};
    int min = 1;

    static SizeRule draw() { return {}; }
    static SizeRule view() { return {.base = Base::View}; }
    static SizeRule half(Round r) { return {.base = Base::Draw, .num = 1, .den = 2, .round = r}; }
    static SizeRule fixedSize(int w, int h) { return {.base = Base::Fixed, .fixed = {w, h}}; }
    /// The size in pixels for a view whose draw and view targets have these sizes.
    glm::ivec2 resolve(glm::ivec2 drawSize, glm::ivec2 viewSize) const;
    bool operator==(const SizeRule&) const = default;
};

/// GL internal formats of frame resources, so effects declare targets without including GL.
namespace format {
inline constexpr unsigned Depth32F = 0x8CAC;    // GL_DEPTH_COMPONENT32F
inline constexpr unsigned Rgba16F = 0x881A;     // GL_RGBA16F
inline constexpr unsigned Rgba32F = 0x8814;     // GL_RGBA32F
inline constexpr unsigned Rg32F = 0x8230;       // GL_RG32F
inline constexpr unsigned R32F = 0x822E;        // GL_R32F
inline constexpr unsigned R16F = 0x822D;        // GL_R16F
inline constexpr unsigned R8 = 0x8229;          // GL_R8
inline constexpr unsigned Rgba8 = 0x8058;       // GL_RGBA8
inline constexpr unsigned Srgb8Alpha8 = 0x8C43; // GL_SRGB8_ALPHA8
} // namespace format

/// What a texture of the graph is: GL internal format, size rule, samples (1: a plain texture).
struct SGFX_API TextureDesc {
    unsigned format = 0;
    SizeRule size{};
    int samples = 1;
    Filter filter = Filter::Nearest;
    Wrap wrapS = Wrap::ClampToEdge; ///< across the first coordinate (a table over azimuth repeats)
    /// A full mip chain (single-sample only; Filter::Linear then filters trilinearly): a copy of
    /// the scene that rough glass blurs by level. PassCommands::copyColour fills it.
    bool mipmaps = false;
    bool operator==(const TextureDesc&) const = default;
};

/// A description with its size worked out: what a pool compares to reuse a texture.
struct SGFX_API ResolvedDesc {
    unsigned format = 0;
    int width = 0, height = 0, samples = 1;
    Filter filter = Filter::Nearest;
    Wrap wrapS = Wrap::ClampToEdge;
    bool mipmaps = false;
    /// Mip levels: 1, or the full chain down to 1 × 1.
    int levels() const;
    bool operator==(const ResolvedDesc&) const = default;
    auto operator<=>(const ResolvedDesc&) const = default;
    /// Bytes of GPU memory the texture holds (format size × pixels × samples).
    std::size_t bytes() const;
};

/// Short name of a GL internal format for graphs and messages ("D32F", "RGBA16F"...).
SGFX_API std::string formatName(unsigned format);

/// One version of one resource. Writing a resource gives a new version; the old handle can still
/// be read by passes declared before the write, never after it.
struct SGFX_API ResourceId {
    std::uint16_t index = 0xffff;
    std::uint16_t version = 0;
    bool valid() const { return index != 0xffff; }
    bool operator==(const ResourceId&) const = default;
};

/// Where the textures of the graph come from: the renderer's pool (GL), or a fake in tests.
class SGFX_API ResourceAllocator {
public:
    virtual ~ResourceAllocator() = default;
    /// A texture for a resource about to be written first; `name` is for diagnostics.
    virtual unsigned acquire(const ResolvedDesc& desc, std::string_view name) = 0;
    /// The resource's last use is over: the texture may serve a later resource this frame.
    virtual void release(unsigned texture, const ResolvedDesc& desc) = 0;
};

/// Name → resource, so passes that produce and consume a resource meet without knowing each other
/// (Filament's Blackboard): a depth producer puts "scene.depth", the fog and AO passes get it.
class SGFX_API Blackboard {
public:
    void put(std::string name, ResourceId id) { entries_[std::move(name)] = id; }
    bool has(std::string_view name) const { return entries_.find(name) != entries_.end(); }
    /// Throws std::out_of_range naming the entry when nothing was put under `name`.
    ResourceId get(std::string_view name) const;
    const std::map<std::string, ResourceId, std::less<>>& entries() const { return entries_; }

private:
    std::map<std::string, ResourceId, std::less<>> entries_;
};

class SGFX_API FrameGraph {
public:
    using Execute = std::function<void(PassCommands&)>;
    enum class Access : std::uint8_t { Sample, ColourAttachment, DepthAttachment, DepthTest };

    /// What a pass's setup may do: declare, never touch GL.
    class Builder {
    public:
        /// A transient texture, made when its first writer runs, given back after its last user.
        ResourceId create(std::string name, const TextureDesc& desc);
        /// Sampled by the pass (`binding` names the sampler it is bound to, for the graph picture).
        ResourceId sample(ResourceId id, std::string_view binding = {});
        /// Written as colour attachment `attachment`; `keep` reads what is there (blending onto it).
        ResourceId colour(ResourceId id, int attachment = 0, bool keep = true);
        /// Written as the depth attachment (test and write); `keep` as for colour.
        ResourceId depth(ResourceId id, bool keep = true);
        /// Bound as the depth attachment for testing only: a read, no new version.
        ResourceId depthTest(ResourceId id);
        /// The pass is never culled (it writes something outside the graph: buffers, history).
        void sideEffect();

    private:
        friend class FrameGraph;
        Builder(FrameGraph& g, std::uint32_t pass)
            : graph_(g)
            , pass_(pass) {}
        FrameGraph& graph_;
        std::uint32_t pass_;
    };

    /// Declares a pass: `setup(Builder&)` runs now and declares what the pass uses; `execute` runs
    /// in execute() if the pass survives culling. `phase` is only a label for the picture.
    void addPass(std::string name, const std::function<void(Builder&)>& setup, Execute execute,
                 std::string phase = {});
    /// A texture made outside the graph (the view's target, a history); writing it is a side effect.
    ResourceId import(std::string name, const TextureDesc& desc, unsigned texture);
    /// Marks the resource's current version as the frame's result: its writers are kept.
    void present(ResourceId id);

    /// Culls, checks and plans lifetimes for a view with these draw and view target sizes.
    void compile(glm::ivec2 drawSize, glm::ivec2 viewSize);
    /// Runs the live passes in order; `run` invokes a pass's execute (the renderer wraps it in
    /// its timers and state reset), textures come from `allocator`.
    void execute(ResourceAllocator& allocator,
                 const std::function<void(std::string_view name, const Execute&)>& run);

    // ---- after compile()
    bool culled(std::string_view pass) const;
    std::vector<std::string> livePasses() const;
    std::vector<std::string> passNames() const;
    /// The texture of a resource (during execute: between its first and last use), 0 otherwise.
    unsigned texture(ResourceId id) const;
    const ResolvedDesc& resolved(ResourceId id) const;
    const std::string& resourceName(ResourceId id) const;
    /// Names of the passes that write any version of the resource and survive culling.
    std::vector<std::string> writers(std::string_view resource) const;
    /// Distinct textures the transient resources needed (equal descriptions with disjoint lives
    /// share one), and the bytes they hold.
    std::size_t textureSlots() const;
    std::size_t transientBytes() const;

    /// The graph in Graphviz DOT as one cluster (`cluster` names it); `gpuMs` gives pass times.
    std::string dotCluster(std::string_view cluster, const std::map<std::string, double>& gpuMs) const;

    Blackboard blackboard;

private:
    struct Resource {
        std::string name;
        TextureDesc desc;
        ResolvedDesc resolved;
        bool imported = false;
        unsigned texture = 0; // imported, or during its lifetime
        std::uint16_t versions = 1;
        std::uint32_t first = ~0u, last = 0; // live pass order positions
        int slot = -1;
    };
    struct Use {
        ResourceId id;
        Access access;
        std::string binding;
    };
    struct Pass {
        std::string name, phase;
        Execute execute;
        std::vector<Use> reads, writes;
        bool sideEffect = false;
        int refs = 0;
        bool culled = false;
    };
    Resource& resource(ResourceId id, std::string_view pass);
    ResourceId use(std::uint32_t pass, ResourceId id, Access access, bool write, bool keep,
                   std::string_view binding);
    void cull();
    void planLifetimes();
    std::vector<Resource> resources_;
    std::vector<Pass> passes_;
    std::vector<ResourceId> presented_;
    std::size_t slots_ = 0;
    bool compiled_ = false;
};

} // namespace sgfx

#pragma once
#include "sgfx/Export.h"
#include "sgfx/LOD.h"

#include <cstdint>
#include <filesystem>
#include <functional>
#include <limits>

namespace sgfx {

class DatabasePager;

/// An LOD whose children may be files loaded on demand (OSG's osg::PagedLOD). Each child slot
/// has a range and, optionally, a file name. A slot whose file is not loaded holds an empty
/// placeholder node; when a cull with a DatabasePager (a Viewer's) finds the slot's range active
/// it asks the pager for the file, and meanwhile draws the finest loaded child coarser than the
/// slot (the parent level keeps drawing). The pager loads on its own thread and attaches the
/// subgraph between frames (Viewer::update); a loaded slot that no cull draws for the pager's
/// expiry frames and seconds is put back to its placeholder, so its memory and GL objects go.
/// Children added with a node and no file are never unloaded.
class SGFX_API PagedLOD : public LOD {
public:
    /// Reads a file into a subgraph; runs on the pager's thread (no GL). Throws or returns null
    /// on failure. The model loaders' sgfx::loadModel fits.
    using Loader = std::function<NodePtr(const std::filesystem::path&)>;
    static constexpr std::size_t npos = std::numeric_limits<std::size_t>::max();

    static std::shared_ptr<PagedLOD> create() { return std::make_shared<PagedLOD>(); }
    void accept(NodeVisitor& v) override;

    using LOD::addChild;
    /// A slot loaded on demand from `file` (relative names resolve against databasePath()), drawn
    /// in [min, max). Throws std::invalid_argument naming the node for an empty name or a bad range.
    void addChild(const std::filesystem::path& file, float min, float max);
    /// Gives slot `index` a file (an empty path: none). A loaded child with a file may be unloaded
    /// and loaded again; a load in flight for the old name is dropped. Throws std::out_of_range.
    void setFileName(std::size_t index, const std::filesystem::path& file);
    const std::filesystem::path& fileName(std::size_t index) const;
    /// The file the pager reads for slot `index`: fileName() against databasePath().
    std::filesystem::path resolvedFileName(std::size_t index) const;
    /// Whether slot `index` holds its node (false: the placeholder, the file not loaded).
    bool loaded(std::size_t index) const;
    /// Whether loading slot `index` failed (reported once; not asked for again until its file
    /// name is set again).
    bool failed(std::size_t index) const;
    /// The child drawn in place of slot `index` while it is not loaded: the finest loaded child
    /// coarser than it (LOD::fineness), or npos.
    std::size_t coarserLoaded(std::size_t index) const;

    void setDatabasePath(std::filesystem::path path) { databasePath_ = std::move(path); }
    const std::filesystem::path& databasePath() const { return databasePath_; }
    /// This node's loader; without one the pager's is used.
    void setLoader(Loader loader) { loader_ = std::move(loader); }
    const Loader& loader() const { return loader_; }

    /// The cull's note that slot `index` was drawn in the pager's frame `frame` at `time`.
    void markUsed(std::size_t index, std::uint64_t frame, double time);

protected:
    /// The children's bound, grown to hold the user sphere: a node whose files are not loaded
    /// yet must still be found in view.
    BoundingSphere computeBound() const override;
    void childInserted(std::size_t index) override;
    void childRemoved(std::size_t index) override;

private:
    friend class DatabasePager;
    enum class State : std::uint8_t { Idle, Requested, Failed };
    /// Per slot, on the viewer's thread only (cull and update).
    struct Slot {
        std::filesystem::path file;
        State state = State::Idle;
        std::uint64_t id = 0; ///< new whenever the slot's file or node changes: stale loads are dropped
        std::uint64_t lastUsedFrame = 0;
        double lastUsedTime = 0.0;
    };
    std::size_t slotIndex(std::uint64_t id) const; ///< npos when no slot has this id
    static std::uint64_t nextId();
    std::vector<Slot> slots_;
    std::filesystem::path databasePath_;
    Loader loader_;
    bool registered_ = false; ///< whether the pager tracks this node for expiry
};

} // namespace sgfx

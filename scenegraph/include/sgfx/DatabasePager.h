#pragma once
#include "sgfx/Export.h"
#include "sgfx/PagedLOD.h"

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace sgfx {

/// Loads PagedLOD files on a worker thread (OSG's osgDB::DatabasePager). The cull asks for files
/// (request(), thread-safe, never blocks on a load); Viewer::update calls updateSceneGraph()
/// between frames, which attaches what has loaded and unloads what has gone unused. No frame ever
/// waits for a load. The worker starts at the first request and joins on destruction (after the
/// load in progress, if any, returns).
class SGFX_API DatabasePager {
public:
    using Loader = PagedLOD::Loader;

    struct Stats {
        std::size_t requested = 0; ///< requests taken, in all
        std::size_t pending = 0;   ///< requests not yet attached or failed (queued, loading, ready)
        std::size_t loaded = 0;    ///< subgraphs attached, in all
        std::size_t expired = 0;   ///< subgraphs unloaded for disuse, in all
        std::size_t failed = 0;    ///< loads that failed, in all
        std::size_t live = 0;      ///< slots the pager loaded that hold their subgraph now
    };

    DatabasePager() = default;
    ~DatabasePager();
    DatabasePager(const DatabasePager&) = delete;
    DatabasePager& operator=(const DatabasePager&) = delete;

    /// The loader for nodes without their own.
    void setLoader(Loader loader);
    /// A loaded slot is unloaded once no cull has drawn it for more than `frames` frames and at
    /// least `seconds` of simulation time (OSG: 1 frame, 10 s). Throws std::invalid_argument for
    /// a non-finite or negative time, keeping the old values.
    void setExpiry(std::uint64_t frames, double seconds);
    std::uint64_t expiryFrames() const { return expiryFrames_; }
    double expiryDelay() const { return expiryDelay_; }

    Stats stats() const;
    /// Every load error so far, one line each naming the node and the file.
    std::vector<std::string> errors() const;

    /// Cull side: asks for slot `index` of `node` unless it is loaded, asked for or failed.
    void request(PagedLOD& node, std::size_t index);
    /// Marks slot `index` drawn this frame (the cull calls it for what it draws).
    void markUsed(PagedLOD& node, std::size_t index);
    /// Between frames, on the viewer's thread: attaches the loaded subgraphs and unloads the
    /// slots unused for the expiry frames and time; returns what it unloaded, whose GL objects
    /// the caller releases (Viewer does).
    std::vector<NodePtr> updateSceneGraph(std::uint64_t frameNumber, double time);
    std::uint64_t frameNumber() const { return frameNumber_; }
    double time() const { return time_; }

    /// Waits until nothing is queued or loading (tests, tools; frames never wait). False when
    /// `timeout` passed first.
    bool waitUntilIdle(std::chrono::milliseconds timeout) const;

private:
    struct Request {
        std::weak_ptr<Node> node;
        std::uint64_t slotId = 0;
        std::filesystem::path file;
        std::string nodeName;
        Loader loader; ///< the node's, else empty (the pager's is taken when loading)
    };
    struct Result {
        Request request;
        NodePtr node;
        std::string error;
    };
    void run();
    void attach(Result& r);
    void expire(std::vector<NodePtr>& unloaded);

    mutable std::mutex mutex_;
    mutable std::condition_variable wake_; ///< worker: a request or stop
    mutable std::condition_variable idle_; ///< waitUntilIdle: queue drained
    std::deque<Request> queue_;            ///< guarded by mutex_
    std::vector<Result> ready_;            ///< guarded by mutex_
    bool loading_ = false;                 ///< guarded by mutex_
    bool stop_ = false;                    ///< guarded by mutex_
    Loader loader_;                        ///< guarded by mutex_
    Stats stats_;                          ///< guarded by mutex_
    std::vector<std::string> errors_;      ///< guarded by mutex_
    std::thread worker_;
    /// Viewer-thread state: the nodes with slots the pager loaded.
    std::vector<std::weak_ptr<Node>> tracked_;
    std::uint64_t expiryFrames_ = 1;
    double expiryDelay_ = 10.0;
    std::uint64_t frameNumber_ = 0;
    double time_ = 0.0;
};

} // namespace sgfx

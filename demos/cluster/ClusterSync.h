#pragma once
// sgfx-cluster's use of MPI: the ranks' host names, the frame packet from rank 0 to every rank,
// the frame lock (a barrier with a timeout) and the gather of the channels' images to rank 0.
// Every wait is a nonblocking request polled against a deadline, so a rank that stalls or dies is
// named (rank and host) and the others stop within the timeout instead of hanging in a collective.
#include <sgfx/Image.h>

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace sgfxcluster {

class ClusterSync {
public:
    /// MPI_Init and the gathering of every rank's host name (the one blocking collective: at
    /// start, before any rank can have stalled in a frame).
    ClusterSync(int& argc, char**& argv);
    ~ClusterSync(); ///< MPI_Finalize (only after a run whose every wait succeeded)
    ClusterSync(const ClusterSync&) = delete;
    ClusterSync& operator=(const ClusterSync&) = delete;

    int rank() const { return rank_; }
    int size() const { return size_; }
    const std::string& host(int rank) const { return hosts_.at(std::size_t(rank)); }
    /// "rank R (host H)"
    std::string describe(int rank) const;

    /// How long one wait may take (seconds; first frame: its own, longer limit).
    void setTimeout(double seconds) { timeout_ = seconds; }

    /// Rank 0: sends `packet` to every other rank. Other ranks: receives it into `packet`. Waits
    /// at most the timeout (frame 0: `firstFrameSeconds`), else fail().
    void broadcast(std::vector<std::byte>& packet, std::uint64_t frame, double firstFrameSeconds);
    /// The frame lock: returns once every rank has called it for `frame` (all finished drawing
    /// frame N before any presents N + 1). Ranks tell rank 0; rank 0 releases them all or, when a
    /// rank does not arrive within the timeout, names it to every rank and stops the run.
    /// Returns the seconds this rank waited.
    double frameBarrier(std::uint64_t frame, double limitSeconds);
    /// MPI_Gatherv of every rank's RGBA8 image to rank 0 (called by all ranks after the last
    /// barrier). Rank 0 gets them in rank order; other ranks get an empty vector.
    std::vector<sgfx::Image> gather(const sgfx::Image& mine);
    /// MPI_Gather of one number per rank to rank 0 (after the last barrier, like gather()).
    std::vector<double> gather(double mine);

    /// Prints the message on this rank's stderr (prefixed with its rank and host) and ends the
    /// whole run with MPI_Abort (exit status `code`).
    [[noreturn]] void fail(const std::string& message, int code = 3) const;

private:
    int rank_ = 0, size_ = 1;
    std::vector<std::string> hosts_;
    double timeout_ = 5.0;
};

} // namespace sgfxcluster

#include "ClusterSync.h"

#include <mpi.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <stdexcept>
#include <thread>

namespace sgfxcluster {
namespace {

enum Tag : int { kPacket = 11, kDone = 12, kGo = 13 };
constexpr int kHostChars = 64;
using Clock = std::chrono::steady_clock;

Clock::time_point after(double seconds) {
    return Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(seconds));
}

// Polls until every request completed (true) or the deadline passed (false). The short sleep
// keeps ranks that share a core with others from spinning while they wait.
bool waitAll(std::vector<MPI_Request>& requests, Clock::time_point deadline) {
    for (;;) {
        int done = 0;
        MPI_Testall(int(requests.size()), requests.data(), &done, MPI_STATUSES_IGNORE);
        if (done) return true;
        if (Clock::now() > deadline) return false;
        std::this_thread::sleep_for(std::chrono::microseconds(200));
    }
}

std::string seconds(double s) {
    char text[32];
    std::snprintf(text, sizeof text, "%.1f s", s);
    return text;
}

} // namespace

ClusterSync::ClusterSync(int& argc, char**& argv) {
    MPI_Init(&argc, &argv);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &size_);
    std::array<char, kHostChars> mine{};
    int length = 0;
    std::array<char, MPI_MAX_PROCESSOR_NAME> name{};
    MPI_Get_processor_name(name.data(), &length);
    std::copy_n(name.data(), std::min(length, kHostChars - 1), mine.data());
    std::vector<char> all(std::size_t(size_) * kHostChars);
    MPI_Allgather(mine.data(), kHostChars, MPI_CHAR, all.data(), kHostChars, MPI_CHAR, MPI_COMM_WORLD);
    for (int r = 0; r < size_; ++r)
        hosts_.emplace_back(all.data() + std::size_t(r) * kHostChars);
}

ClusterSync::~ClusterSync() {
    MPI_Finalize();
}

std::string ClusterSync::describe(int rank) const {
    return "rank " + std::to_string(rank) + " (host " + host(rank) + ")";
}

void ClusterSync::fail(const std::string& message, int code) const {
    std::fprintf(stderr, "sgfx-cluster: %s: %s\n", describe(rank_).c_str(), message.c_str());
    std::fflush(stderr);
    MPI_Abort(MPI_COMM_WORLD, code);
    std::_Exit(code); // MPI_Abort does not return; this keeps [[noreturn]] honest
}

void ClusterSync::broadcast(std::vector<std::byte>& packet, std::uint64_t frame, double firstFrameSeconds) {
    const double limit = frame == 0 ? firstFrameSeconds : timeout_;
    const auto deadline = after(limit);
    if (rank_ == 0) {
        // Point to point from rank 0 (not MPI_Bcast): a stalled rank inside a broadcast tree
        // would hold up the ranks below it, with no way to time out.
        std::vector<MPI_Request> sends(std::size_t(size_ - 1));
        for (int r = 1; r < size_; ++r)
            MPI_Isend(packet.data(), int(packet.size()), MPI_BYTE, r, kPacket, MPI_COMM_WORLD,
                      &sends[std::size_t(r - 1)]);
        if (!waitAll(sends, deadline))
            fail("could not send the packet of frame " + std::to_string(frame) + " within " + seconds(limit));
        return;
    }
    for (;;) {
        int arrived = 0;
        MPI_Status status;
        MPI_Iprobe(0, kPacket, MPI_COMM_WORLD, &arrived, &status);
        if (arrived) {
            int bytes = 0;
            MPI_Get_count(&status, MPI_BYTE, &bytes);
            packet.resize(std::size_t(bytes));
            MPI_Recv(packet.data(), bytes, MPI_BYTE, 0, kPacket, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
            return;
        }
        if (Clock::now() > deadline)
            fail(describe(0) + " sent no frame packet for frame " + std::to_string(frame) + " within " +
                 seconds(limit) + " (stalled or died); stopping");
        std::this_thread::sleep_for(std::chrono::microseconds(200));
    }
}

double ClusterSync::frameBarrier(std::uint64_t frame, double limitSeconds) {
    const auto start = Clock::now();
    const std::string what = "frame " + std::to_string(frame);
    std::array<int, 2> go{0, -1}; // {0: go on, 1: stop; the rank that did not arrive}
    if (rank_ == 0) {
        std::vector<MPI_Request> dones(std::size_t(size_ - 1));
        std::vector<int> frames(std::size_t(size_ - 1));
        for (int r = 1; r < size_; ++r)
            MPI_Irecv(&frames[std::size_t(r - 1)], 1, MPI_INT, r, kDone, MPI_COMM_WORLD,
                      &dones[std::size_t(r - 1)]);
        const bool all = waitAll(dones, after(limitSeconds));
        for (int r = 1; r < size_ && all; ++r)
            if (frames[std::size_t(r - 1)] != int(frame))
                fail(describe(r) + " finished frame " + std::to_string(frames[std::size_t(r - 1)]) +
                     " when rank 0 waited for " + what);
        if (!all)
            for (int r = 1; r < size_ && go[1] < 0; ++r) {
                int finished = 0;
                MPI_Test(&dones[std::size_t(r - 1)], &finished, MPI_STATUS_IGNORE);
                if (!finished) go = {1, r};
            }
        std::vector<MPI_Request> sends;
        for (int r = 1; r < size_; ++r)
            if (r != go[1]) {
                sends.emplace_back();
                MPI_Isend(go.data(), 2, MPI_INT, r, kGo, MPI_COMM_WORLD, &sends.back());
            }
        // The others are waiting for this answer: let it leave before a stop aborts the run.
        waitAll(sends, after(all ? limitSeconds : 1.0));
        if (!all)
            fail(describe(go[1]) + " did not finish " + what + " within " + seconds(limitSeconds) +
                 " (stalled or died); stopping all ranks");
        return std::chrono::duration<double>(Clock::now() - start).count();
    }
    const int mine = int(frame);
    std::vector<MPI_Request> requests(2);
    MPI_Isend(&mine, 1, MPI_INT, 0, kDone, MPI_COMM_WORLD, &requests[0]);
    MPI_Irecv(go.data(), 2, MPI_INT, 0, kGo, MPI_COMM_WORLD, &requests[1]);
    // Longer than rank 0's limit, so that rank 0's verdict (naming the late rank) arrives first.
    if (!waitAll(requests, after(limitSeconds + 2.0)))
        fail(describe(0) + " did not release " + what + " within " + seconds(limitSeconds + 2.0) +
             " (stalled or died); stopping");
    if (go[0] != 0)
        fail("stopping at " + what + ": rank 0 reports " + describe(go[1]) + " did not finish it");
    return std::chrono::duration<double>(Clock::now() - start).count();
}

std::vector<sgfx::Image> ClusterSync::gather(const sgfx::Image& mine) {
    const std::array<int, 3> shape{mine.width, mine.height, mine.channels};
    std::vector<int> shapes(std::size_t(size_) * 3);
    MPI_Gather(shape.data(), 3, MPI_INT, shapes.data(), 3, MPI_INT, 0, MPI_COMM_WORLD);
    const std::size_t n = std::size_t(size_);
    std::vector<int> counts(n), offsets(n);
    std::vector<std::uint8_t> all;
    if (rank_ == 0) {
        std::size_t total = 0;
        for (std::size_t r = 0; r < std::size_t(size_); ++r) {
            counts[r] = shapes[3 * r] * shapes[3 * r + 1] * shapes[3 * r + 2];
            offsets[r] = int(total);
            total += std::size_t(counts[r]);
        }
        if (total > std::size_t(1) << 31) throw std::runtime_error("gather: composite over 2 GiB");
        all.resize(total);
    }
    MPI_Gatherv(mine.pixels.data(), int(mine.pixels.size()), MPI_BYTE, all.data(), counts.data(),
                offsets.data(), MPI_BYTE, 0, MPI_COMM_WORLD);
    std::vector<sgfx::Image> images;
    if (rank_ != 0) return images;
    for (std::size_t r = 0; r < std::size_t(size_); ++r) {
        sgfx::Image im;
        im.width = shapes[3 * r];
        im.height = shapes[3 * r + 1];
        im.channels = shapes[3 * r + 2];
        im.pixels.assign(all.begin() + offsets[r], all.begin() + offsets[r] + counts[r]);
        images.push_back(std::move(im));
    }
    return images;
}

std::vector<double> ClusterSync::gather(double mine) {
    std::vector<double> all(rank_ == 0 ? std::size_t(size_) : 0);
    MPI_Gather(&mine, 1, MPI_DOUBLE, all.data(), 1, MPI_DOUBLE, 0, MPI_COMM_WORLD);
    return all;
}

} // namespace sgfxcluster

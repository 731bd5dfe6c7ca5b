#pragma once
// The per-frame packet rank 0 of sgfx-cluster broadcasts: everything the other ranks need to show
// the same frame (frame number, time step, simulation time, the eye's view, the parameters and
// transforms that changed). No MPI here: the packet is plain bytes, unit-tested on its own.
//
// Wire format (little endian, version 1):
//   u32 magic 'SGFP' | u16 version | u16 reserved (0) | u64 frame | f64 dt | f64 simulationTime |
//   f32[16] eyeView (column major) | u32 change count | per change: u32 id, u32 n, f32[n] values
#include <glm/glm.hpp>

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace sgfxcluster {

struct FramePacket {
    static constexpr std::uint32_t kMagic = 0x50464753u; // "SGFP" read as little-endian bytes
    static constexpr std::uint16_t kVersion = 1;
    static constexpr std::size_t kMaxChanges = 4096;       // a frame that changes more is an error
    static constexpr std::size_t kMaxValuesPerChange = 64; // a mat4 is 16

    /// One changed thing: a parameter or transform the application numbered (ids are the
    /// application's; the packet only carries them).
    struct Change {
        std::uint32_t id = 0;
        std::vector<float> values;
        bool operator==(const Change&) const = default;
    };

    std::uint64_t frame = 0;
    double dt = 0.0;             ///< seconds, finite and >= 0
    double simulationTime = 0.0; ///< seconds, finite
    glm::mat4 eyeView{1.0f};     ///< the eye's view matrix (the channels' offsets apply on top)
    std::vector<Change> changes;

    /// Throws std::invalid_argument naming the field (non-finite dt, too many changes, ...).
    std::vector<std::byte> serialize() const;
    /// Throws std::invalid_argument naming the field and the reason for anything that is not a
    /// whole, well-formed packet of this version (wrong magic or version, truncated, trailing
    /// bytes, counts over the limits, non-finite numbers).
    static FramePacket deserialize(std::span<const std::byte> bytes);
    bool operator==(const FramePacket&) const = default;
};

} // namespace sgfxcluster

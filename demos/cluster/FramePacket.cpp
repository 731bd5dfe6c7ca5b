#include "FramePacket.h"

#include <bit>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>

namespace sgfxcluster {
namespace {

static_assert(std::endian::native == std::endian::little, "the frame packet is written little endian");

[[noreturn]] void refuse(const std::string& field, const std::string& why) {
    throw std::invalid_argument("frame packet: " + field + ": " + why);
}

template <class T> void put(std::vector<std::byte>& out, const T& v) {
    const std::size_t at = out.size();
    out.resize(at + sizeof(T));
    std::memcpy(out.data() + at, &v, sizeof(T));
}

// Reads from a span, refusing to run past its end (naming what it was reading).
class Reader {
public:
    explicit Reader(std::span<const std::byte> bytes)
        : bytes_(bytes) {}
    template <class T> T get(const char* field) {
        if (bytes_.size() - at_ < sizeof(T))
            refuse(field, "truncated (" + std::to_string(bytes_.size()) + " bytes, needs more at offset " +
                              std::to_string(at_) + ")");
        T v;
        std::memcpy(&v, bytes_.data() + at_, sizeof(T));
        at_ += sizeof(T);
        return v;
    }
    std::size_t left() const { return bytes_.size() - at_; }

private:
    std::span<const std::byte> bytes_;
    std::size_t at_ = 0;
};

void checkFinite(double v, const std::string& field) {
    if (!std::isfinite(v)) refuse(field, "not finite");
}

void checkPacket(const FramePacket& p) {
    checkFinite(p.dt, "dt");
    if (p.dt < 0.0) refuse("dt", "negative");
    checkFinite(p.simulationTime, "simulationTime");
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            checkFinite(p.eyeView[c][r], "eyeView");
    if (p.changes.size() > FramePacket::kMaxChanges)
        refuse("changes", std::to_string(p.changes.size()) + " over the limit of " +
                              std::to_string(FramePacket::kMaxChanges));
    for (const FramePacket::Change& ch : p.changes) {
        const std::string where = "change id " + std::to_string(ch.id);
        if (ch.values.size() > FramePacket::kMaxValuesPerChange)
            refuse(where, std::to_string(ch.values.size()) + " values, over the limit of " +
                              std::to_string(FramePacket::kMaxValuesPerChange));
        for (const float v : ch.values)
            checkFinite(v, where);
    }
}

} // namespace

std::vector<std::byte> FramePacket::serialize() const {
    checkPacket(*this);
    std::vector<std::byte> out;
    out.reserve(100 + changes.size() * 16);
    put(out, kMagic);
    put(out, kVersion);
    put(out, std::uint16_t(0));
    put(out, frame);
    put(out, dt);
    put(out, simulationTime);
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            put(out, eyeView[c][r]);
    put(out, std::uint32_t(changes.size()));
    for (const Change& ch : changes) {
        put(out, ch.id);
        put(out, std::uint32_t(ch.values.size()));
        for (const float v : ch.values)
            put(out, v);
    }
    return out;
}

FramePacket FramePacket::deserialize(std::span<const std::byte> bytes) {
    Reader in(bytes);
    if (in.get<std::uint32_t>("magic") != kMagic) refuse("magic", "not a frame packet");
    const auto version = in.get<std::uint16_t>("version");
    if (version != kVersion)
        refuse("version", std::to_string(version) + ", this build reads " + std::to_string(kVersion));
    if (in.get<std::uint16_t>("reserved") != 0) refuse("reserved", "not 0");
    FramePacket p;
    p.frame = in.get<std::uint64_t>("frame");
    p.dt = in.get<double>("dt");
    p.simulationTime = in.get<double>("simulationTime");
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            p.eyeView[c][r] = in.get<float>("eyeView");
    const auto count = in.get<std::uint32_t>("change count");
    if (count > kMaxChanges)
        refuse("change count", std::to_string(count) + " over the limit of " + std::to_string(kMaxChanges));
    // Each change is at least 8 bytes: a count the bytes cannot hold is garbage (no huge reserve).
    if (std::size_t(count) * 8 > in.left())
        refuse("change count", std::to_string(count) + " changes do not fit in the " +
                                   std::to_string(in.left()) + " bytes left");
    p.changes.resize(count);
    for (Change& ch : p.changes) {
        ch.id = in.get<std::uint32_t>("change id");
        const auto n = in.get<std::uint32_t>("change value count");
        if (n > kMaxValuesPerChange)
            refuse("change id " + std::to_string(ch.id),
                   std::to_string(n) + " values, over the limit of " + std::to_string(kMaxValuesPerChange));
        ch.values.resize(n);
        for (float& v : ch.values)
            v = in.get<float>("change values");
    }
    if (in.left() != 0) refuse("length", std::to_string(in.left()) + " trailing bytes after the last change");
    checkPacket(p);
    return p;
}

} // namespace sgfxcluster

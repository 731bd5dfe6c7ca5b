// sgfx-cluster's frame packet (demos/cluster/FramePacket.h), without MPI: what goes in comes out
// bit for bit, and anything that is not a whole packet of this version is refused, naming why.
#include "FramePacket.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>

namespace {

using sgfxcluster::FramePacket;

FramePacket sample() {
    FramePacket p;
    p.frame = 123456789012ull;
    p.dt = 1.0 / 60.0;
    p.simulationTime = 2057.25;
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            p.eyeView[c][r] = float(c * 4 + r) * 0.37f - 1.5f;
    p.changes = {
        {1, {0.0125f}}, {2, std::vector<float>(16, -3.25f)}, {100, {}}, {4000000000u, {1e-30f, 7.0f}}};
    return p;
}

std::string refusal(const std::vector<std::byte>& bytes) {
    try {
        FramePacket::deserialize(bytes);
    } catch (const std::invalid_argument& e) {
        return e.what();
    }
    return "(accepted)";
}

template <class T> void poke(std::vector<std::byte>& bytes, std::size_t at, T v) {
    std::memcpy(bytes.data() + at, &v, sizeof(T));
}

TEST(FramePacket, RoundTripIsExact) {
    const FramePacket p = sample();
    const std::vector<std::byte> bytes = p.serialize();
    // 100 bytes of header and eye, then 8 bytes and the values per change.
    EXPECT_EQ(bytes.size(), 100u + (8 + 4) + (8 + 64) + 8 + (8 + 8));
    EXPECT_EQ(FramePacket::deserialize(bytes), p);
    const FramePacket empty;
    EXPECT_EQ(FramePacket::deserialize(empty.serialize()), empty);
}

TEST(FramePacket, RefusesGarbage) {
    const std::vector<std::byte> good = sample().serialize();
    EXPECT_NE(refusal({}).find("magic: truncated"), std::string::npos) << refusal({});
    std::vector<std::byte> b = good;
    b[0] = std::byte{'X'};
    EXPECT_NE(refusal(b).find("magic: not a frame packet"), std::string::npos) << refusal(b);
    b = good;
    poke<std::uint16_t>(b, 4, 2);
    EXPECT_NE(refusal(b).find("version: 2, this build reads 1"), std::string::npos) << refusal(b);
    for (std::size_t cut = 1; cut < good.size(); cut += 7) { // every truncation is caught
        b.assign(good.begin(), good.end() - std::ptrdiff_t(cut));
        EXPECT_NE(refusal(b).find("frame packet: "), std::string::npos) << cut << ": " << refusal(b);
    }
    b = good;
    b.push_back(std::byte{0});
    EXPECT_NE(refusal(b).find("length: 1 trailing bytes"), std::string::npos) << refusal(b);
    b = good;
    poke<std::uint32_t>(b, 96, 0xFFFFFFFFu); // change count
    EXPECT_NE(refusal(b).find("change count: 4294967295 over the limit"), std::string::npos) << refusal(b);
    b = good;
    poke<std::uint32_t>(b, 96, 1000); // within the limit, but the bytes cannot hold them
    EXPECT_NE(refusal(b).find("change count: 1000 changes do not fit"), std::string::npos) << refusal(b);
    b = good;
    poke<std::uint32_t>(b, 104, 65); // the first change's value count
    EXPECT_NE(refusal(b).find("change id 1: 65 values, over the limit of 64"), std::string::npos)
        << refusal(b);
    b = good;
    poke<double>(b, 16, std::numeric_limits<double>::quiet_NaN()); // dt
    EXPECT_NE(refusal(b).find("dt: not finite"), std::string::npos) << refusal(b);
    b = good;
    poke<double>(b, 16, -0.5);
    EXPECT_NE(refusal(b).find("dt: negative"), std::string::npos) << refusal(b);
    b = good;
    poke<float>(b, 108, std::numeric_limits<float>::infinity()); // the first change's value
    EXPECT_NE(refusal(b).find("change id 1: not finite"), std::string::npos) << refusal(b);
}

TEST(FramePacket, SerializeRefusesWhatItCouldNotRead) {
    FramePacket p = sample();
    p.eyeView[3][0] = std::nanf("");
    EXPECT_THROW(p.serialize(), std::invalid_argument);
    p = sample();
    p.changes.assign(FramePacket::kMaxChanges + 1, {7, {1.0f}});
    EXPECT_THROW(p.serialize(), std::invalid_argument);
    p = sample();
    p.changes[0].values.assign(FramePacket::kMaxValuesPerChange + 1, 0.0f);
    EXPECT_THROW(p.serialize(), std::invalid_argument);
}

} // namespace

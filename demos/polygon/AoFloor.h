#pragma once
// The floor under any ambient occlusion that reads a depth pre-pass of the same frame
// (`polygon --ao floor`, bench/ao_table.sh's "floor" row): what AO costs on this driver before
// it computes anything. Issue 24's AO goal is read against it (docs/effects/ao.md, "The floor").
#include <sgfx/Effect.h>

#include <memory>

namespace polygon {

/// Requests the view's depth pre-pass, reads it in one half-resolution full-screen pass that
/// writes k = 0, and has every material below read k with one texel fetch: the pre-pass, a
/// half-size pass and the materials' read, with no occlusion arithmetic at all. The image is the
/// plain one.
class AoFloorNode : public sgfx::EffectNode {
public:
    static std::shared_ptr<AoFloorNode> create() { return std::make_shared<AoFloorNode>(); }
    std::string_view kind() const override { return "ao_floor"; }
    int order() const override { return 100; } // where AmbientOcclusionNode is
    const sgfx::ShaderSnippet& snippet() const override;
    void setupFrame(sgfx::FrameSetup& frame) const override;
};

} // namespace polygon

#pragma once
#include "sgfx/Export.h"
#include <sgfx/Effect.h>

#include <glm/glm.hpp>

#include <memory>

namespace sgfx {

/// Tints the final colour of everything below it: colour = mix(colour, tint.rgb, tint.a).
/// A diagnostic (highlight a subtree) and the smallest example of an effect node.
class SGFX_API DebugTintNode : public EffectNode {
public:
    static std::shared_ptr<DebugTintNode> create(const glm::vec4& tint = {1, 0, 0, 0.5f});

    std::string_view kind() const override { return "debug_tint"; }
    int order() const override { return 1000; } // after every other colour effect
    const ShaderSnippet& snippet() const override;
    void applyUniforms(gl::Program& program, const DrawContext&) const override;

    /// Throws std::invalid_argument for non-finite values or alpha outside [0, 1]; the old tint stays.
    void setTint(const glm::vec4& tint);
    const glm::vec4& tint() const { return tint_; }

private:
    glm::vec4 tint_{1, 0, 0, 0.5f};
};

} // namespace sgfx

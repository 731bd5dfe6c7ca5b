#include <sgfx/nodes/debugtint/DebugTintNode.h>

#include "EmbeddedShaders.h"

#include <sgfx/gl/Objects.h>

#include <cmath>
#include <stdexcept>

namespace sgfx {

std::shared_ptr<DebugTintNode> DebugTintNode::create(const glm::vec4& tint) {
    auto n = std::make_shared<DebugTintNode>();
    n->setTint(tint);
    return n;
}

const ShaderSnippet& DebugTintNode::snippet() const {
    static const ShaderSnippet s{.name = "debug_tint",
                                 .defines = {},
                                 .vertexDecl = {},
                                 .vertexCode = {},
                                 .fragmentDecl =
                                     std::string(nodes::shaders::embedded("debug_tint_decl.glsl")),
                                 .ambientCode = {},
                                 .transmittedCode = {},
                                 .colorCode = std::string(nodes::shaders::embedded("debug_tint_color.glsl")),
                                 .samplers = {}};
    return s;
}

void DebugTintNode::applyUniforms(gl::Program& program, const DrawContext&) const {
    program.set("sgfx_debugTint", tint_);
}

void DebugTintNode::setTint(const glm::vec4& t) {
    for (int i = 0; i < 4; ++i)
        if (!std::isfinite(t[i]))
            throw std::invalid_argument("sgfx: DebugTintNode::setTint: component " + std::to_string(i) +
                                        " is not finite");
    if (t.a < 0.0f || t.a > 1.0f)
        throw std::invalid_argument("sgfx: DebugTintNode::setTint: amount (alpha) " + std::to_string(t.a) +
                                    " must be in [0, 1]");
    tint_ = t;
}

} // namespace sgfx

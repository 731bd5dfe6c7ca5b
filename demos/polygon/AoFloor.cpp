#include "AoFloor.h"

#include <sgfx/FrameSetup.h>
#include <sgfx/PassCommands.h>
#include <sgfx/ShaderComposer.h>

#include <string>

namespace polygon {

namespace {

constexpr const char* kMap = "ao_floor.map";

// Reads the depth once per texel so the pass depends on the pre-pass; writes k = 0.
constexpr const char* kFragment = R"(#version 450 core
layout(location = 0) out vec2 sgfx_fragColor;
uniform sampler2D sgfx_aoFloorDepth;
void main() {
    float z = texelFetch(sgfx_aoFloorDepth, min(ivec2(gl_FragCoord.xy) * 2, textureSize(sgfx_aoFloorDepth, 0) - 1), 0).r;
    sgfx_fragColor = vec2(0.0, z);
}
)";

} // namespace

const sgfx::ShaderSnippet& AoFloorNode::snippet() const {
    static const sgfx::ShaderSnippet s{.name = "ao_floor",
                                       .defines = {},
                                       .vertexDecl = {},
                                       .vertexCode = {},
                                       .fragmentDecl = "uniform sampler2D sgfx_aoFloorMap;\n",
                                       // The least any AO does in the material: read k once.
                                       .ambientCode =
                                           "// blended surfaces are not in the pre-pass\n#ifndef SGFX_BLEND\n"
                                           "sgfx_indirect *= 1.0 - texelFetch(sgfx_aoFloorMap, "
                                           "ivec2(gl_FragCoord.xy) / 2, 0).r;\n"
                                           "#endif\n",
                                       .transmittedCode = {},
                                       .colorCode = {},
                                       .samplers = {{"sgfx_aoFloorMap", kMap}}};
    return s;
}

void AoFloorNode::setupFrame(sgfx::FrameSetup& f) const {
    if (!f.once("ao floor")) return;
    f.requestSceneDepth({.when = sgfx::PassPhase::BeforeMain});
    struct Data {
        sgfx::ResourceId depth, map;
    };
    f.addPass<Data>(
        "ao floor", sgfx::PassPhase::BeforeMain,
        [](sgfx::PassBuilder& b, Data& d) {
            d.depth = b.sample(b.get(sgfx::resources::SceneDepth), "sgfx_aoFloorDepth");
            const sgfx::TextureDesc desc{.format = sgfx::format::Rg32F,
                                         .size = sgfx::SizeRule::half(sgfx::SizeRule::Round::Up)};
            d.map = b.colour(b.create(kMap, desc), 0, false);
            b.publish(kMap, d.map);
        },
        [](sgfx::PassCommands& c, const Data& d) {
            static const sgfx::BaseShader base{"ao_floor", "blit.vert",
                                               std::string(sgfx::ShaderComposer::fullscreenVertex()),
                                               "ao_floor.frag", kFragment};
            sgfx::gl::Program& program = c.program(base);
            c.target({d.map});
            c.bind(program, "sgfx_aoFloorDepth", d.depth);
            c.fullscreen(program);
        });
}

} // namespace polygon

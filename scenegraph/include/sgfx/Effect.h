#pragma once
#include "sgfx/Export.h"
#include "sgfx/Group.h"
#include "sgfx/StateSet.h"

#include <string>
#include <string_view>
#include <vector>

namespace sgfx {

namespace gl {
class Program;
}
class FramePlan;
class FrameSetup;
class Renderer;
struct DrawContext;

/// A sampler of a snippet that reads a frame resource (the fog's nearest depth, the occlusion
/// map): the renderer binds the resource published under `resource` to the uniform `uniform` on a
/// unit it chooses, and the main pass's frame-graph node reads the resource. With `nodeTexture`
/// it binds the node's own texture instead (EffectNode::texture(resource): lookup tables,
/// environment maps made in compile()), which is no frame resource.
struct SGFX_API SnippetSampler {
    std::string uniform;  ///< `uniform sampler2D <uniform>;` (or samplerCube) in the declarations
    std::string resource; ///< blackboard name (see FrameSetup.h), or the node's name for it
    bool nodeTexture = false;
    /// A depth resource read with hardware comparison (shadow maps): it is bound with the
    /// renderer's depth-comparison sampler object (GL_TEXTURE_COMPARE_MODE =
    /// GL_COMPARE_REF_TO_TEXTURE, GL_LEQUAL: 1 where the reference is at most the stored depth;
    /// GL_LINEAR both ways, a 2×2 percentage-closer filter; clamped to the edges), so `uniform` is a
    /// `sampler2DShadow`. The same resource may be listed again without it for a plain read
    /// (`sampler2D`, blocker search): that unit gets no sampler object and reads with the
    /// texture's own state (its TextureDesc filter, nearest by default).
    bool comparison = false;
};

/// GLSL an effect contributes at the material's hook points. Every field may be empty.
///  vertexDecl/fragmentDecl: uniforms, varyings, functions (file scope)
///  vertexCode:   runs after the world position is known; may read/write
///                `vec3 sgfx_worldPos`, `vec3 sgfx_worldNormal`, `vec4 sgfx_viewPos`
///  ambientCode:  may modify `vec3 sgfx_ambient` (the ambient light term) and `float
///                sgfx_indirect` (scales all indirect light: ambient and environment)
///  transmittedCode: may modify `vec3 sgfx_transmitted`, the scene seen through a transmissive
///                surface (Material::transmission) as the copy of the opaque scene shows it, i.e.
///                as the eye sees it: an effect that changes light between eye and surface takes
///                its share out here so it is not applied twice (Forward fog does);
///                `vec3 sgfx_worldPos` and `vec3 sgfx_eyePos` are available.
///  colorCode:    may modify `vec4 sgfx_color` (final linear colour, before output);
///                `vec3 sgfx_worldPos` and `vec3 sgfx_eyePos` are available.
struct SGFX_API ShaderSnippet {
    std::string name; ///< identifies the code: equal names must mean equal code
    std::string defines;
    std::string vertexDecl;
    std::string vertexCode;
    std::string fragmentDecl;
    std::string ambientCode;
    std::string transmittedCode;
    std::string colorCode;
    std::vector<SnippetSampler> samplers;
};

/// A Group whose subtree gets an effect. The core knows effects only through this interface.
/// Nested effects of the same kind: the inner one wins for its subtree.
class SGFX_API EffectNode : public Group {
public:
    void accept(NodeVisitor& v) override;

    virtual std::string_view kind() const = 0;
    /// Lower runs first at a hook (e.g. AO before fog).
    virtual int order() const { return 0; }
    virtual const ShaderSnippet& snippet() const = 0;
    /// Called once per view and frame while the node is visible: declares the passes the effect
    /// adds and what they read and write (see FrameSetup.h). No GL, no change to the node.
    virtual void setupFrame(FrameSetup&) const {}
    /// Makes or updates the node's own GPU objects (noise, lookup data) for the view about to be
    /// drawn: called after setup and before the frame's passes run (VulkanSceneGraph's compile
    /// traversal), so no pass or draw creates them. GL is current.
    virtual void compile(Renderer&) const {}
    /// Sets this effect's uniforms on a program that contains its snippet.
    virtual void applyUniforms(gl::Program&, const DrawContext&) const {}
    /// The GL texture the node made in compile() for a SnippetSampler with `nodeTexture` (0: none
    /// yet, the sampler reads nothing).
    virtual unsigned texture(std::string_view /*resource*/) const { return 0; }
    /// Whether this effect draws the blended items below it that use `mode` itself (in a pass of
    /// its own, from RenderQueue::claimed) instead of the main pass's sorted transparent stage.
    virtual bool drawsBlended(BlendMode) const { return false; }
    /// The node masks this effect applies to: a node below it whose nodeMask shares no bit with
    /// this mask drops the effect for its own subtree (a shadow's "receives" bit). ~0: every node.
    virtual NodeMask subtreeMask() const { return ~NodeMask{0}; }
    /// Deletes the GL objects the node's passes made (targets, noise textures) while their context
    /// is current; the next frame, in whatever viewer, makes them again. Called by ~Viewer, so a
    /// scene may outlive the viewer that drew it and be drawn by another (OSG's releaseGLObjects).
    virtual void releaseGLObjects() {}
    bool enabled = true;
};

} // namespace sgfx

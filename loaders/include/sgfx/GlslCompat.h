#pragma once
/// @file
/// OpenSceneGraph's compatibility-profile GLSL (1.10–1.30 with gl_Vertex, gl_ModelViewMatrix,
/// gl_FragColor, ...) translated into GLSL 450 core foreign programs, by textual replacement at
/// identifier boundaries as OSG's own vertex-attribute aliasing does
/// (State::convertVertexShaderSourceToOsgBuiltIns). Pure text: no GL, no OpenSceneGraph.
#include "sgfx/Export.h"
#include "sgfx/ShaderComposer.h"
#include "sgfx/StateSet.h"

#include <glm/glm.hpp>

#include <map>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace sgfx {

/// The stage of one osg::Shader. Only Vertex and Fragment are translated.
enum class CompatStage { Vertex, Fragment, Geometry, TessControl, TessEvaluation, Compute };

/// One osg::Shader of an osg::Program. Several of one stage are joined in order (a function
/// library followed by the shader with `main`).
struct SGFX_API CompatShader {
    CompatStage stage = CompatStage::Vertex;
    std::string source;
};

/// A sampler uniform the sources declare: the converter binds the osg texture of the unit the
/// osg::Uniform of this name selects with StateSet::setTexture(name, texture).
struct SGFX_API CompatSampler {
    std::string name;
    std::string type;  ///< GLSL type as declared: "sampler2D", "samplerCube", "sampler2DShadow"...
    int arraySize = 0; ///< 0: not an array
    bool operator==(const CompatSampler&) const = default;
};

/// A translated program.
struct SGFX_API CompatProgram {
    std::shared_ptr<ShaderProgram> program;
    std::vector<CompatSampler> samplers;
    /// What the translation approximates or leaves to the application (one line each).
    std::vector<std::string> notes;
    /// The sources read gl_FrontMaterial, gl_BackMaterial or their light products: set
    /// compatMaterialUniforms() from the osg::Material in force.
    bool usesMaterial = false;
};

/// Thrown for what cannot be translated; what() names the program, the stage, the line and the
/// construct ("sgfx: OSG program 'brick', vertex shader line 12: `gl_FogCoord` ...").
class SGFX_API CompatError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

struct SGFX_API CompatOptions {
    /// osg::Program's attribute bindings (name → location) for the shaders' own attributes;
    /// sgfx feeds 0 position, 1 normal, 2 tangent, 3 texcoord 0, 4 colour, 5 texcoord 1.
    std::map<std::string, int, std::less<>> attributeLocations;
};

/// Translates an osg::Program. A missing vertex or fragment stage gets the fixed-function
/// stand-in (ftransform, gl_FrontColor = gl_Color, gl_TexCoord[0] = gl_MultiTexCoord0;
/// gl_FragColor = gl_Color). Throws CompatError for geometry/tessellation/compute stages and for
/// built-ins without an sgfx equivalent.
SGFX_API CompatProgram translateCompatibilityProgram(std::string name, std::span<const CompatShader> shaders,
                                                     const CompatOptions& options = {});
/// The same for one vertex and one fragment source (either may be empty: the stand-in).
SGFX_API CompatProgram translateCompatibilityProgram(std::string name, std::string_view vertex,
                                                     std::string_view fragment);

/// Uniforms behind gl_FrontMaterial / gl_BackMaterial (GL's default material until set).
namespace compat_uniforms {
inline constexpr const char* kFrontAmbient = "osg_FrontMaterialAmbient";
inline constexpr const char* kFrontDiffuse = "osg_FrontMaterialDiffuse";
inline constexpr const char* kFrontSpecular = "osg_FrontMaterialSpecular";
inline constexpr const char* kFrontEmission = "osg_FrontMaterialEmission";
inline constexpr const char* kFrontShininess = "osg_FrontMaterialShininess";
inline constexpr const char* kBackAmbient = "osg_BackMaterialAmbient";
inline constexpr const char* kBackDiffuse = "osg_BackMaterialDiffuse";
inline constexpr const char* kBackSpecular = "osg_BackMaterialSpecular";
inline constexpr const char* kBackEmission = "osg_BackMaterialEmission";
inline constexpr const char* kBackShininess = "osg_BackMaterialShininess";
} // namespace compat_uniforms

/// One face of an osg::Material; the defaults are GL's.
struct SGFX_API CompatMaterial {
    glm::vec4 ambient{0.2f, 0.2f, 0.2f, 1.0f};
    glm::vec4 diffuse{0.8f, 0.8f, 0.8f, 1.0f};
    glm::vec4 specular{0.0f, 0.0f, 0.0f, 1.0f};
    glm::vec4 emission{0.0f, 0.0f, 0.0f, 1.0f};
    float shininess = 0.0f;
};

/// The (name, value) pairs for StateSet::setUniform that gl_FrontMaterial and gl_BackMaterial read.
SGFX_API std::vector<std::pair<std::string, UniformValue>> compatMaterialUniforms(const CompatMaterial& front,
                                                                                  const CompatMaterial& back);

} // namespace sgfx

#pragma once
// The OpenSceneGraph bridge's insides (loadOsg): one conversion context shared by the node,
// geometry and state converters. Internal to sgfx_loaders; OSG headers only here and in osg/*.cpp.
#include <sgfx/Geometry.h>
#include <sgfx/GlslCompat.h>
#include <sgfx/Group.h>
#include <sgfx/OsgLoader.h>
#include <sgfx/ShaderComposer.h>
#include <sgfx/StateSet.h>

#include <osg/Geometry>
#include <osg/Material>
#include <osg/Node>
#include <osg/Program>
#include <osg/StateSet>
#include <osg/Texture>

#include <map>
#include <memory>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

namespace sgfx::osgbridge {

/// The fixed-function state in force at a point of the osg graph: what the built-in material (or
/// the fixed-function emulation shader) of a Geometry is made from. OSG's defaults are those of
/// osgViewer's SceneView: lighting on, a Material whose colour mode is AMBIENT_AND_DIFFUSE.
struct FixedState {
    const osg::Material* material = nullptr; ///< null: SceneView's default
    bool lighting = true;
    const osg::Texture* texture0 = nullptr; ///< unit 0, when GL_TEXTURE_2D (or the cube map) is on
    int texEnv = 0;                         ///< GL_MODULATE, GL_REPLACE, GL_DECAL, GL_BLEND (0: modulate)
    int texGen = 0;                         ///< 0, or osg::TexGen::SPHERE_MAP / REFLECTION_MAP
    std::optional<float> alphaCutoff;       ///< AlphaFunc GREATER/GEQUAL with GL_ALPHA_TEST on
    bool twoSided = false;                  ///< LightModel
    bool flat = false;                      ///< ShadeModel FLAT
    int polygonMode = 0;                    ///< PolygonMode GL_LINE / GL_POINT (front faces' mode), 0: fill
    const osg::Program* program = nullptr;  ///< an osg::Program in force (foreign shader)
    std::map<int, const osg::Texture*> textures; ///< every unit's texture, for programs' samplers
    std::map<std::string, int> samplerUnits;     ///< int uniforms naming a program's sampler
    bool operator<(const FixedState& o) const;
};

/// Everything one load shares: caches (shared osg objects stay shared), warnings, limits.
struct Context {
    std::filesystem::path file;
    OsgOptions options;
    std::size_t bytes = 0; ///< vertex, index and image bytes made so far

    std::map<std::pair<const osg::Node*, FixedState>, NodePtr> nodes;
    std::map<std::tuple<const osg::Geometry*, bool, bool, int>, std::vector<std::shared_ptr<Geometry>>>
        geometries;
    std::map<const osg::Image*, std::shared_ptr<Texture>> textureImages; ///< per (image) + sampling
    std::map<const osg::Texture*, std::shared_ptr<Texture>> textures;
    std::map<const osg::Program*, std::optional<CompatProgram>> programs;
    std::map<FixedState, std::shared_ptr<Material>> materials;
    std::map<FixedState, std::shared_ptr<ShaderProgram>> fixedPrograms;
    std::vector<std::string> samplerNames; ///< every sampler any program of the file declares

    /// Warnings by what was not converted: the first node path and the count.
    struct Warning {
        std::string where;
        std::size_t count = 0;
    };
    std::map<std::string, Warning> warnings;
    std::vector<std::string> path; ///< node names from the root, for warnings

    void warn(const std::string& what);
    std::string where() const;
    /// Adds `n` bytes to the load's total; LoadError past options.memoryLimit.
    void charge(std::size_t n, const char* what);
};

/// osg nodes → sgfx nodes (OsgNodes.cpp). Shared nodes convert once.
NodePtr convertNode(Context& cx, const osg::Node& node, const FixedState& parent);
/// osg::Geometry → one sgfx Geometry per primitive kind (triangles, lines, points), without state.
/// What of the fixed-function state changes a Geometry's arrays.
struct GeometryShape {
    bool colors = true;  ///< keep the vertex colours (the Material's colour mode uses them)
    bool flat = false;   ///< ShadeModel FLAT: normals and colours of each triangle's provoking vertex
    int polygonMode = 0; ///< PolygonMode GL_LINE or GL_POINT (0: filled)
};
std::vector<std::shared_ptr<Geometry>> convertGeometry(Context& cx, const osg::Geometry& g,
                                                       const GeometryShape& shape);
/// A node's osg StateSet → the sgfx StateSet of its pipeline state (blend, depth, cull, bin,
/// uniforms, program); `state` is updated with the fixed-function state it sets.
std::shared_ptr<StateSet> convertStateSet(Context& cx, const osg::StateSet& s, FixedState& state);
/// The state a Geometry's own StateSet gets from the fixed-function state in force: the built-in
/// material, or the emulation program with its uniforms and textures, or a program's samplers.
void applyFixedState(Context& cx, const FixedState& state, StateSet& out, const Geometry& geometry);
/// Whether the geometry keeps its vertex colours under `state` (Material's colour mode).
bool usesVertexColors(const FixedState& state);
/// The fixed-function emulation shader for what the built-in material cannot do (TexGen sphere
/// and reflection maps, texture environments REPLACE/DECAL/BLEND): OsgFixedFunction.cpp.
std::shared_ptr<ShaderProgram> fixedFunctionProgram(const FixedState& state);
bool needsFixedFunctionProgram(const FixedState& state);
bool isCube(const FixedState& state); ///< texture0 is a cube map (sampled through its panorama)
/// sRGB display value → linear (IEC 61966-2-1); OSG colours are display values.
float srgbToLinear(float s);
glm::vec4 linearColor(const osg::Vec4& c);

} // namespace sgfx::osgbridge

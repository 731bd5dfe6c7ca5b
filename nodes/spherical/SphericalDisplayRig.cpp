#include "sgfx/nodes/spherical/SphericalDisplayRig.h"

#include "EmbeddedShaders.h"
#include "sgfx/ShaderComposer.h"
#include "sgfx/StateSet.h"

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <stdexcept>
#include <string>

namespace sgfx {

namespace {

void require(bool ok, const std::string& what) {
    if (!ok) throw std::invalid_argument("SphericalDisplaySetup: " + what);
}

// Eye view space (looking down −Z, +Y up) → display frame (+Y forward, +Z up, +X right), OSG's
// frame for the cube faces (SphericalDisplay::configure: the front face is +Y, the top +Z).
glm::mat4 displayFromEye() {
    return glm::mat4(glm::vec4(1, 0, 0, 0), glm::vec4(0, 0, 1, 0), glm::vec4(0, -1, 0, 0),
                     glm::vec4(0, 0, 0, 1));
}

std::shared_ptr<ShaderProgram> warpProgram() {
    using nodes::shaders::embedded;
    std::string frag = "#version 450 core\n";
    frag += embedded("spherical_faces.glsl");
    frag += embedded("spherical_intensity.glsl");
    frag += embedded("spherical_warp.frag");
    return ShaderProgram::create("spherical_warp", std::string(embedded("spherical_warp.vert")), frag);
}

std::shared_ptr<Geometry> warpGeometry(const SphericalDisplayParams& p, const SphericalDisplaySetup& s) {
    const WarpMesh m = sphericalWarpMesh(p, s.width, s.height, s.meshSteps);
    auto g = Geometry::create();
    g->name = "spherical display mesh";
    for (const WarpVertex& v : m.vertices) {
        // Straight to clip space: the mesh is the whole projector image, whatever the camera.
        g->positions.emplace_back(2.0f * v.pixel.x / float(s.width) - 1.0f,
                                  2.0f * v.pixel.y / float(s.height) - 1.0f, 0.0f);
        g->normals.push_back(v.direction);
        g->texcoords.emplace_back(v.angleDeg, 0.0f);
    }
    g->indices = m.indices;
    g->setCullingActive(false);
    StateSet& ss = g->getOrCreateStateSet();
    ss.program.set(warpProgram());
    ss.cullFace.set(CullFace::None); // OSG's panoramic mesh mixes windings and switches culling off too
    ss.setUniform("sphere_intensityCount", int(p.intensityMap.size()));
    // The 3D mesh's angle is clamped at the rim, a kink linear interpolation would smooth (OSG
    // interpolates its per-vertex intensities): read it per pixel instead.
    const bool perPixel = p.kind == SphericalDisplayKind::ThreeD;
    ss.setUniform("sphere_pixelAngle", glm::vec4(0.5f * float(s.width), 0.5f * float(s.height),
                                                 0.5f * float(s.height), perPixel ? 1.0f : 0.0f));
    for (std::size_t i = 0; i < p.intensityMap.size(); ++i)
        ss.setUniform("sphere_intensity[" + std::to_string(i) + "]",
                      glm::vec2(p.intensityMap[i].angleDeg, p.intensityMap[i].percent));
    return g;
}

} // namespace

void SphericalDisplaySetup::validate() const {
    require(width >= 1 && width <= 16384 && height >= 1 && height <= 16384,
            "width and height must be in 1..16384, got " + std::to_string(width) + "x" +
                std::to_string(height));
    require(faceSize >= 1 && faceSize <= 8192,
            "faceSize must be in 1..8192, got " + std::to_string(faceSize));
    require(std::isfinite(zNear) && std::isfinite(zFar) && zNear > 0.0f && zFar > zNear,
            "need 0 < zNear < zFar, finite");
    require(meshSteps == 0 || (meshSteps >= 2 && meshSteps <= 1024),
            "meshSteps must be 0 or in 2..1024, got " + std::to_string(meshSteps));
}

glm::mat4 SphericalDisplayRig::faceRotation(int face) {
    static const glm::vec3 axis[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    static const glm::vec3 up[6] = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, -1, 0}, {0, 1, 0}};
    if (face < 0 || face > 5)
        throw std::invalid_argument("SphericalDisplayRig::faceRotation: face must be 0..5");
    return glm::lookAt(glm::vec3(0.0f), axis[face], up[face]);
}

std::shared_ptr<SphericalDisplayRig> SphericalDisplayRig::create(const SphericalDisplayParams& params,
                                                                 const SphericalDisplaySetup& setup,
                                                                 NodePtr scene) {
    params.validate();
    setup.validate();
    if (!scene) throw std::invalid_argument("SphericalDisplayRig: no scene");
    auto rig = std::make_shared<SphericalDisplayRig>();
    rig->params_ = params;
    rig->setup_ = setup;
    rig->root_ = Group::create();
    rig->root_->name = "spherical display";
    rig->mesh_ = warpGeometry(params, setup);
    StateSet& ss = rig->mesh_->getOrCreateStateSet();
    for (int f = 0; f < 6; ++f) {
        auto cam = Camera::create();
        cam->name = "spherical display face " + std::to_string(f);
        cam->setViewport(0, 0, setup.faceSize, setup.faceSize);
        cam->setPerspective(90.0f, setup.zNear, setup.zFar);
        cam->renderTarget = Texture::create(nullptr);
        cam->renderTarget->minFilter = Filter::Linear;
        cam->renderTarget->wrapS = cam->renderTarget->wrapT = Wrap::ClampToEdge;
        cam->setCullingActive(false); // its bound is the scene's, wherever the output camera looks
        cam->addChild(scene);
        const std::string n = std::to_string(f);
        ss.setTexture("sphere_face" + n, cam->renderTarget);
        ss.setUniform("sphere_faceMatrix" + n, cam->projectionMatrix * faceRotation(f));
        rig->root_->addChild(cam);
        rig->faces_[std::size_t(f)] = cam;
    }
    rig->root_->addChild(rig->mesh_);
    rig->setEyeView(glm::lookAt(glm::vec3(0.0f), glm::vec3(0, 1, 0), glm::vec3(0, 0, 1)));
    return rig;
}

void SphericalDisplayRig::setEyeView(const glm::mat4& view) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (!std::isfinite(view[c][r]))
                throw std::invalid_argument("SphericalDisplayRig::setEyeView: non-finite matrix");
    if (!(std::abs(glm::determinant(glm::mat3(view))) > 1e-12f))
        throw std::invalid_argument("SphericalDisplayRig::setEyeView: singular matrix");
    const glm::mat4 world = displayFromEye() * view;
    for (int f = 0; f < 6; ++f)
        faces_[std::size_t(f)]->viewMatrix = faceRotation(f) * world;
}

void SphericalDisplayRig::configureOutputCamera(Camera& output) const {
    output.setViewport(0, 0, setup_.width, setup_.height);
    output.clearColor = {0.0f, 0.0f, 0.0f, 1.0f};
    output.viewMatrix = glm::mat4(1.0f);
    output.projectionMatrix = glm::mat4(1.0f);
}

} // namespace sgfx

// The docs' code snippets that are not excerpts of a demo or a test, compiled (and linked) with the
// build so that they stay true to the API. Each function holds one ```cpp block of a page verbatim
// between the "docs:" and "end" marker comments; lines outside the markers set up the names the
// snippet uses. tests/doc_snippets_check.cmake (test docs_snippets_compiled) fails when a block in
// README.md, docs/*.md or docs/effects/*.md is not found, line for line, in demos/ or tests/.
// The functions are compiled, not run: they would need a display, a GPU or files such as truck.glb.
// A snippet's own #include lines sit inside the function body; the headers are already included
// here (every sgfx header is #pragma once), so they expand to nothing there.
#include <sgfx/GraphicsContext.h>
#include <sgfx/ModelLoader.h>
#include <sgfx/Queries.h>
#include <sgfx/Shapes.h>
#include <sgfx/Viewer.h>
#include <sgfx/nodes/ao/AmbientOcclusionNode.h>
#include <sgfx/nodes/debugtint/DebugTintNode.h>
#include <sgfx/nodes/environment/EnvironmentLightNode.h>
#include <sgfx/nodes/fog/FogNode.h>
#include <sgfx/nodes/particles/ParticleSystemNode.h>
#include <sgfx/nodes/sky/SkyNode.h>
#include <sgfx/nodes/transparency/TransparencyBin.h>
#include <sgfx/nodes/volume/VolumeNode.h>

#include <glm/gtc/matrix_transform.hpp>

#include <cstdio>
#include <functional>
#include <memory>

namespace doc_snippets {

// ---- docs/queries.md

void queriesHelpers(const sgfx::NodePtr& scene, const std::unique_ptr<sgfx::Viewer>& viewer, double x, double y,
                    const glm::dvec3& sensor, const glm::dvec3& target, double mouseX, double mouseY) {
    // docs: queries.md, The helpers
    #include <sgfx/Queries.h>

    // Terrain following: the highest surface under a world point (Z up).
    std::optional<double> z = sgfx::heightOfTerrain(*scene, x, y);
    std::optional<sgfx::Intersection> ground = sgfx::terrainHit(*scene, x, y); // with the normal

    // Line of sight: true when no triangle lies between the two world points. Stops at the first hit.
    bool visible = sgfx::lineOfSight(*scene, sensor, target);

    // Picking: the nearest triangle under a pixel (origin top left, like mouse coordinates).
    if (auto p = sgfx::pick(*viewer, mouseX, mouseY)) {
        const glm::dvec3 point = p->hit.point;   // world
        const glm::dvec3 normal = p->hit.normal; // interpolated, world
        for (const sgfx::Node* n : p->hit.nodePath) // from the scene root down to the Geometry
            std::printf("/%s", n->name.c_str());
        std::printf(" at (%g, %g, %g), normal (%g, %g, %g)\n", point.x, point.y, point.z, normal.x, normal.y,
                    normal.z);
    }
    // end
    (void)z;
    (void)ground;
    (void)visible;
}

void queriesVisitor(const sgfx::NodePtr& scene, const glm::dvec3& start, const glm::dvec3& end,
                    sgfx::NodeMask queryMask) {
    // docs: queries.md, Intersectors and the visitor
    sgfx::LineSegmentIntersector line(start, end);
    line.limit = sgfx::Intersector::Limit::Nearest; // All (default), Nearest, or Any (stop at the first)
    sgfx::IntersectionVisitor iv(line, queryMask);
    iv.visit(*scene);
    for (const sgfx::Intersection& hit : line.intersections()) // sorted by distance
    std::printf("%s at %g m\n", hit.geometry->name.c_str(), hit.distance);
    // end
}

void queriesThreads(const std::unique_ptr<sgfx::Viewer>& viewer, const sgfx::NodePtr& scene, double dt,
                    const std::function<void()>& startQueries, const std::function<void()>& waitForQueries) {
    // docs: queries.md, Threads
    viewer->update(dt);                 // update callbacks: the scene changes here, on this thread
    sgfx::prepareForQueries(*scene);    // bounds and BVHs rebuilt here, not raced by the query threads
    startQueries();                     // other threads may query from now ...
    viewer->renderFrame();              // ... while this culls and draws (it only reads the graph)
    waitForQueries();                   // ... until here
    // end
}

// ---- docs/guide.md

void guideBuildingAScene() {
    // docs: guide.md, Building a scene
    auto root = sgfx::Group::create();
    auto mover = sgfx::Transform::create(glm::translate(glm::mat4(1), {0, 0, 2}));
    auto box = sgfx::shapes::box({1, 1, 1});          // loaders/: box, quad, cylinder, cone, sphere, heightfield
    mover->addChild(box);                             // a node may have several parents
    root->addChild(mover);
    mover->setMatrix(glm::translate(glm::mat4(1), {0, 0, 3})); // bounds above it are refreshed lazily
    // end
}

void guideState(const sgfx::NodePtr& node, const std::shared_ptr<sgfx::Texture>& texture) {
    auto material = sgfx::Material::create();
    auto debugMaterial = sgfx::Material::create();
    auto paint = sgfx::Material::create();
    // docs: guide.md, State
    auto& ss = node->getOrCreateStateSet();
    ss.material.set(material);                        // Blinn-Phong or metallic-roughness (see Loading
                                                      // models): colours, maps, alphaCutoff
    ss.blend.set(sgfx::BlendMode::Alpha);             // Off, Alpha, Premultiplied, Additive, Multiply
    ss.cullFace.set(sgfx::CullFace::None);
    ss.material.set(debugMaterial, sgfx::Override);   // wins over descendants' plain values
    ss.material.set(paint, sgfx::Protected);          // keeps its value under an Override
    ss.setUniform("myUniform", 0.5f);                 // for foreign shaders
    ss.setTexture("mySampler", texture);
    // end
}

void guideEffectNodes(const sgfx::NodePtr& vehicle) {
    // docs: guide.md, Effect nodes
    auto tint = sgfx::DebugTintNode::create({1, 0, 0, 0.5f});  // colour = mix(colour, red, 0.5)
    tint->addChild(vehicle);
    // end
}

void guideLoadingModels(const std::shared_ptr<sgfx::FogNode>& fogNode) {
    // docs: guide.md, Loading models
#include <sgfx/ModelLoader.h>

    auto model = sgfx::loadModel("truck.glb"); // .gltf .glb .obj .off .ply .stl; throws sgfx::LoadError
    fogNode->addChild(model);
    // end
}

void guideMaterials() {
    // docs: guide.md, Materials
    auto m = sgfx::Material::create();
    m->model = sgfx::ShadingModel::MetallicRoughness;
    m->diffuse = {0.9f, 0.6f, 0.2f, 1.0f}; // base colour, alpha = opacity
    m->metallic = 1.0f;                    // [0, 1], default 0
    m->roughness = 0.35f;                  // [0, 1] perceptual (α = roughness²), default 0.5
    m->mapping(sgfx::MaterialMap::BaseColor).scale = {4.0f, 4.0f}; // tile the base colour map
    // end
}

void guideViewer(const sgfx::NodePtr& root) {
    // docs: guide.md, Viewer, contexts, output
    auto viewer = sgfx::Viewer::createHeadless(1280, 720);           // OSMesa (llvmpipe)
    sgfx::Viewer gpu(std::make_unique<sgfx::EglContext>());          // headless GPU or Mesa surfaceless
    sgfx::Viewer window(std::make_unique<sgfx::GlfwWindow>(1280, 720, "title")); // throws ContextError without a display
    viewer->setSceneData(root);
    viewer->frame(1.0 / 60);                                          // update, cull, render
    viewer->writeScreenshot("out.png");                               // or capture() → sgfx::Image
    viewer->renderer().options().lighting = sgfx::RendererOptions::Lighting::PerVertex; // faster, Gouraud
    const sgfx::FrameStats& s = viewer->stats();                      // draw calls, triangles, state changes
    // end
    std::printf("%u draw calls\n", unsigned(s.drawCalls));
}

// ---- docs/effects/*.md

void antialiasingUsage(const std::shared_ptr<sgfx::Camera>& camera) {
    // docs: effects/antialiasing.md, Usage
    camera->setAntiAliasing(sgfx::AntiAliasing::msaa(4));   // or ssaa(2), fxaa(), taa(), none()
    // end
}

void aoUsage(const sgfx::NodePtr& world) {
    // docs: effects/ao.md, Usage
#include <sgfx/nodes/ao/AmbientOcclusionNode.h>

    auto ao = sgfx::AmbientOcclusionNode::create();   // defaults below
    ao->addChild(world);
    sgfx::AmbientOcclusionParameters p = ao->parameters();
    p.radius = 1.0f;                 // R, metres
    p.samples = 16;                  // m, 8..64
    p.halfResolution = true;         // occlusion and blur at half size, depth-aware upsampling
    ao->setParameters(p);            // validated: throws std::invalid_argument, keeps the old values
    ao->setParameters(sgfx::AmbientOcclusionParameters::paper());  // the seed's method as published
    // end
}

void fogUsage(const sgfx::NodePtr& world) {
    // docs: effects/fog.md, Usage
#include <sgfx/nodes/fog/FogNode.h>

    auto fog = sgfx::FogNode::create(sgfx::FogParameters::ground());  // or ::solid()
    fog->addChild(world);              // everything below is fogged: built-in, glTF, foreign shaders
    sgfx::FogParameters p = fog->parameters();
    p.density = 2e-3f;                 // ρ0 per metre at the reference height
    p.falloff = 4.5e-3f;               // b per metre (0 = uniform fog)
    p.color = {0.7f, 0.74f, 0.8f};     // linear RGB
    p.referenceHeight = 120.0f;        // the plane where ρ = ρ0 (metres along `up`)
    p.maxOpacity = 0.9f;               // never hide the scene completely
    fog->setParameters(p);             // validated: throws std::invalid_argument, keeps the old values
    fog->setMode(sgfx::FogMode::ForwardSplit);  // switch at run time
    // end
}

void particlesUsage(const std::shared_ptr<sgfx::FogNode>& fogNode) {
    // docs: effects/particles.md, Usage
#include <sgfx/nodes/particles/ParticleSystemNode.h>

    auto rain = sgfx::ParticleSystemNode::rain({80.0f, 80.0f}, 200000); // area (m), drops
    auto above = sgfx::Transform::create(glm::translate(glm::mat4(1.0f), {0.0f, 0.0f, 36.0f}));
    above->addChild(rain);                  // the emitter is the node's z = 0 plane
    fogNode->addChild(above);               // fogged like the rest of the scene

    sgfx::ParticleSettings s = rain->settings();
    s.emitter.velocity = {3.0f, 0.0f, -9.0f};   // wind; validated, throws and keeps the old settings
    s.capacity = 400000;                         // grows without losing the drops in flight
    rain->setSettings(s);
    rain->timeScale = 0.5f;                      // slow motion; `paused`, `reset()` too
    // end
}

void transparencyUsage(const sgfx::NodePtr& canopy) {
    // docs: effects/transparency.md, Usage
#include <sgfx/nodes/transparency/TransparencyBin.h>

    auto glass = sgfx::TransparencyBin::create();          // Sorted (default)
    glass->addChild(canopy);                               // everything below is in the bin
    glass->setMode(sgfx::TransparencyMode::WeightedBlended);  // switch at run time
    sgfx::OitParameters oit;
    oit.weight = sgfx::OitWeight::Depth7;                  // McGuire & Bavoil eq. 7 (default), 8, 9, 10 or Constant
    oit.depthScale = 10.0f;                                // metres per unit of the paper's z
    glass->setOitParameters(oit);                          // validated; throws, keeps the old values
    // end
}

void volumeUsage(const std::shared_ptr<sgfx::Transform>& place) {
    const glm::vec3 toSun = glm::normalize(glm::vec3(-0.4f, 0.3f, 0.85f));
    // docs: effects/volume-sky.md, Volumes, usage
#include <sgfx/nodes/volume/VolumeNode.h>

    sgfx::VolumeParameters p;
    p.size = {40.0f, 40.0f, 24.0f};        // box (m), centred on the node
    p.absorption = 0.02f;                  // k_a per metre at density 1
    p.scattering = 0.12f;                  // k_s
    p.lightDirection = -toSun;             // the way the sunlight travels
    p.lightColor = glm::vec3(4.0f);
    auto smoke = sgfx::VolumeNode::create(p, sgfx::VolumeGrid::noise(64, /*seed*/ 7, /*octaves*/ 4, /*coverage*/ 0.35f));
    place->addChild(smoke);                // a Transform places, turns and scales the box

    auto scan = sgfx::VolumeNode::create(p, sgfx::VolumeGrid::loadRaw("ct.raw", {256, 256, 128},
                                                                       sgfx::VolumeGrid::Format::R16F));
    auto ball = sgfx::VolumeNode::createFunction(p, "return 1.0 - smoothstep(0.4, 0.5, length(uvw - 0.5));");
    // end
    place->addChild(scan);
    place->addChild(ball);
}

void skyUsage(const std::shared_ptr<sgfx::Group>& root, const std::shared_ptr<sgfx::Light>& sun,
              const std::shared_ptr<sgfx::FogNode>& fogNode) {
    // docs: effects/volume-sky.md, Sky, usage
#include <sgfx/nodes/sky/SkyNode.h>

    auto sky = sgfx::SkyNode::create(sgfx::SkyParameters::atTime(18.5f)); // local solar time, 45°N, midsummer
    root->addChild(sky);
    sky->attachFog(fogNode);  // the fog's colour follows the horizon, and it leaves sky pixels alone
    sun->direction = -sky->parameters().sunDirection;  // light the scene from the same sun
    // end
}

void environmentUsage(const sgfx::NodePtr& world, const std::shared_ptr<sgfx::SkyNode>& sky) {
    // docs: effects/environment.md, usage
#include <sgfx/nodes/environment/EnvironmentLightNode.h>

    auto studio = sgfx::Environment::load("studio.hdr");       // 2:1 panorama, Z up; prefiltered once
    auto light = sgfx::EnvironmentLightNode::create(studio);    // every material below it
    light->addChild(world);
    light->setIntensity(0.8f);                                  // validated; the old value stays on error
    auto skyLight = sgfx::EnvironmentLightNode::create(sky);    // the sky's light, again when the sun moves
    // end
    skyLight->addChild(world);
}

// ---- docs/materials.md

sgfx::Material materialsTransmission() {
    // docs: materials.md, Transmission
    auto canopy = sgfx::Material::create();
    canopy->model = sgfx::ShadingModel::MetallicRoughness;
    canopy->diffuse = {0.95f, 0.97f, 1.0f, 1.0f}; // tints what is seen through it
    canopy->roughness = 0.05f;
    canopy->transmission = 1.0f;                  // all of the diffuse part lets light through
    canopy->ior = 1.5f;                           // F0 = 0.04; how far light bends
    canopy->thickness = 0.01f;                    // metres in the mesh's own units
    canopy->attenuationColor = {0.9f, 0.97f, 0.95f};
    canopy->attenuationDistance = 0.05f;          // Beer–Lambert: 0.9 of red left after 5 cm
    // end
    return *canopy;
}

} // namespace doc_snippets

// Compiled and linked with the build; the snippets are not run (see the top of the file).
int main() {
    std::printf("doc_snippets: the docs' snippets compile and link; run nothing\n");
    return 0;
}

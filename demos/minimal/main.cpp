// The minimal example: a model under a FogNode, rendered headless to a PNG.
// Usage: minimal MODEL [PNG]   (glTF, OBJ, OFF, PLY or STL; the PNG defaults to minimal.png)
#include <sgfx/Manipulator.h>
#include <sgfx/ModelLoader.h>
#include <sgfx/Viewer.h>
#include <sgfx/Visitors.h>
#include <sgfx/nodes/fog/FogNode.h>

#include <cstdio>
#include <exception>
#include <stdexcept>
#include <string>

int main(int argc, char** argv) try {
    if (argc < 2) throw std::runtime_error("usage: minimal MODEL [PNG]");
    const std::string out = argc > 2 ? argv[2] : "minimal.png";
    auto model = sgfx::loadModel(argv[1]); // throws sgfx::LoadError naming the file
    sgfx::ComputeBoundsVisitor bounds;
    model->accept(bounds);
    sgfx::OrbitManipulator camera; // frames the model's bounds in a 40° view
    camera.home(bounds.min, bounds.max, 40.0f, 512.0f / 384.0f);
    const float radius = camera.sceneRadius();

    sgfx::FogParameters fogParameters; // uniform fog: about a third of the light lost at the model
    fogParameters.density = 0.15f / radius;
    auto fog = sgfx::FogNode::create(fogParameters);
    fog->addChild(model);
    auto sun = sgfx::Light::create(sgfx::LightType::Directional);
    sun->direction = {-0.4f, 0.3f, -0.85f};
    auto sky = sgfx::Light::create(sgfx::LightType::Ambient);
    sky->color = glm::vec3(0.35f);
    fog->addChild(sun);
    fog->addChild(sky);

    auto viewer = sgfx::Viewer::createHeadless(512, 384);
    viewer->setSceneData(fog);
    viewer->camera()->setPerspective(40.0f, 0.05f * radius, 20.0f * radius);
    camera.apply(*viewer->camera());
    viewer->frame();
    viewer->writeScreenshot(out);
    std::printf("wrote %s (512x384)\n", out.c_str());
    return 0;
} catch (const std::exception& e) {
    std::fprintf(stderr, "minimal: %s\n", e.what());
    return 1;
}

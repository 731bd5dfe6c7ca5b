// The README's example: build a small scene in code and render it headless to hello.png.
#include <sgfx/Shapes.h>
#include <sgfx/Viewer.h>
#include <sgfx/nodes/debugtint/DebugTintNode.h>

#include <glm/gtc/matrix_transform.hpp>

int main() {
    auto root = sgfx::Group::create();

    auto sun = sgfx::Light::create(sgfx::LightType::Directional);
    sun->direction = {-0.4f, -0.3f, -0.85f};
    auto sky = sgfx::Light::create(sgfx::LightType::Ambient);
    sky->color = glm::vec3(0.3f);
    root->addChild(sun);
    root->addChild(sky);

    auto ground = sgfx::shapes::quad(40.0f, 40.0f);
    ground->getOrCreateStateSet().material.set(sgfx::Material::create());
    root->addChild(ground);

    auto crate = sgfx::shapes::box({2, 2, 2});
    auto red = sgfx::Material::create();
    red->diffuse = {0.8f, 0.1f, 0.1f, 1.0f};
    crate->getOrCreateStateSet().material.set(red);
    for (int i = 0; i < 5; ++i) { // one geometry, five placements
        auto t = sgfx::Transform::create(glm::translate(glm::mat4(1.0f), {i * 4.0f - 8.0f, 0.0f, 1.0f}));
        t->addChild(crate);
        root->addChild(t);
    }
    auto highlight = sgfx::DebugTintNode::create({1, 1, 0, 0.5f}); // an effect node: tints its subtree
    auto spot = sgfx::Transform::create(glm::translate(glm::mat4(1.0f), {0, 6, 1}));
    spot->addChild(crate);
    highlight->addChild(spot);
    root->addChild(highlight);

    auto viewer = sgfx::Viewer::createHeadless(640, 360);
    viewer->setSceneData(root);
    viewer->camera()->setLookAt({12, -18, 10}, {0, 2, 0});
    viewer->frame();
    viewer->writeScreenshot("hello.png");
}

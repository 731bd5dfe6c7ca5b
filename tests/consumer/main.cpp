// Renders a lit box headless through an installed sgfx and checks the centre pixel is lit.
#include <sgfx/Shapes.h>
#include <sgfx/Viewer.h>
#include <sgfx/nodes/debugtint/DebugTintNode.h>

#include <cstdio>

int main() {
    auto viewer = sgfx::Viewer::createHeadless(32, 32);
    auto tint = sgfx::DebugTintNode::create({0, 1, 0, 1});
    tint->addChild(sgfx::shapes::box({1, 1, 1}));
    viewer->setSceneData(tint);
    viewer->camera()->setLookAt({3, 3, 3}, {0, 0, 0});
    viewer->camera()->setPerspective(45.0f, 0.1f, 100.0f);
    viewer->camera()->clearColor = {0, 0, 0, 1};
    viewer->frame();
    const sgfx::Image img = viewer->capture();
    const unsigned char* p = img.pixel(16, 16);
    std::printf("consumer: centre pixel %d %d %d\n", p[0], p[1], p[2]);
    return (p[0] == 0 && p[1] == 255 && p[2] == 0) ? 0 : 1;
}

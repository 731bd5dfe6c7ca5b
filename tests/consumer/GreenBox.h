#pragma once
// The consumers' scene: a green (DebugTint) box filling the centre of a 32x32 headless view.
#include <sgfx/Shapes.h>
#include <sgfx/Viewer.h>
#include <sgfx/nodes/debugtint/DebugTintNode.h>

#include <cstdio>
#include <memory>

inline std::unique_ptr<sgfx::Viewer> greenBoxViewer() {
    auto viewer = sgfx::Viewer::createHeadless(32, 32);
    auto tint = sgfx::DebugTintNode::create({0, 1, 0, 1});
    tint->addChild(sgfx::shapes::box({1, 1, 1}));
    viewer->setSceneData(tint);
    viewer->camera()->setLookAt({3, 3, 3}, {0, 0, 0});
    viewer->camera()->setPerspective(45.0f, 0.1f, 100.0f);
    viewer->camera()->clearColor = {0, 0, 0, 1};
    return viewer;
}

/// Draws a frame and checks that the centre pixel is the box's pure green.
inline bool drawsGreen(sgfx::Viewer& viewer, const char* who) {
    viewer.frame();
    const sgfx::Image img = viewer.capture();
    const unsigned char* p = img.pixel(16, 16);
    std::printf("%s: centre pixel %d %d %d\n", who, p[0], p[1], p[2]);
    return p[0] == 0 && p[1] == 255 && p[2] == 0;
}

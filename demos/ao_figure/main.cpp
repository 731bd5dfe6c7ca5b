// The SSAO seed's figures on sgfx: the robot vehicle on a plane under ambient light only,
// without ambient occlusion (figure 1), with it (figure 8), and the raw and blurred occlusion
// maps (figures 5 and 7). Headless; writes four PNGs.
//   ao_figure [--out-dir DIR] [--size WxH]
#include "CliParse.h"

#include <PolygonScene.h>
#include <sgfx/Shapes.h>
#include <sgfx/Viewer.h>
#include <sgfx/nodes/ao/AmbientOcclusionNode.h>

#include <cstdio>
#include <cstring>
#include <exception>
#include <filesystem>
#include <string>

int main(int argc, char** argv) {
    std::filesystem::path dir = ".";
    int width = 480, height = 320;
    CLI::App cli{"ao_figure: the SSAO seed's figures (the robot under ambient light without and with "
                 "occlusion, the raw and blurred occlusion maps), four PNGs",
                 "ao_figure"};
    demo::lastValueWins(cli);
    demo::addFigureOptions(cli, dir, width, height);
    if (const int status = demo::parse(cli, argc, argv); status >= 0) return status;
    try {
        auto plane = sgfx::shapes::quad(60, 60);
        auto ground = sgfx::Material::create();
        ground->ambient = glm::vec3(0.45f, 0.45f, 0.42f);
        ground->diffuse = glm::vec4(0.45f, 0.45f, 0.42f, 1.0f);
        plane->getOrCreateStateSet().material.set(ground);
        auto ambient = sgfx::Light::create(sgfx::LightType::Ambient);
        ambient->intensity = 1.6f; // overcast: no direct light at all
        struct Shot {
            const char* file;
            bool ao;
            sgfx::AoDebugView view;
        };
        for (const Shot& shot : {Shot{"ao_robot_off.png", false, sgfx::AoDebugView::Off},
                                 Shot{"ao_robot_on.png", true, sgfx::AoDebugView::Off},
                                 Shot{"ao_map_raw.png", true, sgfx::AoDebugView::Raw},
                                 Shot{"ao_map_blurred.png", true, sgfx::AoDebugView::Blurred}}) {
            auto world = sgfx::Group::create();
            world->addChild(plane);
            world->addChild(polygon::buildVehicle());
            auto root = sgfx::Group::create();
            root->addChild(ambient);
            if (shot.ao) {
                sgfx::AmbientOcclusionParameters p;
                p.radius = 0.6f;
                p.debugView = shot.view;
                auto ao = sgfx::AmbientOcclusionNode::create(p);
                ao->addChild(world);
                root->addChild(ao);
            } else {
                root->addChild(world);
            }
            auto viewer = sgfx::Viewer::createHeadless(width, height);
            auto& cam = *viewer->camera();
            cam.setPerspective(40.0f, 0.2f, 200.0f);
            cam.setLookAt({6.5f, -7.5f, 4.5f}, {0.0f, 0.0f, 0.9f});
            cam.clearColor = {0.75f, 0.8f, 0.85f, 1.0f};
            viewer->setSceneData(root);
            viewer->frame();
            for (const std::string& e : viewer->renderer().takeGlErrors())
                std::fprintf(stderr, "ao_figure: GL: %s\n", e.c_str());
            const std::filesystem::path out = dir / shot.file;
            viewer->writeScreenshot(out);
            std::printf("wrote %s (%dx%d)\n", out.c_str(), width, height);
        }
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "ao_figure: %s\n", e.what());
        return 1;
    }
}

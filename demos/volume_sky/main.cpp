// Volume and sky showcase: a smoke cloud (VolumeNode, raymarched, sliced or splatted) drifting over a small
// town on a plain, under the physical sky (SkyNode) at several times of day, one panel per time,
// written headless to a PNG.
//
//   volume_sky [--hours H[,H...]] [--size WxH] [--out PNG]
//              [--method raymarch|slicing|splatting] [--splat-spacing M] [--no-volume] [--no-sky]
//
// Defaults: 7,10,13,18.5 hours, 320x180 per panel, volume_sky.png. --no-volume and --no-sky give
// the "before" images of the docs (scripts/effect-figures.sh).
#include "CliParse.h"

#include <sgfx/nodes/sky/SkyMath.h>
#include <sgfx/nodes/sky/SkyNode.h>
#include <sgfx/nodes/volume/VolumeNode.h>

#include <sgfx/Shapes.h>
#include <sgfx/Viewer.h>

#include <glm/gtc/matrix_transform.hpp>

#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

struct Options {
    std::vector<float> hours{7.0f, 10.0f, 13.0f, 18.5f};
    int width = 320, height = 180;
    std::string out = "volume_sky.png";
    sgfx::VolumeMethod method = sgfx::VolumeMethod::Raymarch;
    float splatSpacing = 2.0f; // metres: 45 × 35 × 15 kernels over the cloud's box
    bool volume = true, sky = true;
};

// Returns -1 when the program goes on, else its exit status (0 after --help, 2 for bad options).
int parse(int argc, char** argv, Options& o) {
    CLI::App cli{
        "volume_sky: a smoke cloud over a small town under the physical sky, one panel per time of day",
        "volume_sky"};
    demo::lastValueWins(cli);
    cli.add_option_function<std::string>(
           "--hours",
           [&o](const std::string& v) {
               o.hours.clear();
               std::stringstream list(v);
               for (std::string h; std::getline(list, h, ',');)
                   o.hours.push_back(float(demo::number("--hours", h, 0, 24)));
               if (o.hours.empty() || o.hours.size() > 8)
                   throw CLI::ValidationError("--hours", "'" + v + "': give 1 to 8 times");
           },
           "solar times of the panels, 0..24 (default 7,10,13,18.5)")
        ->type_name("H[,H...]");
    demo::addSize(cli, o.width, o.height, 16, 2048, "size of each panel (default 320x180)");
    cli.add_option("--out", o.out, "PNG to write (default volume_sky.png)")->type_name("PNG");
    cli.add_option_function<std::string>(
           "--method",
           [&o](const std::string& v) {
               o.method = demo::choice<sgfx::VolumeMethod>("--method", v,
                                                           {{"raymarch", sgfx::VolumeMethod::Raymarch},
                                                            {"slicing", sgfx::VolumeMethod::Slicing},
                                                            {"splatting", sgfx::VolumeMethod::Splatting}},
                                                           "raymarch, slicing or splatting");
           },
           "how the cloud is drawn (default raymarch)")
        ->type_name("raymarch|slicing|splatting");
    cli.add_option_function<std::string>(
           "--splat-spacing",
           [&o](const std::string& v) {
               o.splatSpacing = float(demo::number("--splat-spacing", v, 0.25, 100));
           },
           "metres between the splatted kernels, 0.25..100 (default 2)")
        ->type_name("M");
    cli.add_flag_callback(
        "--no-volume", [&o] { o.volume = false; }, "no smoke cloud (the docs' before image)");
    cli.add_flag_callback(
        "--no-sky", [&o] { o.sky = false; }, "no physical sky (the docs' before image)");
    return demo::parse(cli, argc, argv);
}

// A plain with a few blocks of houses: something for the cloud to drift over and hide.
sgfx::NodePtr town() {
    auto g = sgfx::Group::create();
    auto ground = sgfx::shapes::quad(2000.0f, 2000.0f);
    auto grass = sgfx::Material::create();
    grass->diffuse = {0.32f, 0.42f, 0.22f, 1.0f};
    grass->ambient = glm::vec3(0.32f, 0.42f, 0.22f);
    ground->getOrCreateStateSet().material.set(grass);
    g->addChild(ground);
    auto walls = sgfx::Material::create();
    walls->diffuse = {0.78f, 0.72f, 0.62f, 1.0f};
    walls->ambient = glm::vec3(0.78f, 0.72f, 0.62f);
    auto house = sgfx::shapes::box({8.0f, 8.0f, 10.0f});
    house->getOrCreateStateSet().material.set(walls);
    for (int x = -3; x <= 3; ++x)
        for (int y = -3; y <= 3; ++y) {
            const float h = 1.0f + float((x * 7 + y * 13 + 50) % 5) * 0.5f; // 1..3 storeys
            auto t = sgfx::Transform::create(glm::scale(
                glm::translate(glm::mat4(1.0f), {float(x) * 20.0f, float(y) * 20.0f + 40.0f, 5.0f * h}),
                {1.0f, 1.0f, h}));
            t->addChild(house);
            g->addChild(t);
        }
    return g;
}

} // namespace

int main(int argc, char** argv) {
    Options o;
    if (const int status = parse(argc, argv, o); status >= 0) return status;
    try {
        auto sun = sgfx::Light::create(sgfx::LightType::Directional);
        auto ambient = sgfx::Light::create(sgfx::LightType::Ambient);
        ambient->color = glm::vec3(0.3f);
        auto root = sgfx::Group::create();
        root->addChild(sun);
        root->addChild(ambient);
        root->addChild(town());
        std::shared_ptr<sgfx::VolumeNode> cloud;
        if (o.volume) {
            sgfx::VolumeParameters vp;
            vp.size = {90.0f, 70.0f, 30.0f};
            vp.absorption = 0.04f; // per metre at full density
            vp.scattering = 0.25f; // extinction 0.29/m: a 30 m column at full density lets e^(−8.7) through
            vp.g = 0.5f;
            vp.lightColor = glm::vec3(4.0f, 3.8f, 3.4f);
            vp.method = o.method;
            vp.splatSpacing = o.splatSpacing;
            cloud = sgfx::VolumeNode::create(vp, sgfx::VolumeGrid::noise(64, 7, 4, 0.35f));
            auto place = sgfx::Transform::create(glm::translate(glm::mat4(1.0f), {-15.0f, 15.0f, 20.0f}));
            place->addChild(cloud);
            root->addChild(place);
        }
        std::shared_ptr<sgfx::SkyNode> sky;
        if (o.sky) {
            sky = sgfx::SkyNode::create();
            root->addChild(sky);
        }

        auto viewer = sgfx::Viewer::createHeadless(o.width, o.height);
        viewer->camera()->setPerspective(55.0f, 0.5f, 5000.0f);
        viewer->camera()->setLookAt({-70.0f, -90.0f, 28.0f}, {0.0f, 45.0f, 22.0f});
        viewer->camera()->clearColor = {0.55f, 0.65f, 0.8f, 1.0f};
        viewer->setSceneData(root);

        sgfx::Image out;
        out.width = o.width * int(o.hours.size());
        out.height = o.height;
        out.pixels.assign(std::size_t(out.width) * std::size_t(out.height) * 4, 0);
        for (std::size_t p = 0; p < o.hours.size(); ++p) {
            const glm::vec3 towardsSun = sgfx::sky::sunDirection(o.hours[p]);
            sun->direction = -towardsSun;
            // Sunlight reddens and fades towards the horizon; the sky node's own model does the
            // same for the sky, this keeps the ground in step without a second model.
            const float up = glm::clamp(towardsSun.z * 3.0f, 0.0f, 1.0f);
            sun->color = glm::mix(glm::vec3(0.9f, 0.45f, 0.25f), glm::vec3(1.0f, 0.97f, 0.9f), up) *
                         (0.2f + 0.8f * up);
            if (sky) sky->setParameters(sgfx::SkyParameters::atTime(o.hours[p]));
            if (cloud) {
                sgfx::VolumeParameters vp = cloud->parameters();
                vp.lightDirection = -towardsSun;
                vp.lightColor = 4.0f * sun->color;
                cloud->setParameters(vp);
            }
            viewer->frame();
            const sgfx::Image img = viewer->capture();
            for (int y = 0; y < o.height; ++y)
                std::copy_n(img.pixel(0, y), std::size_t(o.width) * 4,
                            out.pixels.begin() + std::ptrdiff_t((std::size_t(y) * std::size_t(out.width) +
                                                                 p * std::size_t(o.width)) *
                                                                4));
        }
        for (const std::string& e : viewer->renderer().takeGlErrors())
            std::fprintf(stderr, "volume_sky: GL: %s\n", e.c_str());
        sgfx::writePng(o.out, out);
        std::printf("wrote %s (%dx%d): %zu times of day, volume %s, sky %s\n", o.out.c_str(), out.width,
                    out.height, o.hours.size(),
                    o.volume ? (o.method == sgfx::VolumeMethod::Raymarch  ? "raymarched"
                                : o.method == sgfx::VolumeMethod::Slicing ? "sliced"
                                                                          : "splatted")
                             : "off",
                    o.sky ? "on" : "off");
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "volume_sky: %s\n", e.what());
        return 1;
    }
}

#pragma once
// sgfx-view's command line, shared by the headless and the windowed paths.
#include "ViewScene.h"

#include <sgfx/Group.h>

#include <glm/glm.hpp>

#include <optional>
#include <string>
#include <vector>

namespace view {

struct Options {
    std::vector<std::string> files;
    std::string out = "sgfx-view.png";
    bool outGiven = false;
    int width = 512, height = 384;
    Settings settings;
    bool compare = false, keepYUp = false;
    bool headless = false, window = false;
    int selfTestFrames = 0;         // --self-test N: scripted input in the window, then exit
    std::optional<glm::dvec2> pick; // --pick X,Y: image pixels from the top-left corner
    float yaw = 30.0f, pitch = 25.0f, crease = 0.0f;
    std::optional<double> time;           // --time SECONDS: the pose at that time, paused
    std::optional<std::string> animation; // --animation NAME|INDEX
    bool listAnimations = false;          // --list-animations: print them and exit
    int benchFrames = 0;                  // --bench N: time N frames, print a BENCH line
    bool orbit = false;                   // --orbit: the benchmark's orbit camera (main.cpp)
    bool occlusion = false;               // --occlusion: RendererOptions::occlusionCulling On
    float autoLodPixels = 0.0f;           // --auto-lod [PX]: GltfOptions::autoLod, 0 = off
};

// Loads every file under one group (glTF's Y up turned into Z up unless keepYUp). Throws
// std::runtime_error naming the file.
sgfx::NodePtr loadFiles(const std::vector<std::string>& files, const Options& o);

// The interactive window; returns the exit status. Throws sgfx::ContextError when no window can
// be opened (no display), before anything else happens.
int runWindow(const Options& o, ViewScene& scene);

} // namespace view

#pragma once
// THROWAWAY stub of CONFIG's API until the real loader is merged (deleted on merge).
#include <sgfx/DisplayChannel.h>
#include <sgfx/LoadError.h>

#include <glm/gtc/matrix_transform.hpp>

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace sgfx {
struct DisplayConfig {
    std::string name, layout;
    std::vector<DisplayChannel> channels;
    std::optional<OffAxisFrustum> overall;
    Viewport composite;
    static DisplayConfig load(const std::filesystem::path& path) {
        DisplayConfig c;
        const std::string p = path.string();
        if (p.find("bad") != std::string::npos) throw LoadError(p + ": channels[1].viewport: missing");
        if (p.find("wall") != std::string::npos) {
            c.layout = "wall";
            c.overall = OffAxisFrustum::fromAngles(-30, 30, -20, 20, 0.5f, 2000.0f);
            for (int j = 0; j < 2; ++j)
                for (int i = 0; i < 2; ++i) {
                    DisplayChannel ch;
                    ch.name = "s" + std::to_string(i) + std::to_string(j);
                    ch.frustum = c.overall->sub(i * 0.5, i * 0.5 + 0.5, j * 0.5, j * 0.5 + 0.5);
                    ch.viewport = {i * 960, j * 640, 960, 640};
                    c.channels.push_back(ch);
                }
        } else {
            c.layout = "cylinder";
            for (int i = 0; i < 3; ++i) {
                DisplayChannel ch;
                ch.name = "p" + std::to_string(i);
                ch.viewOffset = glm::rotate(glm::mat4(1.0f), glm::radians(40.0f * float(1 - i)), {0, 1, 0});
                ch.frustum = OffAxisFrustum::fromAngles(-20, 20, -15, 15, 0.5f, 2000.0f);
                ch.viewport = {i * 800, 0, 800, 600};
                c.channels.push_back(ch);
            }
        }
        c.composite = compositeViewport(c.channels);
        return c;
    }
};
} // namespace sgfx

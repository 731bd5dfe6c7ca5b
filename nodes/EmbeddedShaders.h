#pragma once
#include <string_view>

namespace sgfx::nodes::shaders {
/// GLSL files of the effect folders, embedded at build time; empty when unknown.
std::string_view embedded(std::string_view name);
} // namespace sgfx::nodes::shaders

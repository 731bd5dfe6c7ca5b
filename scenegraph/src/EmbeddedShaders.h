#pragma once
#include <string_view>

namespace sgfx::shaders {
// Text of a file under shaders/, embedded at build time; empty when unknown.
std::string_view embedded(std::string_view name);
} // namespace sgfx::shaders

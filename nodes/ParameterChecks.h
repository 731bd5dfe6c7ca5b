#pragma once
/// @file
/// What the effect nodes share: their GLSL by file name, and parameter checks whose messages have
/// one form ("sgfx: FogParameters: density = -1 is outside [0, 1e+06]").
#include "EmbeddedShaders.h"

#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <string_view>

namespace sgfx::nodes {

inline std::string shaderText(std::string_view file) {
    return std::string(shaders::embedded(file));
}

/// `src` with `text` inserted after its first line (the `#version` line): defines, declarations.
inline std::string afterVersion(std::string src, std::string_view text) {
    src.insert(src.find('\n') + 1, text);
    return src;
}

/// The file with each `#include "other.glsl"` line replaced by that embedded file (one level).
inline std::string shaderWithIncludes(std::string_view file) {
    std::string src = shaderText(file);
    const std::string key = "#include \"";
    for (auto at = src.find(key); at != std::string::npos; at = src.find(key)) {
        const auto close = src.find('"', at + key.size());
        const auto eol = src.find('\n', at);
        src.replace(at, eol - at, shaderText(src.substr(at + key.size(), close - at - key.size())));
    }
    return src;
}

inline std::string number(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", v);
    return buf;
}

/// Throws std::invalid_argument("sgfx: <owner>: <what>").
[[noreturn]] inline void refuse(std::string_view owner, const std::string& what) {
    throw std::invalid_argument("sgfx: " + std::string(owner) + ": " + what);
}

/// `v` must be finite and in [lo, hi] (or (lo, hi] with openLow).
inline void checkRange(std::string_view owner, const char* name, float v, double lo, double hi,
                       bool openLow = false) {
    if (!std::isfinite(v)) refuse(owner, std::string(name) + " is " + number(v) + "; it must be finite");
    if (v < lo || v > hi || (openLow && v == lo))
        refuse(owner, std::string(name) + " = " + number(v) + " is outside " + (openLow ? "(" : "[") +
                          number(lo) + ", " + number(hi) + "]");
}

} // namespace sgfx::nodes

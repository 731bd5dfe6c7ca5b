#pragma once
#include "sgfx/Export.h"
#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <vector>

namespace sgfx {

/// 8-bit image, rows stored top to bottom (the PNG order).
struct SGFX_API Image {
    int width = 0;
    int height = 0;
    int channels = 4; ///< 1..4
    std::vector<std::uint8_t> pixels;

    static std::shared_ptr<Image> create(int w, int h, int channels);
    std::uint8_t* pixel(int x, int y) { return pixels.data() + (std::size_t(y) * width + x) * channels; }
    const std::uint8_t* pixel(int x, int y) const {
        return pixels.data() + (std::size_t(y) * width + x) * channels;
    }
};

/// Linear RGBA floats, rows top to bottom.
struct SGFX_API FloatImage {
    int width = 0;
    int height = 0;
    std::vector<float> rgba;
};

/// Throws std::runtime_error with the path and the reason.
SGFX_API void writePng(const std::filesystem::path& path, const Image& image);
SGFX_API Image readPng(const std::filesystem::path& path);
/// Reads any image stb_image reads as linear RGBA: Radiance `.hdr` as stored, 8-bit files
/// (PNG, JPEG, ...) decoded from sRGB (IEC 61966-2-1), opaque when they have no alpha. Throws
/// std::runtime_error with the path and the reason; NaN, infinite or negative texels are refused
/// naming the first one.
SGFX_API FloatImage readImageLinear(const std::filesystem::path& path);

} // namespace sgfx

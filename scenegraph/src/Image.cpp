#include "sgfx/Image.h"

#include <stb_image.h>
#include <stb_image_write.h>

#include <cmath>
#include <stdexcept>

namespace sgfx {

std::shared_ptr<Image> Image::create(int w, int h, int channels) {
    constexpr int kMaxSide = 1 << 16; // larger than any GL texture; refuses absurd allocations
    if (w <= 0 || h <= 0 || w > kMaxSide || h > kMaxSide || channels < 1 || channels > 4)
        throw std::invalid_argument("sgfx: Image::create(" + std::to_string(w) + ", " + std::to_string(h) +
                                    ", " + std::to_string(channels) + "): sides must be in 1.." +
                                    std::to_string(kMaxSide) + ", channels in 1..4");
    auto img = std::make_shared<Image>();
    img->width = w;
    img->height = h;
    img->channels = channels;
    img->pixels.assign(std::size_t(w) * h * channels, 0);
    return img;
}

void writePng(const std::filesystem::path& path, const Image& image) {
    if (image.width <= 0 || image.height <= 0 ||
        image.pixels.size() != std::size_t(image.width) * image.height * image.channels)
        throw std::invalid_argument("sgfx: cannot write " + path.string() +
                                    ": image is empty or inconsistent");
    if (!stbi_write_png(path.c_str(), image.width, image.height, image.channels, image.pixels.data(),
                        image.width * image.channels))
        throw std::runtime_error("sgfx: could not write PNG " + path.string());
}

Image readPng(const std::filesystem::path& path) {
    int w = 0, h = 0, c = 0;
    stbi_uc* data = stbi_load(path.c_str(), &w, &h, &c, 0);
    if (!data) {
        const char* why = stbi_failure_reason();
        throw std::runtime_error("sgfx: could not read image " + path.string() + ": " +
                                 (why ? why : "unknown"));
    }
    Image img;
    img.width = w;
    img.height = h;
    img.channels = c;
    img.pixels.assign(data, data + std::size_t(w) * h * c);
    stbi_image_free(data);
    return img;
}

namespace {
float srgbToLinear(std::uint8_t v) {
    const float c = float(v) / 255.0f;
    return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}
} // namespace

FloatImage readImageLinear(const std::filesystem::path& path) {
    auto fail = [&](const std::string& why) {
        return std::runtime_error("sgfx: could not read image " + path.string() + ": " + why);
    };
    FloatImage img;
    int c = 0;
    if (stbi_is_hdr(path.c_str())) {
        float* data = stbi_loadf(path.c_str(), &img.width, &img.height, &c, 4);
        if (!data) throw fail(stbi_failure_reason() ? stbi_failure_reason() : "unknown");
        img.rgba.assign(data, data + std::size_t(img.width) * img.height * 4);
        stbi_image_free(data);
    } else {
        stbi_uc* data = stbi_load(path.c_str(), &img.width, &img.height, &c, 4);
        if (!data) throw fail(stbi_failure_reason() ? stbi_failure_reason() : "unknown");
        img.rgba.resize(std::size_t(img.width) * img.height * 4);
        for (std::size_t i = 0; i < img.rgba.size(); ++i)
            img.rgba[i] = i % 4 == 3 ? float(data[i]) / 255.0f : srgbToLinear(data[i]);
        stbi_image_free(data);
    }
    for (std::size_t i = 0; i < img.rgba.size(); ++i)
        if (!std::isfinite(img.rgba[i]) || img.rgba[i] < 0.0f)
            throw fail("texel (" + std::to_string(i / 4 % std::size_t(img.width)) + ", " +
                       std::to_string(i / 4 / std::size_t(img.width)) + ") is " +
                       std::to_string(img.rgba[i]) + " (not a finite, non-negative value)");
    return img;
}

} // namespace sgfx

#include "sgfx/Texture.h"
#include "sgfx/gl/Objects.h"

namespace sgfx {
Texture::Texture() = default;
Texture::~Texture() = default;
std::shared_ptr<Texture> Texture::create(std::shared_ptr<Image> image, bool srgb) {
    auto t = std::make_shared<Texture>();
    t->image = std::move(image);
    t->srgb = srgb;
    return t;
}
} // namespace sgfx

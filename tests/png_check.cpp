// png_check PNG [WxH] [--min-colors N] [--same PNG2] [--differs PNG2] [--darker PNG2 N]: prints the
// image's size and how many distinct colours it has; exits 1 when the file is unreadable, the size
// differs or it has fewer colours than asked (a blank or single-colour render), or when it is not
// pixel for pixel the same as PNG2 (--same) or is (--differs), or (--darker: PNG2 without shadows)
// when a pixel is brighter than PNG2's by more than 2/255 in a colour channel or fewer than N
// pixels are darker by more than 8/255. The demos' tests run it on what they wrote.
#include <sgfx/Image.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <stdexcept>
#include <string>
#include <unordered_set>
#include <utility>

namespace {

// Pixels that differ in any channel; every pixel when the sizes or channel counts differ.
std::size_t differingPixels(const sgfx::Image& a, const sgfx::Image& b) {
    const std::size_t all = std::size_t(a.width) * std::size_t(a.height);
    if (a.width != b.width || a.height != b.height || a.channels != b.channels) return all;
    std::size_t n = 0;
    for (int y = 0; y < a.height; ++y)
        for (int x = 0; x < a.width; ++x)
            n += std::memcmp(a.pixel(x, y), b.pixel(x, y), std::size_t(a.channels)) != 0;
    return n;
}

// --darker: pixels brighter than `b`'s by more than 2/255 in a colour channel (rounding), and
// pixels darker by more than 8/255 in one. Throws when the sizes or channel counts differ.
std::pair<std::size_t, std::size_t> brighterAndDarker(const sgfx::Image& a, const sgfx::Image& b) {
    if (a.width != b.width || a.height != b.height || a.channels != b.channels)
        throw std::runtime_error("--darker: the images differ in size or channels");
    std::size_t brighter = 0, darker = 0;
    for (int y = 0; y < a.height; ++y)
        for (int x = 0; x < a.width; ++x) {
            int up = 0, down = 0;
            for (int k = 0; k < std::min(a.channels, 3); ++k) {
                const int d = int(a.pixel(x, y)[k]) - int(b.pixel(x, y)[k]);
                up = std::max(up, d);
                down = std::max(down, -d);
            }
            brighter += up > 2;
            darker += down > 8;
        }
    return {brighter, darker};
}

} // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: png_check PNG [WxH] [--min-colors N] [--same PNG2] [--differs PNG2] "
                             "[--darker PNG2 N]\n");
        return 2;
    }
    try {
        const sgfx::Image img = sgfx::readPng(argv[1]);
        std::unordered_set<std::uint32_t> colours;
        for (int y = 0; y < img.height; ++y)
            for (int x = 0; x < img.width; ++x) {
                std::uint32_t c = 0;
                for (int k = 0; k < img.channels; ++k)
                    c = c << 8 | img.pixel(x, y)[k];
                colours.insert(c);
            }
        std::printf("png_check %s: %dx%d, %zu colours\n", argv[1], img.width, img.height, colours.size());
        int status = 0;
        for (int i = 2; i < argc; ++i) {
            const std::string a = argv[i];
            if (a == "--min-colors" && i + 1 < argc) {
                const std::size_t n = std::strtoul(argv[++i], nullptr, 10);
                if (colours.size() < n) {
                    std::printf("png_check: FAIL: %zu colours, fewer than %zu (blank?)\n", colours.size(), n);
                    status = 1;
                }
            } else if ((a == "--same" || a == "--differs") && i + 1 < argc) {
                const std::size_t n = differingPixels(img, sgfx::readPng(argv[++i]));
                std::printf("png_check: %zu pixels differ from %s\n", n, argv[i]);
                if ((a == "--same") != (n == 0)) {
                    std::printf("png_check: FAIL: %s %s\n", a == "--same" ? "not the same as" : "the same as",
                                argv[i]);
                    status = 1;
                }
            } else if (a == "--darker" && i + 2 < argc) {
                const char* other = argv[++i];
                const std::size_t least = std::strtoul(argv[++i], nullptr, 10);
                const auto [brighter, darker] = brighterAndDarker(img, sgfx::readPng(other));
                std::printf("png_check: %zu pixels darker than %s, %zu brighter\n", darker, other, brighter);
                if (brighter > 0 || darker < least) {
                    std::printf("png_check: FAIL: %s\n", brighter > 0
                                                             ? "brighter somewhere (a shadow lights?)"
                                                             : "too few darker pixels");
                    status = 1;
                }
            } else if (a != std::to_string(img.width) + "x" + std::to_string(img.height)) {
                std::printf("png_check: FAIL: size %dx%d, expected %s\n", img.width, img.height, a.c_str());
                status = 1;
            }
        }
        if (status == 0) std::printf("png_check: ok\n");
        return status;
    } catch (const std::exception& e) {
        std::printf("png_check: FAIL: %s\n", e.what());
        return 1;
    }
}

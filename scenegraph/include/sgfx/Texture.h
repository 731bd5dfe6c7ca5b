#pragma once
#include "sgfx/Export.h"
#include "sgfx/Image.h"

#include <cstdint>
#include <memory>

namespace sgfx {

namespace gl {
class Texture;
}

enum class Filter : std::uint8_t { Nearest, Linear, LinearMipmapLinear };
enum class Wrap : std::uint8_t { Repeat, ClampToEdge, MirroredRepeat };

/// An image plus sampling state. `srgb` marks colour data stored sRGB-encoded (decoded on sampling).
class SGFX_API Texture {
public:
    static std::shared_ptr<Texture> create(std::shared_ptr<Image> image, bool srgb = true);
    Texture();
    ~Texture();

    std::shared_ptr<Image> image;
    bool srgb = true;
    Filter minFilter = Filter::LinearMipmapLinear;
    Filter magFilter = Filter::Linear;
    Wrap wrapS = Wrap::Repeat;
    Wrap wrapT = Wrap::Repeat;

    void dirty() { ++revision_; }
    std::uint64_t revision() const { return revision_; }
    std::unique_ptr<gl::Texture>& gpu() const { return gpu_; }

private:
    std::uint64_t revision_ = 1;
    mutable std::unique_ptr<gl::Texture> gpu_;
};

} // namespace sgfx

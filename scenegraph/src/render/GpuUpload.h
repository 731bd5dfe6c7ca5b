#pragma once
// Uploads of scene data to GL objects and the enum mappings they use (private to the renderer):
// a Geometry's vertex arrays, a Texture's image, a render target copied into a camera's texture.
#include "sgfx/Geometry.h"
#include "sgfx/StateSet.h"
#include "sgfx/Texture.h"
#include "sgfx/gl/Objects.h"

#include <sgfx_glad/gl.h>

namespace sgfx::render {

GLenum glMode(PrimitiveMode mode);
GLenum glCompare(CompareFunc func);
GLint glFilter(Filter filter);
GLint glWrap(Wrap wrap);

/// The geometry's buffers and vertex array, (re)uploaded when its revision changed.
gl::GeometryBuffers& buffersFor(const Geometry& geometry);
/// Uploads a skinned or morphed geometry's pose when it changed and binds its storage buffers
/// (kJointsBinding, kMorphBinding, kMorphWeightsBinding).
void bindPose(const Geometry& geometry, gl::GeometryBuffers& buffers);
/// The texture's GL object, (re)created from its image when its revision changed; throws
/// std::invalid_argument for invalid settings or image data.
GLuint textureFor(const Texture& texture);
/// Copies a render target's colour into the texture a render-to-texture camera draws into.
void copyToTexture(const gl::RenderTarget& from, const Texture& to);

} // namespace sgfx::render

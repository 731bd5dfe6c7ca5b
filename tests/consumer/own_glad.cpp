// An application that calls GL itself through its own glad (<glad/gl.h>, glad_glClear, gladLoadGL)
// beside sgfx, whose loader is private and prefixed: it links (no duplicate symbol), and both
// loaders work on one context, interleaved. The application clears a framebuffer of its own and
// reads it back through its glad between two sgfx frames, each of which must still draw the box.
#include "GreenBox.h"

#include <glad/gl.h>

namespace {

// The application's own GL: a 4x4 RGBA8 target cleared to (0.2, 0.4, 0.6) and read back.
bool ownGlWorks() {
    GLuint texture = 0, framebuffer = 0;
    glCreateTextures(GL_TEXTURE_2D, 1, &texture);
    glTextureStorage2D(texture, 1, GL_RGBA8, 4, 4);
    glCreateFramebuffers(1, &framebuffer);
    glNamedFramebufferTexture(framebuffer, GL_COLOR_ATTACHMENT0, texture, 0);
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
    glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glViewport(0, 0, 4, 4);
    glDisable(GL_SCISSOR_TEST);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glClearColor(0.2f, 0.4f, 0.6f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT);
    unsigned char own[4] = {1, 2, 3, 4};
    glReadPixels(1, 1, 1, 1, GL_RGBA, GL_UNSIGNED_BYTE, own);
    const GLenum error = glGetError();
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glDeleteFramebuffers(1, &framebuffer);
    glDeleteTextures(1, &texture);
    std::printf("own glad: own framebuffer reads %d %d %d (expected 51 102 153), GL error 0x%x\n", own[0],
                own[1], own[2], error);
    return own[0] == 51 && own[1] == 102 && own[2] == 153 && error == GL_NO_ERROR;
}

} // namespace

int main() {
    auto viewer = greenBoxViewer();
    if (!drawsGreen(*viewer, "own glad: sgfx")) return 1;

    // The documented way to call GL beside sgfx: feed your own loader the context's getProcAddress.
    viewer->context().makeCurrent();
    const int version = gladLoadGL(reinterpret_cast<GLADloadfunc>(viewer->context().procAddress()));
    if (version == 0 || glad_glClear == nullptr) {
        std::printf("own glad: gladLoadGL failed\n");
        return 1;
    }
    std::printf("own glad: GL %d.%d on %s\n", GLAD_VERSION_MAJOR(version), GLAD_VERSION_MINOR(version),
                reinterpret_cast<const char*>(glGetString(GL_RENDERER)));
    if (!ownGlWorks()) return 1;
    return drawsGreen(*viewer, "own glad: sgfx again") ? 0 : 1;
}

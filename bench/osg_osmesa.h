// The headless OSMesa context the OpenSceneGraph peer benchmarks draw into (osg_polygon, osg_view,
// osg_particles): compatibility profile, since OSG 3.6 as packaged draws fixed function, and
// checked to reach OSMesa. Debian's libosg links libGL (glvnd), whose gl* do nothing without GLX;
// the programs link OSMesa first (osg_polygon.cpp's header comment explains the link order), and
// open() proves it before anything is drawn.
#pragma once

#include <GL/osmesa.h>
#include <dlfcn.h>
#include <osg/GLExtensions>

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

class OsgOsmesaContext {
public:
    // The context, current, drawing into its own RGBA8 buffer; or null after a message on stderr
    // that names `program` and the step that failed.
    static std::unique_ptr<OsgOsmesaContext> open(const char* program, int width, int height) {
        std::unique_ptr<OsgOsmesaContext> c(new OsgOsmesaContext(width, height));
        if (!c->ctx_) {
            std::fprintf(stderr, "%s: OSMesaCreateContextExt failed\n", program);
            return nullptr;
        }
        if (!OSMesaMakeCurrent(c->ctx_, c->buffer_.data(), GL_UNSIGNED_BYTE, width, height)) {
            std::fprintf(stderr, "%s: OSMesaMakeCurrent failed\n", program);
            return nullptr;
        }
        if (!c->renderer() || !c->version()) {
            std::fprintf(stderr,
                         "%s: glGetString returned NULL: GL calls are not reaching OSMesa (libGL's dispatch "
                         "won; try LD_PRELOAD=libOSMesa.so.8)\n",
                         program);
            return nullptr;
        }
        for (const char* name : kProbes) {
            const std::string direct = libraryOf(dlsym(RTLD_DEFAULT, name));
            const std::string viaOsg = libraryOf(osg::getGLExtensionFuncPtr(name));
            if (!isMesa(direct) || !isMesa(viaOsg)) {
                std::fprintf(stderr,
                             "%s: %s resolves to '%s' (direct) / '%s' (osg::getGLExtensionFuncPtr), not "
                             "OSMesa; try LD_PRELOAD=libOSMesa.so.8\n",
                             program, name, direct.c_str(), viaOsg.c_str());
                return nullptr;
            }
        }
        return c;
    }
    ~OsgOsmesaContext() {
        if (ctx_) OSMesaDestroyContext(ctx_);
    }
    OsgOsmesaContext(const OsgOsmesaContext&) = delete;
    OsgOsmesaContext& operator=(const OsgOsmesaContext&) = delete;

    const char* renderer() const { return reinterpret_cast<const char*>(glGetString(GL_RENDERER)); }
    const char* version() const { return reinterpret_cast<const char*>(glGetString(GL_VERSION)); }
    // The window-system framebuffer (RGBA8, bottom row first).
    const std::vector<unsigned char>& buffer() const { return buffer_; }

private:
    OsgOsmesaContext(int width, int height)
        : ctx_(OSMesaCreateContextExt(OSMESA_RGBA, 24, 0, 0, nullptr))
        , buffer_(std::size_t(width) * std::size_t(height) * 4) {}

    // GL entry points OSG uses on these paths (fixed function + VBOs).
    static constexpr const char* kProbes[] = {
        "glGetString",  "glClear",      "glDrawElements", "glEnable",        "glLightfv",      "glGenBuffers",
        "glBindBuffer", "glBufferData", "glUseProgram",   "glVertexPointer", "glNormalPointer"};
    static std::string libraryOf(void* p) {
        Dl_info info;
        return p && dladdr(p, &info) && info.dli_fname ? info.dli_fname : "(null)";
    }
    // OSMesa's own entry points, or libglapi's dispatch stubs that OSMesa drives.
    static bool isMesa(const std::string& lib) {
        return lib.find("libOSMesa") != std::string::npos || lib.find("libglapi") != std::string::npos;
    }

    OSMesaContext ctx_;
    std::vector<unsigned char> buffer_;
};

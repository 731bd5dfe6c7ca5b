// Per-pixel cost of llvmpipe's draw targets, without sgfx (docs/performance.md, "Per-pixel cost on
// foreign content"): is drawing into OSMesa's own buffer (what OSG does) cheaper per pixel than
// drawing into a framebuffer object's textures (what sgfx does), and does the colour format
// (RGBA8, SRGB8_ALPHA8 with GL_FRAMEBUFFER_SRGB, RGBA16F), the depth format (24-bit, 32F) or the
// number of draw calls (a uniform changed between draws, as a scene graph does) matter?
//
// One OSMesa 4.5 core context; the scene is LAYERS screen-covering grids of GRID×GRID cells (two
// triangles each: at 1280×720 a cell is 6×4 pixels, the size of the city's triangles), drawn front
// to back so that early depth rejects the hidden layers, each vertex with its own colour (Gouraud,
// as OSG's fixed function). Per round, every configuration draws one untimed and one timed frame
// (clear, draw, glFinish) at 1280×720 and at 320×180; the per-pixel cost is their difference, and
// the last columns are the medians of its per-round ratio to the first configuration's (OSMesa's
// own buffer). Times are the CPU time of all threads (llvmpipe's rasterizer threads included).
//
//   target_cost [--rounds 15] [--grid 200] [--layers 4] [--draws 3000]
#include <sgfx/GraphicsContext.h>
#include <sgfx_glad/gl.h>

#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

struct Config {
    const char* name;
    GLenum color; // 0: OSMesa's own buffer (the default framebuffer), which has its own 24-bit depth
    GLenum depth;
    bool srgb;        // GL_FRAMEBUFFER_SRGB on
    bool manyDraws;   // the grid split into --draws draw calls
    bool uniformEach; // with a uniform changed between them (as a scene graph's model matrix)
};
constexpr Config kConfigs[] = {
    {"osmesa-buffer", 0, 0, false, false, false},
    {"fbo-rgba8-d24", GL_RGBA8, GL_DEPTH_COMPONENT24, false, false, false},
    {"fbo-rgba8-d32f", GL_RGBA8, GL_DEPTH_COMPONENT32F, false, false, false},
    {"fbo-srgb8-d32f", GL_SRGB8_ALPHA8, GL_DEPTH_COMPONENT32F, true, false, false},
    {"fbo-rgba16f-d32f", GL_RGBA16F, GL_DEPTH_COMPONENT32F, false, false, false},
    {"osmesa-buffer-draws", 0, 0, false, true, false},
    {"osmesa-buffer-draws-uniform", 0, 0, false, true, true},
    {"fbo-srgb8-d32f-draws", GL_SRGB8_ALPHA8, GL_DEPTH_COMPONENT32F, true, true, false},
    {"fbo-srgb8-d32f-draws-uniform", GL_SRGB8_ALPHA8, GL_DEPTH_COMPONENT32F, true, true, true},
};

constexpr int kBigW = 1280, kBigH = 720, kSmallW = 320, kSmallH = 180;

const char* const kVert = R"(#version 450 core
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec4 a_color;
out vec4 v_color;
void main() { v_color = a_color; gl_Position = vec4(a_position, 1.0); }
)";
const char* const kFrag = R"(#version 450 core
in vec4 v_color;
uniform vec4 u_tint;
layout(location = 0) out vec4 o_color;
void main() { o_color = v_color * u_tint; }
)";

double cpuMs() {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return double(t.tv_sec) * 1e3 + double(t.tv_nsec) * 1e-6;
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

GLuint compile(GLenum type, const char* src) {
    const GLuint s = glCreateShader(type);
    glShaderSource(s, 1, &src, nullptr);
    glCompileShader(s);
    GLint ok = 0;
    glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
    if (!ok) throw std::runtime_error("target_cost: shader does not compile");
    return s;
}

struct Target {
    GLuint fbo = 0, color = 0, depth = 0;
};

Target makeTarget(const Config& c, int w, int h) {
    Target t;
    if (!c.color) return t;
    glCreateTextures(GL_TEXTURE_2D, 1, &t.color);
    glTextureStorage2D(t.color, 1, c.color, w, h);
    glCreateTextures(GL_TEXTURE_2D, 1, &t.depth);
    glTextureStorage2D(t.depth, 1, c.depth, w, h);
    glCreateFramebuffers(1, &t.fbo);
    glNamedFramebufferTexture(t.fbo, GL_COLOR_ATTACHMENT0, t.color, 0);
    glNamedFramebufferTexture(t.fbo, GL_DEPTH_ATTACHMENT, t.depth, 0);
    if (glCheckNamedFramebufferStatus(t.fbo, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        throw std::runtime_error(std::string("target_cost: incomplete framebuffer for ") + c.name);
    return t;
}

struct Scene {
    GLuint vao = 0, program = 0;
    GLint tint = -1;
    GLsizei indices = 0;
};

// LAYERS grids over the whole screen, nearest first.
Scene makeScene(int grid, int layers) {
    std::vector<float> v;
    std::vector<GLuint> idx;
    for (int l = 0; l < layers; ++l) {
        const auto base = GLuint(v.size() / 7);
        const float z = -0.8f + 0.4f * float(l) / float(std::max(layers, 1));
        for (int j = 0; j <= grid; ++j)
            for (int i = 0; i <= grid; ++i) {
                const unsigned hash =
                    unsigned(i * 73856093) ^ unsigned(j * 19349663) ^ unsigned(l * 83492791);
                v.insert(v.end(),
                         {-1.0f + 2.0f * float(i) / float(grid), -1.0f + 2.0f * float(j) / float(grid), z,
                          float(hash & 255u) / 255.0f, float((hash >> 8) & 255u) / 255.0f,
                          float((hash >> 16) & 255u) / 255.0f, 1.0f});
            }
        for (int j = 0; j < grid; ++j)
            for (int i = 0; i < grid; ++i) {
                const GLuint a = base + GLuint(j * (grid + 1) + i), b = a + 1, c = a + GLuint(grid + 1),
                             d = c + 1;
                idx.insert(idx.end(), {a, b, d, a, d, c});
            }
    }
    Scene s;
    GLuint buffers[2];
    glCreateBuffers(2, buffers);
    glNamedBufferStorage(buffers[0], GLsizeiptr(v.size() * sizeof(float)), v.data(), 0);
    glNamedBufferStorage(buffers[1], GLsizeiptr(idx.size() * sizeof(GLuint)), idx.data(), 0);
    glCreateVertexArrays(1, &s.vao);
    glVertexArrayVertexBuffer(s.vao, 0, buffers[0], 0, 7 * sizeof(float));
    glVertexArrayElementBuffer(s.vao, buffers[1]);
    glEnableVertexArrayAttrib(s.vao, 0);
    glEnableVertexArrayAttrib(s.vao, 1);
    glVertexArrayAttribFormat(s.vao, 0, 3, GL_FLOAT, GL_FALSE, 0);
    glVertexArrayAttribFormat(s.vao, 1, 4, GL_FLOAT, GL_FALSE, 3 * sizeof(float));
    glVertexArrayAttribBinding(s.vao, 0, 0);
    glVertexArrayAttribBinding(s.vao, 1, 0);
    s.program = glCreateProgram();
    glAttachShader(s.program, compile(GL_VERTEX_SHADER, kVert));
    glAttachShader(s.program, compile(GL_FRAGMENT_SHADER, kFrag));
    glLinkProgram(s.program);
    GLint ok = 0;
    glGetProgramiv(s.program, GL_LINK_STATUS, &ok);
    if (!ok) throw std::runtime_error("target_cost: program does not link");
    s.tint = glGetUniformLocation(s.program, "u_tint");
    s.indices = GLsizei(idx.size());
    return s;
}

struct Bench {
    sgfx::OsmesaContext ctx{kBigW, kBigH}; // the OSMesa 4.5 core context sgfx's headless viewer uses
    Scene scene;
    Target big[std::size(kConfigs)], small[std::size(kConfigs)];
    int draws = 3000;

    void bindSize(int w, int h) { ctx.resizeDrawable(w, h); }
    // CPU time of one frame: clear, the scene, glFinish.
    double frame(const Config& c, const Target& t, int w, int h) {
        bindSize(w, h);
        const double t0 = cpuMs();
        glBindFramebuffer(GL_FRAMEBUFFER, t.fbo);
        glViewport(0, 0, w, h);
        if (c.srgb)
            glEnable(GL_FRAMEBUFFER_SRGB);
        else
            glDisable(GL_FRAMEBUFFER_SRGB);
        glEnable(GL_DEPTH_TEST);
        glDepthFunc(GL_LESS);
        glClearColor(0.7f, 0.75f, 0.8f, 1.0f);
        glClearDepth(1.0);
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        glUseProgram(scene.program);
        glBindVertexArray(scene.vao);
        const int n = c.manyDraws ? draws : 1;
        const GLsizei per = (scene.indices / 3 + n - 1) / n * 3;
        glUniform4f(scene.tint, 1.0f, 1.0f, 1.0f, 1.0f);
        for (int d = 0; d < n; ++d) {
            const GLsizei first = GLsizei(d) * per, count = std::min(per, scene.indices - first);
            if (count <= 0) break;
            if (c.uniformEach) glUniform4f(scene.tint, 1.0f, 1.0f - float(d & 1) * 1e-3f, 1.0f, 1.0f);
            glDrawElements(GL_TRIANGLES, count, GL_UNSIGNED_INT,
                           reinterpret_cast<const void*>(std::size_t(first) * sizeof(GLuint)));
        }
        glFinish();
        return cpuMs() - t0;
    }
};

} // namespace

int main(int argc, char** argv) {
    int rounds = 15, grid = 200, layers = 4, draws = 3000;
    CLI::App app{"Per-pixel cost of llvmpipe's draw targets (OSMesa buffer against FBO textures)"};
    app.add_option("--rounds", rounds, "interleaved rounds (default 15)")->check(CLI::Range(1, 1000));
    app.add_option("--grid", grid, "cells per side of each layer (default 200)")->check(CLI::Range(1, 2000));
    app.add_option("--layers", layers, "screen-covering layers, front to back (default 4)")
        ->check(CLI::Range(1, 64));
    app.add_option("--draws", draws, "draw calls of the *-draws configurations (default 3000)")
        ->check(CLI::Range(1, 1000000));
    CLI11_PARSE(app, argc, argv);
    try {
        Bench b;
        b.draws = draws;
        // This program's own GL calls go through its glad table, loaded from the same context.
        if (!sgfx_gladLoadGL(reinterpret_cast<SGFX_GLADloadfunc>(b.ctx.procAddress())))
            throw std::runtime_error("target_cost: glad could not load GL");
        b.scene = makeScene(grid, layers);
        constexpr std::size_t n = std::size(kConfigs);
        for (std::size_t c = 0; c < n; ++c) {
            b.big[c] = makeTarget(kConfigs[c], kBigW, kBigH);
            b.small[c] = makeTarget(kConfigs[c], kSmallW, kSmallH);
        }
        std::vector<double> bigMs[n], smallMs[n], cost[n], ratio[n];
        for (int r = 0; r < rounds; ++r) {
            double base = 0.0;
            for (std::size_t c = 0; c < n; ++c) {
                b.frame(kConfigs[c], b.big[c], kBigW, kBigH);
                const double big = b.frame(kConfigs[c], b.big[c], kBigW, kBigH);
                b.frame(kConfigs[c], b.small[c], kSmallW, kSmallH);
                const double small = b.frame(kConfigs[c], b.small[c], kSmallW, kSmallH);
                if (c == 0) base = big - small;
                bigMs[c].push_back(big);
                smallMs[c].push_back(small);
                cost[c].push_back(big - small);
                ratio[c].push_back((big - small) / base);
            }
        }
        if (const GLenum e = glGetError(); e != GL_NO_ERROR)
            throw std::runtime_error("target_cost: GL error");
        for (std::size_t c = 0; c < n; ++c)
            std::printf("TARGET config=%s big_ms=%.2f small_ms=%.2f per_pixel_ms=%.2f ratio=%.3f rounds=%d "
                        "triangles=%d\n",
                        kConfigs[c].name, median(bigMs[c]), median(smallMs[c]), median(cost[c]),
                        median(ratio[c]), rounds, b.scene.indices / 3);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "%s\n", e.what());
        return 1;
    }
    return 0;
}

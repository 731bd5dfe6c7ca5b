// How fast can any GL path step the particle seed's state on this driver? (issue 24, Must 5;
// docs/effects/particles.md, "The floor on llvmpipe".) The goal, 3× osgParticle's simulation at
// 10^6 particles, is about 11 ms a step here. This program times, without sgfx, each way GL 4.5
// can run one step M → M' of the same 52-byte records, first as a plain copy (the record read and
// written unchanged: the path's input/output floor) and then with the real update
// (nodes/particles/particle_motion.glsl and particle_random.glsl, the shaders sgfx runs):
//
//   compute-ssbo   a compute shader reading and writing shader storage (sgfx's compute path)
//   compute-tbo    the same, reading through a buffer texture (texelFetch) instead
//   compute-vec4   a compute shader over four storage streams laid out as the fragment path's
//                  textures (vec4, vec4, vec4, float): the same data layout as fragment-mrt
//   fragment-mrt   a full-screen fragment pass, the records in four float textures (RGBA32F × 3
//                  and R32F: 13 floats), read by texelFetch and written as four colour targets
//   feedback       a vertex shader captured by transform feedback (sgfx's transform feedback path)
//
// One OSMesa 4.5 core context; per round every path runs one untimed and --steps timed steps
// (each ended by glFinish) from the same records, paths interleaved; the figures are medians over
// rounds of wall-clock ms per step. Every path's copy must leave the records bit-identical, and
// every update path must agree with compute-ssbo's records after the same steps (the run fails
// otherwise), so a path cannot look fast by doing less.
//
//   particle_floor [--count 1000000] [--rounds 5] [--steps 4]
#include <sgfx/GraphicsContext.h>
#include <sgfx_glad/gl.h>

#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

constexpr int kFloats = 13;     // age, position, velocity, angles0, angles
constexpr int kTexWidth = 1024; // the fragment path's texture rows
constexpr float kLifetime = 3.0f;

std::string readGlsl(const char* name) {
    std::ifstream f(std::string(SGFX_PARTICLE_GLSL_DIR) + "/" + name);
    if (!f) throw std::runtime_error(std::string("particle_floor: cannot read ") + name);
    std::stringstream s;
    s << f.rdbuf();
    return s.str();
}

GLuint compile(GLenum type, const std::string& src, const char* what) {
    const GLuint s = glCreateShader(type);
    const char* text = src.c_str();
    glShaderSource(s, 1, &text, nullptr);
    glCompileShader(s);
    GLint ok = 0;
    glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[4096];
        glGetShaderInfoLog(s, sizeof log, nullptr, log);
        throw std::runtime_error(std::string("particle_floor: ") + what + " does not compile: " + log);
    }
    return s;
}

GLuint link(std::initializer_list<GLuint> shaders, const char* what, const char* const* feedback = nullptr,
            int feedbackCount = 0) {
    const GLuint p = glCreateProgram();
    for (GLuint s : shaders)
        glAttachShader(p, s);
    if (feedback) glTransformFeedbackVaryings(p, feedbackCount, feedback, GL_INTERLEAVED_ATTRIBS);
    glLinkProgram(p);
    GLint ok = 0;
    glGetProgramiv(p, GL_LINK_STATUS, &ok);
    if (!ok) throw std::runtime_error(std::string("particle_floor: ") + what + " does not link");
    return p;
}

// The step's uniforms (particle_motion.glsl): an emitter at the origin, gravity, the defaults'
// respawn (carry age) and bounce (reflect).
void setUniforms(GLuint p, unsigned step, unsigned count) {
    const float identity[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    glProgramUniformMatrix4fv(p, glGetUniformLocation(p, "u_emitter"), 1, GL_FALSE, identity);
    glProgramUniform2f(p, glGetUniformLocation(p, "u_emitterSize"), 10.0f, 10.0f);
    glProgramUniform3f(p, glGetUniformLocation(p, "u_velocity"), 0.0f, 0.0f, 5.0f);
    glProgramUniform1f(p, glGetUniformLocation(p, "u_spread"), 1.0f);
    glProgramUniform3f(p, glGetUniformLocation(p, "u_acceleration"), 0.0f, 0.0f, -9.81f);
    glProgramUniform1f(p, glGetUniformLocation(p, "u_krot"), 1.0f);
    glProgramUniform1f(p, glGetUniformLocation(p, "u_kvel"), 1.0f);
    glProgramUniform1f(p, glGetUniformLocation(p, "u_tmax"), kLifetime);
    glProgramUniform1f(p, glGetUniformLocation(p, "u_dt"), 1.0f / 60.0f);
    glProgramUniform1ui(p, glGetUniformLocation(p, "u_step"), step);
    glProgramUniform1ui(p, glGetUniformLocation(p, "u_seed"), 7u);
    glProgramUniform1i(p, glGetUniformLocation(p, "u_carryAge"), 1);
    glProgramUniform1i(p, glGetUniformLocation(p, "u_reflect"), 1);
    glProgramUniform1ui(p, glGetUniformLocation(p, "u_count"), count);
}

// The body every path shares: `p` read, then copied or updated.
std::string stepBody(bool update) {
    return update ? "    p = updateParticle(p, index);\n" : "";
}

std::string header(bool update) {
    return update
               ? readGlsl("particle_random.glsl") + readGlsl("particle_motion.glsl")
               : "struct Particle { float age; vec3 position; vec3 velocity; vec3 angles0; vec3 angles; };\n"
                 "uniform uint u_count;\n";
}

std::string computeSource(bool update, bool tbo) {
    std::string s = "#version 450 core\nlayout(local_size_x = 64) in;\n" + header(update);
    if (update) s += "uniform uint u_count;\n";
    s += tbo ? "layout(binding = 0) uniform samplerBuffer m_tex;\n"
               "float rec(uint at) { return texelFetch(m_tex, int(at)).x; }\n"
             : "layout(std430, binding = 0) readonly buffer In { float m_record[]; };\n"
               "float rec(uint at) { return m_record[at]; }\n";
    s += R"(layout(std430, binding = 1) writeonly buffer Out { float o_record[]; };
vec3 rec3(uint at) { return vec3(rec(at), rec(at + 1u), rec(at + 2u)); }
void main() {
    uint index = gl_GlobalInvocationID.y * gl_NumWorkGroups.x * 64u + gl_GlobalInvocationID.x;
    if (index >= u_count) return;
    uint at = 13u * index;
    Particle p = Particle(rec(at), rec3(at + 1u), rec3(at + 4u), rec3(at + 7u), rec3(at + 10u));
)" + stepBody(update) +
         R"(    o_record[at] = p.age;
    for (uint k = 0u; k < 3u; ++k) {
        o_record[at + 1u + k] = p.position[k];
        o_record[at + 4u + k] = p.velocity[k];
        o_record[at + 7u + k] = p.angles0[k];
        o_record[at + 10u + k] = p.angles[k];
    }
}
)";
    return s;
}

std::string computeVec4Source(bool update) {
    std::string s = "#version 450 core\nlayout(local_size_x = 64) in;\n" + header(update);
    if (update) s += "uniform uint u_count;\n";
    s += R"(layout(std430, binding = 0) readonly buffer S0 { vec4 s0[]; };
layout(std430, binding = 1) readonly buffer S1 { vec4 s1[]; };
layout(std430, binding = 2) readonly buffer S2 { vec4 s2[]; };
layout(std430, binding = 3) readonly buffer S3 { float s3[]; };
layout(std430, binding = 4) writeonly buffer O0 { vec4 o0[]; };
layout(std430, binding = 5) writeonly buffer O1 { vec4 o1[]; };
layout(std430, binding = 6) writeonly buffer O2 { vec4 o2[]; };
layout(std430, binding = 7) writeonly buffer O3 { float o3[]; };
void main() {
    uint index = gl_GlobalInvocationID.y * gl_NumWorkGroups.x * 64u + gl_GlobalInvocationID.x;
    if (index >= u_count) return;
    vec4 a = s0[index], b = s1[index], d = s2[index];
    Particle p = Particle(a.x, a.yzw, b.xyz, vec3(b.w, d.xy), vec3(d.zw, s3[index]));
)" + stepBody(update) +
         R"(    o0[index] = vec4(p.age, p.position);
    o1[index] = vec4(p.velocity, p.angles0.x);
    o2[index] = vec4(p.angles0.yz, p.angles.xy);
    o3[index] = p.angles.z;
}
)";
    return s;
}

std::string fragmentSource(bool update) {
    return "#version 450 core\n" + header(update) + R"(
layout(binding = 0) uniform sampler2D s0;
layout(binding = 1) uniform sampler2D s1;
layout(binding = 2) uniform sampler2D s2;
layout(binding = 3) uniform sampler2D s3;
layout(location = 0) out vec4 o0;
layout(location = 1) out vec4 o1;
layout(location = 2) out vec4 o2;
layout(location = 3) out float o3;
void main() {
    ivec2 c = ivec2(gl_FragCoord.xy);
    uint index = uint(c.y * 1024 + c.x);
    vec4 a = texelFetch(s0, c, 0), b = texelFetch(s1, c, 0), d = texelFetch(s2, c, 0);
    float e = texelFetch(s3, c, 0).x;
    Particle p = Particle(a.x, a.yzw, b.xyz, vec3(b.w, d.xy), vec3(d.zw, e));
)" + stepBody(update) +
           R"(    o0 = vec4(p.age, p.position);
    o1 = vec4(p.velocity, p.angles0.x);
    o2 = vec4(p.angles0.yz, p.angles.xy);
    o3 = p.angles.z;
}
)";
}

std::string feedbackSource(bool update) {
    return "#version 450 core\n" + header(update) + R"(
layout(location = 0) in vec4 a_state;
layout(location = 1) in vec3 a_velocity;
layout(location = 2) in vec3 a_angles0;
layout(location = 3) in vec3 a_angles;
out vec4 o_state;
out vec3 o_velocity;
out vec3 o_angles0;
out vec3 o_angles;
void main() {
    uint index = uint(gl_VertexID);
    Particle p = Particle(a_state.x, a_state.yzw, a_velocity, a_angles0, a_angles);
)" + stepBody(update) +
           R"(    o_state = vec4(p.age, p.position);
    o_velocity = p.velocity;
    o_angles0 = p.angles0;
    o_angles = p.angles;
}
)";
}

const char* const kFullscreen = R"(#version 450 core
void main() { gl_Position = vec4(vec2(gl_VertexID & 1, gl_VertexID >> 1) * 4.0 - 1.0, 0.0, 1.0); }
)";

enum Path { ComputeSsbo, ComputeTbo, ComputeVec4, FragmentMrt, Feedback, kPaths };
const char* const kPathNames[kPaths] = {"compute-ssbo", "compute-tbo", "compute-vec4", "fragment-mrt",
                                        "feedback"};

// Floats per particle of each of the four streams (compute-vec4) and textures (fragment-mrt).
constexpr int kStreamFloats[4] = {4, 4, 4, 1};

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

struct Bench {
    sgfx::OsmesaContext ctx{64, 64};
    unsigned count = 0;
    int rows = 0;
    std::vector<float> initial; // count records of 13 floats
    // Buffers (compute, feedback): two copies of the records; buffer-texture views of them.
    GLuint buffers[2]{}, views[2]{}, vaos[2]{};
    // Textures (fragment): two copies of four textures, and their framebuffers.
    GLuint textures[2][4]{}, framebuffers[2]{}, emptyVao = 0;
    // Streams (compute-vec4): two copies of four buffers, laid out as the textures.
    GLuint streams[2][4]{};
    GLuint programs[kPaths][2]{}; // [path][update]
    int current[kPaths]{};        // which copy holds M, per path
    unsigned steps[kPaths]{};     // steps run, per path (the RNG's step counter)

    void setUp(unsigned n) {
        count = n;
        rows = int((n + kTexWidth - 1) / kTexWidth);
        initial.assign(std::size_t(n) * kFloats, 0.0f);
        for (unsigned i = 0; i < n; ++i) // alive, ages spread over the lifetime (a steady stream)
            initial[std::size_t(i) * kFloats] = kLifetime * 0.999f * (float(i) + 0.5f) / float(n);
        glCreateBuffers(2, buffers);
        glCreateTextures(GL_TEXTURE_BUFFER, 2, views);
        glCreateVertexArrays(2, vaos);
        glCreateVertexArrays(1, &emptyVao);
        for (int c = 0; c < 2; ++c) {
            glNamedBufferData(buffers[c], GLsizeiptr(initial.size() * sizeof(float)), nullptr,
                              GL_DYNAMIC_COPY);
            glTextureBuffer(views[c], GL_R32F, buffers[c]);
            static const int sizes[4] = {4, 3, 3, 3}, offsets[4] = {0, 16, 28, 40};
            for (GLuint a = 0; a < 4; ++a) {
                glVertexArrayAttribFormat(vaos[c], a, sizes[a], GL_FLOAT, GL_FALSE, GLuint(offsets[a]));
                glVertexArrayAttribBinding(vaos[c], a, 0);
                glEnableVertexArrayAttrib(vaos[c], a);
            }
            glVertexArrayVertexBuffer(vaos[c], 0, buffers[c], 0, kFloats * sizeof(float));
            glCreateBuffers(4, streams[c]);
            for (int k = 0; k < 4; ++k)
                glNamedBufferData(streams[c][k],
                                  GLsizeiptr(std::size_t(n) * std::size_t(kStreamFloats[k]) * sizeof(float)),
                                  nullptr, GL_DYNAMIC_COPY);
            glCreateTextures(GL_TEXTURE_2D, 4, textures[c]);
            glCreateFramebuffers(1, &framebuffers[c]);
            for (int k = 0; k < 4; ++k) {
                glTextureStorage2D(textures[c][k], 1, k == 3 ? GL_R32F : GL_RGBA32F, kTexWidth, rows);
                glNamedFramebufferTexture(framebuffers[c], GLenum(GL_COLOR_ATTACHMENT0 + k), textures[c][k],
                                          0);
            }
            const GLenum draw[4] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2,
                                    GL_COLOR_ATTACHMENT3};
            glNamedFramebufferDrawBuffers(framebuffers[c], 4, draw);
            if (glCheckNamedFramebufferStatus(framebuffers[c], GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
                throw std::runtime_error("particle_floor: the fragment path's framebuffer is incomplete");
        }
        const char* const varyings[] = {"o_state", "o_velocity", "o_angles0", "o_angles"};
        for (int u = 0; u < 2; ++u) {
            programs[ComputeSsbo][u] =
                link({compile(GL_COMPUTE_SHADER, computeSource(u, false), "compute")}, "compute");
            programs[ComputeVec4][u] =
                link({compile(GL_COMPUTE_SHADER, computeVec4Source(u), "compute")}, "compute");
            programs[ComputeTbo][u] =
                link({compile(GL_COMPUTE_SHADER, computeSource(u, true), "compute")}, "compute");
            programs[FragmentMrt][u] = link({compile(GL_VERTEX_SHADER, kFullscreen, "full screen"),
                                             compile(GL_FRAGMENT_SHADER, fragmentSource(u), "fragment")},
                                            "fragment");
            programs[Feedback][u] =
                link({compile(GL_VERTEX_SHADER, feedbackSource(u), "feedback")}, "feedback", varyings, 4);
        }
    }

    // Every path's copy M := the initial records.
    void reset() {
        for (int p = 0; p < kPaths; ++p)
            current[p] = 0, steps[p] = 0;
        glNamedBufferSubData(buffers[0], 0, GLsizeiptr(initial.size() * sizeof(float)), initial.data());
        // The textures hold the same 13 floats a particle as 4 + 4 + 4 + 1 (particles past count: 0).
        std::vector<float> t[4];
        for (int k = 0; k < 4; ++k)
            t[k].assign(std::size_t(kTexWidth) * std::size_t(rows) * (k == 3 ? 1 : 4), 0.0f);
        for (std::size_t i = 0; i < count; ++i)
            for (int f = 0; f < kFloats; ++f) {
                const int k = f / 4;
                t[k][i * (k == 3 ? 1 : 4) + std::size_t(f % 4)] = initial[i * kFloats + std::size_t(f)];
            }
        for (int k = 0; k < 4; ++k) {
            glTextureSubImage2D(textures[0][k], 0, 0, 0, kTexWidth, rows, k == 3 ? GL_RED : GL_RGBA, GL_FLOAT,
                                t[k].data());
            glNamedBufferSubData(
                streams[0][k], 0,
                GLsizeiptr(std::size_t(count) * std::size_t(kStreamFloats[k]) * sizeof(float)), t[k].data());
        }
        glFinish();
    }

    // One step of `path` (M → M'), ended by glFinish; its wall-clock ms.
    double step(Path path, bool update) {
        const GLuint prog = programs[path][update];
        const int src = current[path], dst = 1 - src;
        setUniforms(prog, steps[path], count);
        const auto t0 = std::chrono::steady_clock::now();
        glUseProgram(prog);
        if (path == ComputeSsbo || path == ComputeTbo || path == ComputeVec4) {
            if (path == ComputeVec4) {
                for (int k = 0; k < 4; ++k) {
                    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, GLuint(k), streams[src][k]);
                    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, GLuint(4 + k), streams[dst][k]);
                }
            } else {
                if (path == ComputeTbo)
                    glBindTextureUnit(0, views[src]);
                else
                    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, buffers[src]);
                glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, buffers[dst]);
            }
            const unsigned groups = (count + 63) / 64, row = std::min(groups, 128u);
            glDispatchCompute(row, (groups + row - 1) / row, 1);
            glMemoryBarrier(GL_ALL_BARRIER_BITS);
        } else if (path == FragmentMrt) {
            glBindFramebuffer(GL_FRAMEBUFFER, framebuffers[dst]);
            glViewport(0, 0, kTexWidth, rows);
            for (int k = 0; k < 4; ++k)
                glBindTextureUnit(GLuint(k), textures[src][k]);
            glBindVertexArray(emptyVao);
            glDrawArrays(GL_TRIANGLES, 0, 3);
        } else {
            glBindFramebuffer(GL_FRAMEBUFFER, 0);
            glEnable(GL_RASTERIZER_DISCARD);
            glBindVertexArray(vaos[src]);
            glBindBufferBase(GL_TRANSFORM_FEEDBACK_BUFFER, 0, buffers[dst]);
            glBeginTransformFeedback(GL_POINTS);
            glDrawArrays(GL_POINTS, 0, GLsizei(count));
            glEndTransformFeedback();
            glDisable(GL_RASTERIZER_DISCARD);
        }
        glFinish();
        const double ms =
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        current[path] = dst;
        ++steps[path];
        return ms;
    }

    // The records M of `path`, 13 floats each.
    std::vector<float> records(Path path) const {
        const int c = current[path];
        std::vector<float> out(std::size_t(count) * kFloats);
        if (path != FragmentMrt && path != ComputeVec4) {
            glGetNamedBufferSubData(buffers[c], 0, GLsizeiptr(out.size() * sizeof(float)), out.data());
            return out;
        }
        for (int k = 0; k < 4; ++k) {
            const int per = kStreamFloats[k];
            std::vector<float> t(std::size_t(kTexWidth) * std::size_t(rows) * std::size_t(per));
            if (path == ComputeVec4)
                glGetNamedBufferSubData(streams[c][k], 0,
                                        GLsizeiptr(std::size_t(count) * std::size_t(per) * sizeof(float)),
                                        t.data());
            else
                glGetTextureImage(textures[c][k], 0, k == 3 ? GL_RED : GL_RGBA, GL_FLOAT,
                                  GLsizei(t.size() * sizeof(float)), t.data());
            for (std::size_t i = 0; i < count; ++i)
                for (int f = 4 * k; f < std::min(4 * k + 4, kFloats); ++f)
                    out[i * kFloats + std::size_t(f)] = t[i * std::size_t(per) + std::size_t(f % 4)];
        }
        return out;
    }
};

} // namespace

int main(int argc, char** argv) {
    unsigned count = 1000000;
    int rounds = 5, steps = 4;
    CLI::App app{"The fastest GL particle step on this driver: copy floors and real updates per path"};
    app.add_option("--count", count, "particles (default 10^6)")->check(CLI::Range(1u, 1u << 24));
    app.add_option("--rounds", rounds, "interleaved rounds (default 5)")->check(CLI::Range(1, 1000));
    app.add_option("--steps", steps, "timed steps per path and round (default 4)")
        ->check(CLI::Range(1, 1000));
    CLI11_PARSE(app, argc, argv);
    try {
        Bench b;
        if (!sgfx_gladLoadGL(reinterpret_cast<SGFX_GLADloadfunc>(b.ctx.procAddress())))
            throw std::runtime_error("particle_floor: glad could not load GL");
        GLint maxTexels = 0;
        glGetIntegerv(GL_MAX_TEXTURE_BUFFER_SIZE, &maxTexels);
        if (double(count) * kFloats > double(maxTexels))
            throw std::runtime_error("particle_floor: --count " + std::to_string(count) +
                                     " needs a buffer texture of " +
                                     std::to_string(std::uint64_t(count) * kFloats) +
                                     " texels; this driver allows " + std::to_string(maxTexels));
        GLint64 maxBlock = 0;
        glGetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &maxBlock);
        if (double(count) * kFloats * sizeof(float) > double(maxBlock))
            throw std::runtime_error("particle_floor: --count " + std::to_string(count) + " needs " +
                                     std::to_string(std::uint64_t(count) * kFloats * sizeof(float)) +
                                     "-byte storage blocks; this driver allows " + std::to_string(maxBlock));
        b.setUp(count);
        std::printf("GL_RENDERER: %s\n", reinterpret_cast<const char*>(glGetString(GL_RENDERER)));
        for (int update = 0; update < 2; ++update) {
            std::vector<double> ms[kPaths];
            for (int r = 0; r < rounds; ++r) {
                for (int p = 0; p < kPaths; ++p) {
                    b.reset();               // the buffer paths share their two copies
                    b.step(Path(p), update); // untimed: compilation, first touch
                    std::vector<double> one;
                    for (int s = 0; s < steps; ++s)
                        one.push_back(b.step(Path(p), update));
                    ms[p].push_back(median(one));
                }
            }
            // Every path, 3 steps from the same records: they agree bit for bit.
            const auto run = [&](Path p) {
                b.reset();
                for (int s = 0; s < 3; ++s)
                    b.step(p, update);
                return b.records(p);
            };
            const std::vector<float> reference = run(ComputeSsbo);
            if (!update &&
                std::memcmp(reference.data(), b.initial.data(), reference.size() * sizeof(float)) != 0)
                throw std::runtime_error("particle_floor: the compute copy changed the records");
            for (int p = 1; p < kPaths; ++p) {
                const std::vector<float> got = run(Path(p));
                std::size_t bad = 0, first = got.size();
                for (std::size_t i = 0; i < got.size(); ++i)
                    if (std::memcmp(&got[i], &reference[i], sizeof(float)) != 0) {
                        if (!bad) first = i;
                        ++bad;
                    }
                if (bad)
                    throw std::runtime_error(
                        std::string("particle_floor: ") + kPathNames[p] +
                        " does not reproduce compute-ssbo's " + "records: " + std::to_string(bad) +
                        " floats differ, the first particle " + std::to_string(first / kFloats) + " float " +
                        std::to_string(first % kFloats) + " (" + std::to_string(got[first]) + " against " +
                        std::to_string(reference[first]) + ")");
            }
            if (const GLenum e = glGetError(); e != GL_NO_ERROR)
                throw std::runtime_error("particle_floor: GL error " + std::to_string(e));
            for (int p = 0; p < kPaths; ++p)
                std::printf("FLOOR path=%s op=%s ms=%.2f count=%u rounds=%d steps=%d\n", kPathNames[p],
                            update ? "update" : "copy", median(ms[p]), count, rounds, steps);
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "%s\n", e.what());
        return 1;
    }
    return 0;
}

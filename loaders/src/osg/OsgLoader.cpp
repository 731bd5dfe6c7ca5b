// loadOsg: osgDB reads, the converters in this folder build the sgfx graph (OsgConvert.h).
#include "OsgConvert.h"

#include <osg/Billboard>
#include <osg/Geode>
#include <osg/NodeVisitor>
#include <osgDB/ReadFile>
#include <osgDB/Registry>

#include <chrono>
#include <cmath>
#include <csignal>
#include <functional>
#include <mutex>
#include <thread>

#include <cstdio>
#include <fstream>
#include <sstream>
#include <sys/wait.h>
#include <unistd.h>

namespace sgfx {

namespace osgbridge {

bool FixedState::operator<(const FixedState& o) const {
    const auto key = [](const FixedState& s) {
        return std::tie(s.material, s.lighting, s.texture0, s.texEnv, s.texGen, s.alphaCutoff, s.twoSided,
                        s.flat, s.polygonMode, s.program, s.textures, s.samplerUnits);
    };
    return key(*this) < key(o);
}

void Context::warn(const std::string& what) {
    auto& w = warnings[what];
    if (w.count++ == 0) w.where = where();
}

std::string Context::where() const {
    std::string s;
    for (const auto& p : path)
        s += "/" + p;
    return s.empty() ? "/" : s;
}

void Context::charge(std::size_t n, const char* what) {
    bytes += n;
    if (bytes > options.memoryLimit)
        throw LoadError("sgfx: model '" + file.string() + "': " + what + " at " + where() +
                        " takes the load past " + std::to_string(options.memoryLimit) +
                        " bytes (OsgOptions::memoryLimit)");
}

float srgbToLinear(float s) {
    const double v = std::isfinite(s) ? std::clamp(double(s), 0.0, 1.0) : 0.0; // a corrupt file's NaN: black
    return float(v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4));
}

glm::vec4 linearColor(const osg::Vec4& c) {
    return {srgbToLinear(c.r()), srgbToLinear(c.g()), srgbToLinear(c.b()),
            std::isfinite(c.a()) ? std::clamp(c.a(), 0.0f, 1.0f) : 1.0f};
}

namespace {

/// OSG's own statistics: every Geometry once per parent path (osgUtil::StatsVisitor's way), and
/// every program of the file, so samplers are known before any uniform is converted.
/// It runs before the conversion, so it is also where a corrupt file's cycles (a node that is its
/// own ancestor through shared UniqueIDs) and absurd nesting are refused, before any recursion.
class CountVisitor : public osg::NodeVisitor {
public:
    static constexpr std::size_t kMaxDepth = 512;
    explicit CountVisitor(const std::filesystem::path& file)
        : osg::NodeVisitor(TRAVERSE_ALL_CHILDREN)
        , file_(file) {}
    void apply(osg::Node& node) override {
        const Enter enter(*this, node);
        collect(node.getStateSet());
        traverse(node);
    }
    void apply(osg::Geode& geode) override {
        const Enter enter(*this, geode);
        collect(geode.getStateSet());
        for (unsigned i = 0; i < geode.getNumDrawables(); ++i)
            count(geode.getDrawable(i));
        traverse(geode);
    }
    /// The node on the current path for the time of its visit.
    struct Enter {
        Enter(CountVisitor& v, const osg::Node& n)
            : visitor(v) {
            auto& p = v.path_;
            if (std::find(p.begin(), p.end(), &n) != p.end())
                throw LoadError("sgfx: model '" + v.file_.string() + "': " + n.className() + " '" +
                                n.getName() +
                                "' is its own ancestor (a cycle in the graph): the file is corrupt");
            if (p.size() >= kMaxDepth)
                throw LoadError("sgfx: model '" + v.file_.string() + "': nodes nested deeper than " +
                                std::to_string(kMaxDepth) + " levels: the file is corrupt");
            p.push_back(&n);
        }
        ~Enter() { visitor.path_.pop_back(); }
        Enter(const Enter&) = delete;
        Enter& operator=(const Enter&) = delete;
        CountVisitor& visitor;
    };
    void count(osg::Drawable* d) {
        if (!d) return;
        collect(d->getStateSet());
        const auto* g = d->asGeometry();
        if (!g) return;
        ++stats.drawables;
        if (g->getVertexArray()) stats.vertices += g->getVertexArray()->getNumElements();
        stats.triangles += triangleCount(*g);
    }
    static std::size_t triangleCount(const osg::Geometry& g) {
        std::size_t n = 0;
        for (unsigned p = 0; p < g.getNumPrimitiveSets(); ++p) {
            const auto* set = g.getPrimitiveSet(p);
            const auto add = [&](GLenum mode, std::size_t c) {
                switch (mode) {
                case GL_TRIANGLES:
                    n += c / 3;
                    break;
                case GL_TRIANGLE_STRIP:
                case GL_TRIANGLE_FAN:
                case GL_POLYGON:
                    n += c >= 3 ? c - 2 : 0;
                    break;
                case GL_QUADS:
                    n += c / 4 * 2;
                    break;
                case GL_QUAD_STRIP:
                    n += c >= 4 ? (c - 2) / 2 * 2 : 0;
                    break;
                default:
                    break;
                }
            };
            if (const auto* l = dynamic_cast<const osg::DrawArrayLengths*>(set))
                for (auto len : *l)
                    add(set->getMode(), std::size_t(len));
            else
                add(set->getMode(), set->getNumIndices());
        }
        return n;
    }
    void collect(const osg::StateSet* s) {
        if (!s) return;
        if (const auto* p = dynamic_cast<const osg::Program*>(s->getAttribute(osg::StateAttribute::PROGRAM)))
            programs.push_back(p);
    }
    OsgStats stats;
    std::vector<const osg::Program*> programs;

private:
    const std::filesystem::path& file_;
    std::vector<const osg::Node*> path_;
};

std::string readerMessage(const osgDB::ReaderWriter::ReadResult& r) {
    if (!r.message().empty()) return r.message();
    switch (r.status()) {
    case osgDB::ReaderWriter::ReadResult::FILE_NOT_HANDLED:
        return "no osgDB plugin reads this format";
    case osgDB::ReaderWriter::ReadResult::FILE_NOT_FOUND:
        return "file not found";
    case osgDB::ReaderWriter::ReadResult::ERROR_IN_READING_FILE:
        return "osgDB could not parse it";
    default:
        return "osgDB returned no node (empty, truncated or not a scene)";
    }
}

/// Runs `read` in a forked child first (OsgOptions::isolateReader): LoadError when the child dies
/// on a signal or runs out of time; a child that finished either way lets the caller read for real.
void readInChild(const std::function<bool()>& read, const OsgOptions& options, const std::string& name) {
    if (!options.isolateReader) return;
    std::fflush(nullptr);
    const pid_t pid = fork();
    if (pid < 0) return; // no process to spare: read in this one
    if (pid == 0) {
        int code = 3;
        try {
            code = read() ? 0 : 3;
        } catch (...) {
            code = 4;
        }
        _exit(code); // no destructors, atexit handlers or leak checks of the parent's state
    }
    const auto start = std::chrono::steady_clock::now();
    int status = 0;
    for (;;) {
        const pid_t r = waitpid(pid, &status, WNOHANG);
        if (r == pid) break;
        if (r < 0) return;
        if (std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() >
            options.readTimeout) {
            kill(pid, SIGKILL);
            waitpid(pid, &status, 0);
            throw LoadError("sgfx: model '" + name + "': osgDB's reader did not finish within " +
                            std::to_string(int(options.readTimeout)) + " s (OsgOptions::readTimeout)");
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    if (WIFSIGNALED(status))
        throw LoadError("sgfx: model '" + name + "': osgDB's reader crashed on it (signal " +
                        std::to_string(WTERMSIG(status)) + "): the file is corrupt");
    // 0: read, 3: no node, 4: an exception; anything else is a death that did not end on a signal
    // (a sanitizer's report exits with 1, std::terminate's abort may be caught and turned into an exit).
    const int code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    if (code == 4) // std::bad_alloc for a count the file declares, mostly: not tried again here
        throw LoadError("sgfx: model '" + name +
                        "': osgDB's reader failed on it (an exception, most often memory " +
                        "for a count the file declares): the file is corrupt");
    if (code != 0 && code != 3)
        throw LoadError("sgfx: model '" + name + "': osgDB's reader died on it (exit status " +
                        std::to_string(code) + "): the file is corrupt");
}

osg::ref_ptr<osgDB::Options> readerOptions(const OsgOptions& options, const std::filesystem::path& folder,
                                           bool environment) {
    osg::ref_ptr<osgDB::Options> o = new osgDB::Options;
    for (const auto& p : options.databasePaths)
        o->getDatabasePathList().push_back(p.string());
    if (!folder.empty()) o->getDatabasePathList().push_back(folder.string());
    if (const char* env = environment ? std::getenv("OSG_FILE_PATH") : nullptr) { // once per load
        std::stringstream ss(env);
        for (std::string item; std::getline(ss, item, ':');)
            if (!item.empty()) o->getDatabasePathList().push_back(item);
    }
    return o;
}

/// One osgDB read at a time in the process, first in a child (readInChild): a fork while another
/// thread (the pager's) is inside osgDB would copy its locks held, and the child would wait forever.
/// A reader that throws (std::bad_alloc on a huge declared count) is a LoadError too.
osg::ref_ptr<osg::Node> guardedRead(const std::function<osgDB::ReaderWriter::ReadResult()>& read,
                                    const OsgOptions& options, const std::string& name) {
    static std::mutex oneReader;
    const std::lock_guard lock(oneReader);
    readInChild([&] { return read().validNode(); }, options, name);
    try {
        auto result = read();
        if (!result.validNode()) throw LoadError("sgfx: model '" + name + "': " + readerMessage(result));
        return result.getNode();
    } catch (const LoadError&) {
        throw;
    } catch (const std::exception& e) {
        throw LoadError("sgfx: model '" + name + "': osgDB's reader failed: " + e.what());
    }
}

osg::ref_ptr<osg::Node> readNode(const std::filesystem::path& file, const OsgOptions& options) {
    const auto fail = [&](const std::string& why) {
        return LoadError("sgfx: model '" + file.string() + "': " + why);
    };
    std::error_code ec;
    if (!std::filesystem::is_regular_file(file, ec)) throw fail("no such file");
    auto o = readerOptions(options, file.parent_path(), true);
    return guardedRead([&] { return osgDB::Registry::instance()->readNode(file.string(), o.get()); }, options,
                       file.string());
}

void convertPrograms(Context& cx, const std::vector<const osg::Program*>& programs, OsgStats& stats) {
    for (const auto* p : programs) {
        if (cx.programs.count(p)) continue;
        const std::string name = p->getName().empty() ? "osg_program" : p->getName();
        std::vector<CompatShader> shaders;
        for (unsigned i = 0; i < p->getNumShaders(); ++i) {
            const auto* s = p->getShader(i);
            const auto stage = s->getType() == osg::Shader::VERTEX        ? CompatStage::Vertex
                               : s->getType() == osg::Shader::FRAGMENT    ? CompatStage::Fragment
                               : s->getType() == osg::Shader::GEOMETRY    ? CompatStage::Geometry
                               : s->getType() == osg::Shader::COMPUTE     ? CompatStage::Compute
                               : s->getType() == osg::Shader::TESSCONTROL ? CompatStage::TessControl
                                                                          : CompatStage::TessEvaluation;
            shaders.push_back({stage, s->getShaderSource()});
        }
        CompatOptions options; // the program's own attribute bindings (osg::Program::addBindAttribLocation)
        for (const auto& [attribute, location] : p->getAttribBindingList())
            options.attributeLocations[attribute] = int(location);
        try {
            auto compat = translateCompatibilityProgram(name, shaders, options);
            for (const auto& s : compat.samplers)
                cx.samplerNames.push_back(s.name);
            cx.programs[p] = std::move(compat);
            ++stats.programs;
        } catch (const std::exception& e) {
            cx.warn(std::string("osg::Program not converted, drawn with the built-in material: ") + e.what());
            cx.programs[p] = std::nullopt;
        }
    }
}

} // namespace

std::shared_ptr<Group> convertRead(osg::Node& node, const std::filesystem::path& file,
                                   const OsgOptions& options, OsgStats* stats);

} // namespace osgbridge

bool osgSupported() {
    return true;
}

const std::vector<std::string>& osgExtensions() {
    // Formats Debian's OpenSceneGraph 3.6 plugins read as scenes (osgdb_*); glTF, OBJ, OFF, PLY
    // and STL stay with sgfx's own loaders.
    static const std::vector<std::string> e{".osg", ".osgt", ".osgb", ".osgx", ".ive", ".flt", ".3ds",
                                            ".ac",  ".lwo",  ".lws",  ".dxf",  ".x",   ".md2", ".bsp"};
    return e;
}

std::shared_ptr<Group> loadOsg(const std::filesystem::path& file, const OsgOptions& options,
                               OsgStats* stats) {
    auto node = osgbridge::readNode(file, options);
    return osgbridge::convertRead(*node, file, options, stats);
}

std::shared_ptr<Group> loadOsgFromMemory(std::span<const std::byte> bytes, const std::string& extension,
                                         const std::string& nameForErrors, const OsgOptions& options,
                                         OsgStats* stats) {
    const auto fail = [&](const std::string& why) {
        return LoadError("sgfx: model '" + nameForErrors + "': " + why);
    };
    const std::string ext = extension.empty() || extension[0] != '.' ? extension : extension.substr(1);
    auto* rw = osgDB::Registry::instance()->getReaderWriterForExtension(ext);
    if (!rw) throw fail("no osgDB plugin reads '" + extension + "'");
    const std::string text(reinterpret_cast<const char*>(bytes.data()), bytes.size());
    auto o = osgbridge::readerOptions(options, {}, false);
    const auto read = [&] {
        std::istringstream in(text, std::ios::binary);
        return rw->readNode(in, o.get());
    };
    auto node = osgbridge::guardedRead(read, options, nameForErrors);
    return osgbridge::convertRead(*node, nameForErrors, options, stats);
}

namespace osgbridge {

/// Removes every child link that closes a cycle (a corrupt file's shared UniqueIDs can make a node
/// its own ancestor): ref_ptr cycles would otherwise never be freed.
void breakCycles(osg::Node& node, std::vector<osg::Node*>& path) {
    auto* group = node.asGroup();
    if (!group || path.size() >= CountVisitor::kMaxDepth) return;
    path.push_back(&node);
    for (unsigned i = group->getNumChildren(); i-- > 0;) {
        osg::Node* child = group->getChild(i);
        if (std::find(path.begin(), path.end(), child) != path.end())
            group->removeChild(i);
        else if (child)
            breakCycles(*child, path);
    }
    path.pop_back();
}

void breakCycles(osg::Node& root) {
    std::vector<osg::Node*> path;
    breakCycles(root, path);
}

std::shared_ptr<Group> convertRead(osg::Node& node, const std::filesystem::path& file,
                                   const OsgOptions& options, OsgStats* stats) {
    Context cx;
    cx.file = file;
    cx.options = options;
    CountVisitor count(file);
    try {
        node.accept(count);
    } catch (const LoadError&) {
        breakCycles(node); // else the file's nodes keep each other alive after the LoadError
        throw;
    }
    OsgStats local = count.stats;
    convertPrograms(cx, count.programs, local);

    auto root = Group::create();
    root->name = file.filename().string();
    // OpenGL's default, which OSG keeps: GL_CULL_FACE off (sgfx's default culls back faces).
    root->getOrCreateStateSet().cullFace.set(CullFace::None);
    try {
        root->addChild(convertNode(cx, node, FixedState{}));
    } catch (const std::invalid_argument& e) { // an sgfx setter refused a value the file holds
        throw LoadError("sgfx: model '" + file.string() + "': at " + cx.where() + ": " + e.what());
    } catch (const std::out_of_range& e) {
        throw LoadError("sgfx: model '" + file.string() + "': at " + cx.where() + ": " + e.what());
    }
    for (const auto& [what, w] : cx.warnings)
        local.warnings.push_back(what + " at " + w.where +
                                 (w.count > 1 ? " (" + std::to_string(w.count) + " in all)" : ""));
    if (stats)
        *stats = std::move(local);
    else
        for (const auto& w : local.warnings)
            std::fprintf(stderr, "sgfx: %s: %s\n", file.string().c_str(), w.c_str());
    return root;
}

} // namespace osgbridge

} // namespace sgfx

#include "sgfx/FrameGraph.h"

#include <sgfx_glad/gl.h>

#include <algorithm>
#include <cstdio>
#include <sstream>
#include <stdexcept>

namespace sgfx {

namespace {

struct FormatInfo {
    GLenum format;
    const char* name;
    int bytes;
};
static_assert(format::Depth32F == GL_DEPTH_COMPONENT32F && format::Rgba16F == GL_RGBA16F &&
              format::Rgba32F == GL_RGBA32F && format::Rg32F == GL_RG32F && format::R32F == GL_R32F &&
              format::R16F == GL_R16F && format::R8 == GL_R8 && format::Rgba8 == GL_RGBA8 &&
              format::Srgb8Alpha8 == GL_SRGB8_ALPHA8);
constexpr FormatInfo kFormats[] = {{GL_DEPTH_COMPONENT32F, "D32F", 4},
                                   {GL_DEPTH_COMPONENT24, "D24", 4},
                                   {GL_DEPTH24_STENCIL8, "D24S8", 4},
                                   {GL_STENCIL_INDEX8, "S8", 1},
                                   {GL_RGBA16F, "RGBA16F", 8},
                                   {GL_RGBA32F, "RGBA32F", 16},
                                   {GL_RG32F, "RG32F", 8},
                                   {GL_RG16F, "RG16F", 4},
                                   {GL_R32F, "R32F", 4},
                                   {GL_R16F, "R16F", 2},
                                   {GL_R8, "R8", 1},
                                   {GL_RGBA8, "RGBA8", 4},
                                   {GL_SRGB8_ALPHA8, "SRGB8_A8", 4},
                                   {GL_R11F_G11F_B10F, "R11G11B10F", 4}};

const FormatInfo* formatInfo(unsigned format) {
    for (const FormatInfo& f : kFormats)
        if (f.format == format) return &f;
    return nullptr;
}

int scaled(int side, const SizeRule& r) {
    const long n = long(side) * r.num;
    const long v = r.round == SizeRule::Round::Up ? (n + r.den - 1) / r.den : n / r.den;
    return std::max(int(v), r.min);
}

std::string escape(std::string_view s) {
    std::string out;
    for (char c : s) {
        if (c == '"' || c == '\\') out += '\\';
        out += c;
    }
    return out;
}

} // namespace

glm::ivec2 SizeRule::resolve(glm::ivec2 drawSize, glm::ivec2 viewSize) const {
    if (den <= 0 || num <= 0) throw std::invalid_argument("sgfx: SizeRule needs a positive num/den");
    if (base == Base::Fixed) return glm::max(fixed, glm::ivec2(min));
    const glm::ivec2 b = base == Base::Draw ? drawSize : viewSize;
    return {scaled(b.x, *this), scaled(b.y, *this)};
}

std::size_t ResolvedDesc::bytes() const {
    const FormatInfo* f = formatInfo(format);
    const std::size_t base =
        std::size_t(f ? f->bytes : 4) * std::size_t(width) * std::size_t(height) * std::size_t(samples);
    return mipmaps ? base * 4 / 3 : base; // the chain adds a third
}

int ResolvedDesc::levels() const {
    if (!mipmaps) return 1;
    int n = 1;
    for (int side = std::max(width, height); side > 1; side /= 2)
        ++n;
    return n;
}

std::string formatName(unsigned format) {
    if (const FormatInfo* f = formatInfo(format)) return f->name;
    char buf[32];
    std::snprintf(buf, sizeof buf, "0x%04x", format);
    return buf;
}

ResourceId Blackboard::get(std::string_view name) const {
    const auto it = entries_.find(name);
    if (it == entries_.end())
        throw std::out_of_range("sgfx: frame graph: nothing was published as '" + std::string(name) + "'");
    return it->second;
}

// ---- declaration

ResourceId FrameGraph::Builder::create(std::string name, const TextureDesc& desc) {
    if (desc.format == 0 || desc.samples < 1)
        throw std::invalid_argument("sgfx: frame graph: pass '" + graph_.passes_[pass_].name + "' creates '" +
                                    name + "' without a format or with fewer than one sample");
    Resource& r = graph_.resources_.emplace_back();
    r.name = std::move(name);
    r.desc = desc;
    return {std::uint16_t(graph_.resources_.size() - 1), 0};
}

ResourceId FrameGraph::Builder::sample(ResourceId id, std::string_view binding) {
    return graph_.use(pass_, id, Access::Sample, false, false, binding);
}

ResourceId FrameGraph::Builder::colour(ResourceId id, int attachment, bool keep) {
    return graph_.use(pass_, id, Access::ColourAttachment, true, keep, "colour" + std::to_string(attachment));
}

ResourceId FrameGraph::Builder::depth(ResourceId id, bool keep) {
    return graph_.use(pass_, id, Access::DepthAttachment, true, keep, "depth");
}

ResourceId FrameGraph::Builder::depthTest(ResourceId id) {
    return graph_.use(pass_, id, Access::DepthTest, false, false, "depth test");
}

void FrameGraph::Builder::sideEffect() {
    graph_.passes_[pass_].sideEffect = true;
}

FrameGraph::Resource& FrameGraph::resource(ResourceId id, std::string_view pass) {
    if (!id.valid() || id.index >= resources_.size())
        throw std::invalid_argument("sgfx: frame graph: pass '" + std::string(pass) +
                                    "' uses a resource handle that this graph never made");
    return resources_[id.index];
}

ResourceId FrameGraph::use(std::uint32_t pass, ResourceId id, Access access, bool write, bool keep,
                           std::string_view binding) {
    Pass& p = passes_[pass];
    Resource& r = resource(id, p.name);
    if (id.version + 1u != r.versions)
        throw std::logic_error(
            "sgfx: frame graph: pass '" + p.name + "' uses version " + std::to_string(id.version) + " of '" +
            r.name + "', which a later write replaced (now version " + std::to_string(r.versions - 1) + ")");
    const bool unwritten = !r.imported && id.version == 0;
    if (!write && unwritten)
        throw std::logic_error("sgfx: frame graph: pass '" + p.name + "' reads '" + r.name +
                               "', which no pass before it writes");
    if (!write || (keep && !unwritten)) p.reads.push_back({id, access, std::string(binding)});
    if (!write) return id;
    const ResourceId next{id.index, r.versions++};
    p.writes.push_back({next, access, std::string(binding)});
    return next;
}

void FrameGraph::addPass(std::string name, const std::function<void(Builder&)>& setup, Execute execute,
                         std::string phase) {
    Pass& p = passes_.emplace_back();
    p.name = std::move(name);
    p.phase = std::move(phase);
    p.execute = std::move(execute);
    Builder b(*this, std::uint32_t(passes_.size() - 1));
    if (setup) setup(b);
    compiled_ = false;
}

ResourceId FrameGraph::import(std::string name, const TextureDesc& desc, unsigned texture) {
    Resource& r = resources_.emplace_back();
    r.name = std::move(name);
    r.desc = desc;
    r.imported = true;
    r.texture = texture;
    return {std::uint16_t(resources_.size() - 1), 0};
}

void FrameGraph::present(ResourceId id) {
    resource(id, "present");
    presented_.push_back(id);
}

// ---- compile

// Reference counting as in Filament's DependencyGraph::cull: a pass lives while something reads
// what it writes; a version read by nobody drops its writer, which drops what that writer read.
void FrameGraph::cull() {
    std::vector<std::vector<int>> refs(resources_.size());
    std::vector<std::vector<int>> writer(resources_.size());
    for (std::size_t i = 0; i < resources_.size(); ++i) {
        refs[i].assign(resources_[i].versions, 0);
        writer[i].assign(resources_[i].versions, -1);
    }
    for (std::size_t p = 0; p < passes_.size(); ++p) {
        Pass& pass = passes_[p];
        pass.culled = false;
        pass.refs = int(pass.writes.size()) + (pass.sideEffect ? 1 : 0);
        for (const Use& u : pass.reads)
            ++refs[u.id.index][u.id.version];
        for (const Use& u : pass.writes) {
            writer[u.id.index][u.id.version] = int(p);
            if (resources_[u.id.index].imported)
                ++refs[u.id.index][u.id.version]; // written outside the graph
        }
    }
    for (const ResourceId& id : presented_)
        ++refs[id.index][id.version];
    std::vector<ResourceId> stack;
    for (std::size_t i = 0; i < resources_.size(); ++i)
        for (std::uint16_t v = 0; v < resources_[i].versions; ++v)
            if (refs[i][v] == 0 && writer[i][v] >= 0) stack.push_back({std::uint16_t(i), v});
    while (!stack.empty()) {
        const ResourceId id = stack.back();
        stack.pop_back();
        Pass& p = passes_[std::size_t(writer[id.index][id.version])];
        if (--p.refs > 0) continue;
        p.culled = true;
        for (const Use& u : p.reads)
            if (--refs[u.id.index][u.id.version] == 0 && writer[u.id.index][u.id.version] >= 0)
                stack.push_back(u.id);
    }
}

// First and last live use per transient resource, and the textures they need when a resource
// whose life is over hands its texture to a later one with the same description.
void FrameGraph::planLifetimes() {
    std::uint32_t position = 0;
    for (Pass& p : passes_) {
        if (p.culled) continue;
        for (const auto* uses : {&p.reads, &p.writes})
            for (const Use& u : *uses) {
                Resource& r = resources_[u.id.index];
                r.first = std::min(r.first, position);
                r.last = std::max(r.last, position);
            }
        ++position;
    }
    std::vector<std::pair<ResolvedDesc, bool>> slots; // description, in use
    for (std::uint32_t i = 0; i < position; ++i) {
        for (Resource& r : resources_) {
            if (r.imported || r.first != i) continue;
            auto free = std::find_if(slots.begin(), slots.end(),
                                     [&](const auto& s) { return !s.second && s.first == r.resolved; });
            if (free == slots.end()) free = slots.insert(slots.end(), {r.resolved, false});
            free->second = true;
            r.slot = int(free - slots.begin());
        }
        for (Resource& r : resources_)
            if (!r.imported && r.slot >= 0 && r.last == i) slots[std::size_t(r.slot)].second = false;
    }
    slots_ = slots.size();
}

void FrameGraph::compile(glm::ivec2 drawSize, glm::ivec2 viewSize) {
    for (Resource& r : resources_) {
        const glm::ivec2 size = r.desc.size.resolve(drawSize, viewSize);
        if (r.desc.mipmaps && r.desc.samples > 1)
            throw std::invalid_argument("sgfx: frame graph resource '" + r.name +
                                        "' asks for mipmaps and several samples; mipmaps are single-sample");
        r.resolved = {r.desc.format, size.x, size.y, r.desc.samples, r.desc.filter, r.desc.wrapS, r.desc.mipmaps};
        r.first = ~0u;
        r.last = 0;
        r.slot = -1;
        if (!r.imported) r.texture = 0;
    }
    cull();
    planLifetimes();
    compiled_ = true;
}

// ---- execute

void FrameGraph::execute(ResourceAllocator& allocator,
                         const std::function<void(std::string_view, const Execute&)>& run) {
    if (!compiled_) throw std::logic_error("sgfx: frame graph: execute() before compile()");
    std::uint32_t position = 0;
    for (Pass& p : passes_) {
        if (p.culled) continue;
        for (Resource& r : resources_)
            if (!r.imported && r.first == position) r.texture = allocator.acquire(r.resolved, r.name);
        run(p.name, p.execute);
        for (Resource& r : resources_)
            if (!r.imported && r.last == position && r.texture) {
                allocator.release(r.texture, r.resolved);
                r.texture = 0;
            }
        ++position;
    }
}

// ---- queries

bool FrameGraph::culled(std::string_view pass) const {
    for (const Pass& p : passes_)
        if (p.name == pass) return p.culled;
    throw std::out_of_range("sgfx: frame graph has no pass '" + std::string(pass) + "'");
}

std::vector<std::string> FrameGraph::livePasses() const {
    std::vector<std::string> out;
    for (const Pass& p : passes_)
        if (!p.culled) out.push_back(p.name);
    return out;
}

std::vector<std::string> FrameGraph::passNames() const {
    std::vector<std::string> out;
    for (const Pass& p : passes_)
        out.push_back(p.name);
    return out;
}

unsigned FrameGraph::texture(ResourceId id) const {
    return id.valid() && id.index < resources_.size() ? resources_[id.index].texture : 0;
}

const ResolvedDesc& FrameGraph::resolved(ResourceId id) const {
    return resources_.at(id.index).resolved;
}

const std::string& FrameGraph::resourceName(ResourceId id) const {
    return resources_.at(id.index).name;
}

std::vector<std::string> FrameGraph::writers(std::string_view resource) const {
    std::vector<std::string> out;
    for (const Pass& p : passes_)
        if (!p.culled && std::any_of(p.writes.begin(), p.writes.end(),
                                     [&](const Use& u) { return resources_[u.id.index].name == resource; }))
            out.push_back(p.name);
    return out;
}

std::size_t FrameGraph::textureSlots() const {
    return slots_;
}

std::size_t FrameGraph::transientBytes() const {
    // One texture per slot: the largest of the equal descriptions is the description itself.
    std::vector<bool> counted(slots_, false);
    std::size_t bytes = 0;
    for (const Resource& r : resources_)
        if (!r.imported && r.slot >= 0 && !counted[std::size_t(r.slot)]) {
            counted[std::size_t(r.slot)] = true;
            bytes += r.resolved.bytes();
        }
    return bytes;
}

std::string FrameGraph::dotCluster(std::string_view cluster,
                                   const std::map<std::string, double>& gpuMs) const {
    std::ostringstream o;
    const std::string id = "c" + std::to_string(std::hash<std::string_view>{}(cluster) % 1000000);
    o << "  subgraph \"cluster_" << escape(cluster) << "\" {\n    label=\"" << escape(cluster) << "\";\n";
    for (std::size_t i = 0; i < passes_.size(); ++i) {
        const Pass& p = passes_[i];
        const auto t = gpuMs.find(p.name);
        char ms[32] = "-";
        if (t != gpuMs.end()) std::snprintf(ms, sizeof ms, "%.3f ms", t->second);
        o << "    " << id << "_p" << i << " [shape=box, label=\"" << escape(p.name) << "\\n"
          << ms << "\""
          << (p.culled ? ", style=dashed, color=grey, fontcolor=grey"
                       : ", style=filled, fillcolor=\"#dde8f5\"")
          << "];\n";
    }
    for (std::size_t i = 0; i < resources_.size(); ++i) {
        const Resource& r = resources_[i];
        o << "    " << id << "_r" << i << " [shape=ellipse, label=\"" << escape(r.name) << "\\n"
          << formatName(r.resolved.format) << " " << r.resolved.width << "x" << r.resolved.height;
        if (r.resolved.samples > 1) o << " x" << r.resolved.samples;
        if (r.imported)
            o << " (imported)";
        else if (r.slot >= 0)
            o << " [slot " << r.slot << "]";
        o << "\"" << (r.imported ? ", style=bold" : "") << (!r.imported && r.slot < 0 ? ", color=grey" : "")
          << "];\n";
    }
    for (std::size_t i = 0; i < passes_.size(); ++i) {
        const Pass& p = passes_[i];
        const char* style = p.culled ? ", style=dashed, color=grey" : "";
        for (const Use& u : p.reads)
            o << "    " << id << "_r" << u.id.index << " -> " << id << "_p" << i << " [label=\""
              << escape(u.binding) << "\"" << style << "];\n";
        for (const Use& u : p.writes)
            o << "    " << id << "_p" << i << " -> " << id << "_r" << u.id.index << " [label=\"v"
              << u.id.version << "\"" << style << "];\n";
    }
    o << "  }\n";
    return o.str();
}

} // namespace sgfx

#include "sgfx/ShaderComposer.h"

#include "EmbeddedShaders.h"
#include "render/TextureUnits.h"
#include "sgfx/Geometry.h"
#include "sgfx/Material.h"
#include "sgfx/gl/Objects.h"

#include <cstdlib>
#include <regex>
#include <sstream>

namespace sgfx {

namespace {

// Which snippet field feeds which marker of the base shader.
struct Hook {
    std::string_view marker;
    std::string ShaderSnippet::*field;
    std::string_view label;
};
constexpr std::string_view kMarker = "// @sgfx:";
const Hook kVertexHooks[] = {{"vertex_decl", &ShaderSnippet::vertexDecl, "vertexDecl"},
                             {"vertex", &ShaderSnippet::vertexCode, "vertexCode"}};
const Hook kFragmentHooks[] = {{"fragment_decl", &ShaderSnippet::fragmentDecl, "fragmentDecl"},
                               {"ambient", &ShaderSnippet::ambientCode, "ambientCode"},
                               {"transmitted", &ShaderSnippet::transmittedCode, "transmittedCode"},
                               {"color", &ShaderSnippet::colorCode, "colorCode"}};

// Mesa drops the source-string number of #line from its messages, so the source is also
// encoded in the line number itself: source k, line n → k * kLinesPerSource + n.
constexpr long kLinesPerSource = 10000;

std::string lineDirective(int line, std::size_t source) {
    return "#line " + std::to_string(long(source) * kLinesPerSource + line) + " " + std::to_string(source) +
           "\n";
}

// Emits `text` as its own source string so driver messages point into it.
void appendChunk(std::string& out, std::vector<std::string>& names, std::string name, std::string_view text) {
    out += lineDirective(1, names.size());
    names.push_back(std::move(name));
    out += text;
    if (!text.empty() && text.back() != '\n') out += '\n';
}

// A statement hook's chunk in a scope of its own, so snippets' locals never collide; the braces
// sit on lines of their own, so the code may open with a directive (#ifndef ...).
void appendScoped(std::string& out, std::vector<std::string>& names, std::string name, std::string_view code) {
    out += "{\n";
    appendChunk(out, names, std::move(name), code);
    out += "}\n";
}

// `void main()` of an application's shader, which the wraps rename.
const std::regex& mainPattern() {
    static const std::regex re(R"(\bvoid\s+main\s*\(\s*(void)?\s*\))");
    return re;
}

// The storage-buffer bindings pose.glsl reads (ShaderComposer.h).
std::string poseDefines() {
    return "#define SGFX_JOINTS_BINDING " + std::to_string(kJointsBinding) + "\n#define SGFX_MORPH_BINDING " +
           std::to_string(kMorphBinding) + "\n#define SGFX_MORPH_WEIGHTS_BINDING " +
           std::to_string(kMorphWeightsBinding) + "\n";
}

std::string preamble(std::span<const ShaderSnippet* const> snippets, FeatureMask features) {
    std::string p = ShaderComposer::featureDefines(features);
    // Each material map's texture unit and uv index (render/TextureUnits.h).
    for (std::size_t k = 0; k < kMaterialMapCount; ++k)
        p += std::string("#define ") + render::kMaterialMapDefines[k] + " " +
             std::to_string(render::materialUnit(MaterialMap(k))) + "\n";
    p += "#define SGFX_MAP_COUNT " + std::to_string(kMaterialMapCount) + "\n";
    p += "#define SGFX_UNIT_TRANSMISSION " + std::to_string(render::kTransmissionUnit) + "\n";
    p += poseDefines();
    for (const ShaderSnippet* s : snippets)
        p += s->defines.empty() ? "" : s->defines + "\n";
    p += shaders::embedded("frame_block.glsl");
    return p;
}

std::string splitVersion(std::string_view& src, std::string_view shaderName) {
    const auto start = src.find_first_not_of(" \t\r\n");
    if (start == std::string_view::npos || src.compare(start, 8, "#version") != 0)
        throw ShaderError("sgfx: shader '" + std::string(shaderName) + "' must start with a #version line");
    const auto eol = src.find('\n', start);
    std::string version(src.substr(start, eol - start));
    src = eol == std::string_view::npos ? std::string_view{} : src.substr(eol + 1);
    return version + "\n";
}

// Copies a base stage line by line, expanding hook markers with the snippets' code.
std::string composeStage(std::string_view name, std::string_view src, std::span<const Hook> hooks,
                         std::span<const ShaderSnippet* const> snippets, FeatureMask features,
                         std::vector<std::string>& names) {
    std::string out = splitVersion(src, name);
    appendChunk(out, names, "<sgfx preamble>", preamble(snippets, features));
    const std::size_t baseSource = names.size();
    names.emplace_back(name);
    out += lineDirective(2, baseSource);
    int line = 2;
    std::istringstream in{std::string(src)};
    for (std::string text; std::getline(in, text); ++line) {
        if (text.starts_with("#include \"")) {
            // A built-in GLSL file, as its own source string so messages name it and its line.
            const std::string file = text.substr(10, text.find('"', 10) - 10);
            const std::string_view body = shaders::embedded(file);
            if (body.empty())
                throw ShaderError("sgfx: shader '" + std::string(name) + "' line " + std::to_string(line) +
                                  ": no built-in file '" + file + "' to include");
            appendChunk(out, names, file, body);
            out += lineDirective(line + 1, baseSource);
            continue;
        }
        const auto pos = text.find(kMarker);
        if (pos == std::string::npos) {
            out += text;
            out += '\n';
            continue;
        }
        const std::string marker = text.substr(pos + kMarker.size());
        const Hook* hook = nullptr;
        for (const Hook& h : hooks)
            if (marker == h.marker) hook = &h;
        if (!hook)
            throw ShaderError("sgfx: shader '" + std::string(name) + "' line " + std::to_string(line) +
                              ": unknown hook marker '" + marker + "'");
        const bool fileScope = hook->marker.ends_with("_decl");
        for (const ShaderSnippet* s : snippets) {
            const std::string& code = s->*(hook->field);
            if (code.empty()) continue;
            std::string chunk = s->name + "." + std::string(hook->label);
            if (fileScope)
                appendChunk(out, names, std::move(chunk), code);
            else
                appendScoped(out, names, std::move(chunk), code);
        }
        out += lineDirective(line + 1, baseSource);
    }
    return out;
}

// KHR_materials_clearcoat, _specular and _transmission (with _volume): one bit each (their maps are chosen by
// a uniform), set only when the extension changes the result. `uses` marks the coordinates read.
template <class Uses> FeatureMask extensionFeatures(const Material& m, Uses& uses) {
    FeatureMask f = 0;
    if (m.clearcoat > 0.0f) {
        f |= FeatureClearcoat;
        uses(m.clearcoatTexture, MaterialMap::Clearcoat);
        uses(m.clearcoatRoughnessTexture, MaterialMap::ClearcoatRoughness);
        if (uses(m.clearcoatNormalTexture, MaterialMap::ClearcoatNormal)) f |= FeatureWorldPosition;
    }
    const bool specTex = uses(m.specularTexture, MaterialMap::Specular);
    const bool colourTex = uses(m.specularColorTexture, MaterialMap::SpecularColor);
    if (m.specularFactor != 1.0f || m.specularColorFactor != glm::vec3(1.0f) || specTex || colourTex)
        f |= FeatureSpecularExt;
    if (m.transmission > 0.0f) {
        // The refracted ray starts at the fragment's world position.
        f |= FeatureTransmission | FeatureWorldPosition;
        uses(m.transmissionTexture, MaterialMap::Transmission);
        uses(m.thicknessTexture, MaterialMap::Thickness);
    }
    return f;
}

std::string describe(std::string_view base, std::span<const ShaderSnippet* const> snippets) {
    std::string d = std::string(base) + " + [";
    for (std::size_t i = 0; i < snippets.size(); ++i)
        d += (i ? ", " : "") + snippets[i]->name;
    return d + "]";
}

// A foreign vertex shader over a skinned or morphed mesh: its position, normal and tangent inputs
// (locations 0, 1, 2, as for built-in materials) become globals that a wrapper main fills with
// the posed values before calling the application's main, so its own arithmetic sees the pose.
std::string poseForeignVertex(const ShaderProgram& prog, FeatureMask features,
                              std::vector<std::string>& names) {
    const std::regex& mainRe = mainPattern();
    static const std::regex inRe(
        R"(layout\s*\(\s*location\s*=\s*([012])\s*\)\s*in\s+(vec3|vec4)\s+([A-Za-z_][A-Za-z0-9_]*)\s*;)");
    const std::string& src = prog.vertexSource;
    if (!std::regex_search(src, mainRe))
        throw ShaderError("sgfx: foreign vertex shader '" + prog.name + "' has no `void main()` to wrap");
    std::string inputs[3], types[3];
    for (auto it = std::sregex_iterator(src.begin(), src.end(), inRe); it != std::sregex_iterator(); ++it) {
        const int loc = (*it)[1].str()[0] - '0';
        inputs[loc] = (*it)[3].str();
        types[loc] = (*it)[2].str();
    }
    if (inputs[0].empty())
        throw ShaderError(
            "sgfx: foreign vertex shader '" + prog.name +
            "' declares no `layout(location = 0) in vec3` (or vec4) position for its skinned or "
            "morphed mesh to be posed into");
    std::string_view body = src;
    std::string out = splitVersion(body, prog.name);
    // Storage buffers need GLSL 4.30; a core 3.30 shader compiles unchanged as 4.50 core.
    const std::size_t digits = out.find_first_of("0123456789");
    if (digits == std::string::npos || std::atoi(out.c_str() + digits) < 430) out = "#version 450 core\n";
    out += ShaderComposer::featureDefines(features & FeaturePoseMask) + poseDefines();
    out += lineDirective(2, 0);
    std::string user = std::regex_replace(std::string(body), mainRe, "void sgfx_user_vertex_main()");
    user = std::regex_replace(user, inRe, "$2 $3;"); // the inputs become plain globals
    out += user + "\n";
    appendChunk(out, names, "pose.glsl", shaders::embedded("pose.glsl"));
    std::string wrap =
        "layout(location = 0) in vec3 sgfx_a_position;\nlayout(location = 1) in vec3 sgfx_a_normal;\n"
        "layout(location = 2) in vec4 sgfx_a_tangent;\nvoid main() {\n"
        "    vec3 p = sgfx_a_position, n = sgfx_a_normal, t = sgfx_a_tangent.xyz;\n"
        "    sgfx_pose(p, n, t);\n";
    const char* posed[3] = {"p", "n", "t"};
    const char* fourth[3] = {"1.0", "0.0", "sgfx_a_tangent.w"};
    for (int k = 0; k < 3; ++k)
        if (!inputs[k].empty())
            wrap +=
                "    " + inputs[k] + " = " +
                (types[k] == "vec4" ? "vec4(" + std::string(posed[k]) + ", " + fourth[k] + ")" : posed[k]) +
                ";\n";
    wrap += "    sgfx_user_vertex_main();\n}\n";
    appendChunk(out, names, "<sgfx pose wrapper>", wrap);
    return out;
}

} // namespace

ShaderComposer::ShaderComposer() = default;
ShaderComposer::~ShaderComposer() = default;

const BaseShader& ShaderComposer::blinnPhong() {
    static const BaseShader base{"blinn_phong", "blinn_phong.vert",
                                 std::string(shaders::embedded("blinn_phong.vert")), "blinn_phong.frag",
                                 std::string(shaders::embedded("blinn_phong.frag"))};
    return base;
}

std::string_view ShaderComposer::fullscreenVertex() {
    return shaders::embedded("blit.vert");
}

ComposedProgram ShaderComposer::composeBuiltin(const BaseShader& base,
                                               std::span<const ShaderSnippet* const> snippets,
                                               FeatureMask features) {
    ComposedProgram p;
    const bool geometry = !base.geometrySource.empty();
    p.vertex = composeStage(base.vertexName, base.vertexSource,
                            geometry ? std::span<const Hook>{} : std::span<const Hook>(kVertexHooks),
                            snippets, features, p.vertexSources);
    if (geometry)
        p.geometry = composeStage(base.geometryName, base.geometrySource, kVertexHooks, snippets, features,
                                  p.geometrySources);
    if (!base.fragmentSource.empty())
        p.fragment = composeStage(base.fragmentName, base.fragmentSource, kFragmentHooks, snippets, features,
                                  p.fragmentSources);
    p.feedbackVaryings = base.feedbackVaryings;
    p.feedbackInterleaved = base.feedbackInterleaved;
    p.description = describe(base.name, snippets);
    std::string variant = featureDefines(features);
    for (auto& c : variant)
        if (c == '\n') c = ' ';
    for (const std::string_view drop : {"#define ", "SGFX_"})
        for (auto at = variant.find(drop); at != std::string::npos; at = variant.find(drop))
            variant.erase(at, drop.size());
    p.description += " {" + variant.substr(0, variant.size() - 1) + "}";
    return p;
}

std::string ShaderComposer::featureDefines(FeatureMask f) {
    static const std::pair<FeatureMask, const char*> names[] = {
        {FeatureBaseMap, "SGFX_BASE_MAP"},
        {FeatureAlphaMap, "SGFX_ALPHA_MAP"},
        {FeatureNormalMap, "SGFX_NORMAL_MAP"},
        {FeatureVertexColor, "SGFX_VERTEX_COLOR"},
        {FeatureNormals, "SGFX_NORMALS"},
        {FeatureTangents, "SGFX_TANGENTS"},
        {FeatureTexCoords, "SGFX_TEXCOORDS"},
        {FeatureAlphaMask, "SGFX_ALPHA_MASK"},
        {FeatureBlend, "SGFX_BLEND"},
        {FeatureSpecular, "SGFX_SPECULAR"},
        {FeatureVertexLighting, "SGFX_VERTEX_LIGHTING"},
        {FeatureWorldPosition, "SGFX_WORLD_POSITION"},
        {FeaturePointLights, "SGFX_POINT_LIGHTS"},
        {FeatureBlendPremultiplied, "SGFX_BLEND_PREMULTIPLIED"},
        {FeatureBlendAdditive, "SGFX_BLEND_ADDITIVE"},
        {FeatureBlendMultiply, "SGFX_BLEND_MULTIPLY"},
        {FeatureGBuffer, "SGFX_GBUFFER"},
        {FeatureMetallicRoughness, "SGFX_METALLIC_ROUGHNESS"},
        {FeatureMetalRoughMap, "SGFX_METAL_ROUGH_MAP"},
        {FeatureOcclusionMap, "SGFX_OCCLUSION_MAP"},
        {FeatureEmissiveMap, "SGFX_EMISSIVE_MAP"},
        {FeatureTexCoords1, "SGFX_TEXCOORDS1"},
        {FeatureUvTransform, "SGFX_UV_TRANSFORM"},
        {FeatureInstanced, "SGFX_INSTANCED"},
        {FeatureBatched, "SGFX_BATCHED"},
        {FeatureUnlit, "SGFX_UNLIT"},
        {FeatureClearcoat, "SGFX_CLEARCOAT"},
        {FeatureSpecularExt, "SGFX_SPECULAR_EXT"},
        {FeatureLightAttenuation, "SGFX_LIGHT_ATTENUATION"},
        {FeatureLightList, "SGFX_LIGHT_LIST"},
        {FeatureTransmission, "SGFX_TRANSMISSION"},
        {FeatureSkinned, "SGFX_SKINNED"},
        {FeatureMorphed, "SGFX_MORPHED"},
        {FeatureDebugConstant, "SGFX_DEBUG_CONSTANT"}};
    std::string d;
    for (const auto& [bit, name] : names)
        if (f & bit) d += std::string("#define ") + name + "\n";
    d += "#define SGFX_LIGHT_COUNT " + std::to_string((f & FeatureLightCountMask) >> FeatureLightCountShift) +
         "\n";
    return d;
}

FeatureMask ShaderComposer::withWorldPosition(FeatureMask f, bool hasSnippets) {
    const bool derivedNormal = !(f & FeatureNormals) || ((f & FeatureNormalMap) && !(f & FeatureTangents));
    if (hasSnippets || derivedNormal ||
        (f & (FeatureSpecular | FeaturePointLights | FeatureVertexLighting | FeatureLightAttenuation |
              FeatureLightList)))
        f |= FeatureWorldPosition;
    return f;
}

FeatureMask ShaderComposer::poseFeatures(const Geometry& g) {
    return (g.skin ? FeatureMask(FeatureSkinned) : 0u) |
           (g.morphTargets.empty() ? 0u : FeatureMask(FeatureMorphed));
}

FeatureMask ShaderComposer::blendFeatures(bool blended, BlendMode blend) {
    if (!blended) return 0;
    switch (blend) {
    case BlendMode::Premultiplied:
        return FeatureBlendPremultiplied;
    case BlendMode::Additive:
        return FeatureBlendAdditive;
    case BlendMode::Multiply:
        return FeatureBlendMultiply;
    default:
        return 0;
    }
}

FeatureMask ShaderComposer::featuresFor(const Material* m, const Geometry& g, bool blended, BlendMode blend) {
    // Only what the material reads is interpolated: every varying costs per fragment.
    FeatureMask f = blendFeatures(blended, blend);
    if (!g.normals.empty()) f |= FeatureNormals;
    if (!g.colors.empty()) f |= FeatureVertexColor;
    if (!g.instances.empty()) f |= FeatureInstanced;
    f |= poseFeatures(g);
    if (blended) f |= FeatureBlend;
    if (m) {
        // A map is used when its texture is set and the coordinates it reads exist.
        auto uses = [&](const std::shared_ptr<Texture>& t, MaterialMap map) {
            if (!t) return false;
            const TextureMapping& mapping = m->mapping(map);
            if ((mapping.texCoord == 1 ? g.texcoords1 : g.texcoords).empty()) return false;
            f |= FeatureTexCoords;
            if (mapping.texCoord == 1) f |= FeatureTexCoords1;
            if (!mapping.isIdentity()) f |= FeatureUvTransform;
            return true;
        };
        if (uses(m->baseColorTexture, MaterialMap::BaseColor)) f |= FeatureBaseMap;
        if (uses(m->alphaTexture, MaterialMap::Alpha)) f |= FeatureAlphaMap;
        if (uses(m->normalTexture, MaterialMap::Normal)) {
            f |= FeatureNormalMap;
            if (!g.tangents.empty()) f |= FeatureTangents;
        }
        if (m->alphaCutoff) f |= FeatureAlphaMask;
        if (m->model == ShadingModel::Unlit) return f | FeatureUnlit; // no light: no other map is read
        if (m->model == ShadingModel::MetallicRoughness) {
            f |= FeatureMetallicRoughness | FeatureSpecular; // always a specular lobe
            if (uses(m->metallicRoughnessTexture, MaterialMap::MetallicRoughness)) f |= FeatureMetalRoughMap;
            f |= extensionFeatures(*m, uses);
        } else if (m->specular != glm::vec3(0.0f)) {
            f |= FeatureSpecular;
        }
        if (uses(m->emissiveTexture, MaterialMap::Emissive)) f |= FeatureEmissiveMap;
        if (uses(m->occlusionTexture, MaterialMap::Occlusion)) f |= FeatureOcclusionMap;
    }
    return f;
}

ComposedProgram ShaderComposer::composeForeign(const ShaderProgram& prog,
                                               std::span<const ShaderSnippet* const> snippets,
                                               FeatureMask features) {
    ComposedProgram p;
    p.description = describe(prog.name, snippets);
    // Vertex stage: the application's, untouched (snippets' vertex code does not apply to it),
    // unless its mesh is skinned or morphed: then the wrap poses the attributes it reads.
    p.vertexSources = {prog.name + ".vert"};
    p.vertex =
        features & FeaturePoseMask ? poseForeignVertex(prog, features, p.vertexSources) : prog.vertexSource;
    if (snippets.empty()) {
        p.fragmentSources = {prog.name + ".frag"};
        p.fragment = prog.fragmentSource;
        return p;
    }
    const std::regex& mainRe = mainPattern();
    static const std::regex outRe(
        R"((layout\s*\(\s*location\s*=\s*0\s*\)\s*)?out\s+vec4\s+([A-Za-z_][A-Za-z0-9_]*)\s*;)");
    const std::string& src = prog.fragmentSource;
    if (!std::regex_search(src, mainRe))
        throw ShaderError("sgfx: foreign fragment shader '" + prog.name + "' has no `void main()` to wrap");
    std::string output;
    bool located = false;
    for (auto it = std::sregex_iterator(src.begin(), src.end(), outRe); it != std::sregex_iterator(); ++it) {
        if (output.empty() || (*it)[1].matched) output = (*it)[2].str();
        located = (*it)[1].matched;
        if (located) break;
    }
    if (output.empty())
        throw ShaderError("sgfx: foreign fragment shader '" + prog.name +
                          "' declares no `out vec4` colour output for the effects to modify");
    std::string_view body = src;
    std::string out = splitVersion(body, prog.name);
    out += featureDefines(features & FeatureBlendKindMask);
    if (features & FeatureBlend) out += "#define SGFX_BLEND\n";
    for (const ShaderSnippet* s : snippets)
        out += s->defines.empty() ? "" : s->defines + "\n";
    p.fragmentSources.push_back(prog.name + ".frag");
    out += lineDirective(2, 0);
    std::string user = std::regex_replace(std::string(body), mainRe, "void sgfx_user_main()");
    // Snippets may add outputs (weighted blended OIT adds location 1); GLSL then wants every
    // output located, so the application's colour output is pinned to location 0.
    if (!located)
        user = std::regex_replace(user, std::regex("\\bout\\s+vec4\\s+" + output + "\\s*;"),
                                  "layout(location = 0) out vec4 " + output + ";",
                                  std::regex_constants::format_first_only);
    out += user;
    out += '\n';
    if (src.find("SgfxFrame") == std::string::npos)
        appendChunk(out, p.fragmentSources, "<sgfx frame block>", shaders::embedded("frame_block.glsl"));
    for (const ShaderSnippet* s : snippets)
        if (!s->fragmentDecl.empty())
            appendChunk(out, p.fragmentSources, s->name + ".fragmentDecl", s->fragmentDecl);
    // The wrapper: run the application's main, then the effects on its output. The world
    // position comes from the window position and depth through the inverse view-projection.
    std::string wrap =
        "void main() {\n    sgfx_user_main();\n"
        "    vec4 sgfx_ndc = vec4((gl_FragCoord.xy - sgfx_viewport.xy) / sgfx_viewport.zw * 2.0 - 1.0,"
        " gl_FragCoord.z * 2.0 - 1.0, 1.0);\n"
        "    vec4 sgfx_world4 = sgfx_invViewProjection * sgfx_ndc;\n"
        "    vec3 sgfx_worldPos = sgfx_world4.xyz / sgfx_world4.w;\n"
        "    vec3 sgfx_eyePos = sgfx_eye.xyz;\n"
        "    vec4 sgfx_color = " +
        output + ";\n";
    appendChunk(out, p.fragmentSources, "<sgfx wrapper>", wrap);
    for (const ShaderSnippet* s : snippets)
        if (!s->colorCode.empty())
            appendScoped(out, p.fragmentSources, s->name + ".colorCode", s->colorCode);
    appendChunk(out, p.fragmentSources, "<sgfx wrapper>", "    " + output + " = sgfx_color;\n}\n");
    p.fragment = std::move(out);
    return p;
}

std::string ShaderComposer::translateLog(std::string_view log, std::span<const std::string> names) {
    // Mesa: "0:12(5): error: ..."; NVIDIA: "0(12) : error ...".
    static const std::regex mesa(R"(^(\d+):(\d+)\((\d+)\):\s*(.*)$)");
    static const std::regex nvidia(R"(^(\d+)\((\d+)\)\s*:\s*(.*)$)");
    std::string out;
    std::istringstream in{std::string(log)};
    for (std::string line; std::getline(in, line);) {
        std::smatch m;
        std::size_t src = 0;
        std::string lineNo, msg;
        if (std::regex_match(line, m, mesa)) {
            src = std::stoul(m[1]);
            lineNo = m[2];
            msg = m[4];
        } else if (std::regex_match(line, m, nvidia)) {
            src = std::stoul(m[1]);
            lineNo = m[2];
            msg = m[3];
        } else {
            if (!line.empty()) out += line + "\n";
            continue;
        }
        long n = std::stol(lineNo);
        if (n >= kLinesPerSource) {
            src = std::size_t(n / kLinesPerSource);
            n %= kLinesPerSource;
        }
        const std::string name = src < names.size() ? names[src] : "source " + std::to_string(src);
        out += name + ":" + std::to_string(n) + ": " + msg + "\n";
    }
    return out;
}

gl::Program& ShaderComposer::cached(std::string key, std::span<const ShaderSnippet* const> snippets,
                                    const std::function<ComposedProgram()>& compose) {
    for (const ShaderSnippet* s : snippets)
        key += "|" + s->name;
    if (auto it = cache_.find(key); it != cache_.end()) {
        ++hits_;
        return *it->second;
    }
    ++misses_;
    auto prog = std::make_unique<gl::Program>(compose());
    return *cache_.emplace(std::move(key), std::move(prog)).first->second;
}

gl::Program& ShaderComposer::program(const BaseShader& base, std::span<const ShaderSnippet* const> snippets,
                                     FeatureMask features) {
    return cached("base:" + base.name + ":" + std::to_string(features), snippets,
                  [&] { return composeBuiltin(base, snippets, features); });
}

gl::Program& ShaderComposer::program(const ShaderProgram* foreign,
                                     std::span<const ShaderSnippet* const> snippets, FeatureMask features) {
    if (!foreign) return program(blinnPhong(), snippets, features);
    // Keyed by identity and text, so editing a ShaderProgram's source yields a new variant.
    std::string key =
        "foreign:" + std::to_string(reinterpret_cast<std::uintptr_t>(foreign)) + ":" +
        std::to_string(std::hash<std::string>{}(foreign->vertexSource + foreign->fragmentSource));
    key += ":" + std::to_string(features);
    return cached(std::move(key), snippets, [&] { return composeForeign(*foreign, snippets, features); });
}

void ShaderComposer::clear() {
    cache_.clear();
}

} // namespace sgfx

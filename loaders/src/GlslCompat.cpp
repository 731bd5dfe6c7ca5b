// OSG compatibility-profile GLSL → sgfx GLSL 450 core foreign programs (GlslCompat.h).
// The sources are split into tokens (identifiers, comments, whitespace, the rest), so every
// replacement happens at identifier boundaries and never inside a comment; line numbers are
// kept (a `#line` directive puts the driver's messages on the original lines).
#include "sgfx/GlslCompat.h"

#include <algorithm>
#include <cctype>
#include <set>
#include <unordered_map>

namespace sgfx {
namespace {

enum class Tok { Ident, Space, Comment, Directive, Other };
struct Token {
    Tok kind;
    std::string text;
    int line;
    bool lineStart; ///< first token of its line but for whitespace (preprocessor lines)
};

bool identStart(char c) {
    return std::isalpha(static_cast<unsigned char>(c)) || c == '_';
}
bool identChar(char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
}

// The end of a `#version` or `#extension` line starting at i (one token: it is dropped whole), or i.
std::size_t directiveEnd(std::string_view s, std::size_t i) {
    std::size_t j = i + 1;
    while (j < s.size() && (s[j] == ' ' || s[j] == '\t'))
        ++j;
    const std::string_view rest = s.substr(j);
    if (!rest.starts_with("version") && !rest.starts_with("extension")) return i;
    const std::size_t eol = s.find('\n', i);
    return eol == std::string_view::npos ? s.size() : eol;
}

std::vector<Token> tokenize(std::string_view s) {
    std::vector<Token> out;
    int line = 1;
    bool lineStart = true;
    for (std::size_t i = 0; i < s.size();) {
        const std::size_t start = i;
        Tok kind = Tok::Other;
        const char c = s[i];
        const char next = i + 1 < s.size() ? s[i + 1] : '\0';
        if (c == '/' && next == '/') {
            kind = Tok::Comment;
            i = std::min(s.find('\n', i), s.size());
        } else if (c == '/' && next == '*') {
            kind = Tok::Comment;
            const std::size_t end = s.find("*/", i + 2);
            i = end == std::string_view::npos ? s.size() : end + 2;
        } else if (std::isspace(static_cast<unsigned char>(c))) {
            kind = Tok::Space;
            while (i < s.size() && std::isspace(static_cast<unsigned char>(s[i])))
                ++i;
        } else if (identStart(c)) {
            kind = Tok::Ident;
            while (i < s.size() && identChar(s[i]))
                ++i;
        } else if (std::isdigit(static_cast<unsigned char>(c)) ||
                   (c == '.' && std::isdigit(static_cast<unsigned char>(next)))) {
            while (i < s.size() && (identChar(s[i]) || s[i] == '.'))
                ++i; // a number, "1.0e5" included: its letters are no identifier
        } else if (c == '#' && lineStart && directiveEnd(s, i) != i) {
            kind = Tok::Directive;
            i = directiveEnd(s, i);
        } else {
            ++i;
        }
        Token t{kind, std::string(s.substr(start, i - start)), line, lineStart};
        line += int(std::count(t.text.begin(), t.text.end(), '\n'));
        lineStart = kind == Tok::Space || kind == Tok::Comment
                        ? lineStart || t.text.find('\n') != std::string::npos
                        : false;
        out.push_back(std::move(t));
    }
    return out;
}

bool isCode(const Token& t) {
    return t.kind != Tok::Space && t.kind != Tok::Comment;
}

// The next token after i that is neither whitespace nor a comment (or tokens.size()).
std::size_t nextCode(const std::vector<Token>& t, std::size_t i) {
    for (++i; i < t.size(); ++i)
        if (isCode(t[i])) return i;
    return t.size();
}

// Keeps only the newlines of a token, so the lines after it keep their numbers.
void blank(Token& t) {
    t.text = std::string(std::size_t(std::count(t.text.begin(), t.text.end(), '\n')), '\n');
}

const char* stageName(CompatStage s) {
    switch (s) {
    case CompatStage::Vertex:
        return "vertex";
    case CompatStage::Fragment:
        return "fragment";
    case CompatStage::Geometry:
        return "geometry";
    case CompatStage::TessControl:
        return "tessellation control";
    case CompatStage::TessEvaluation:
        return "tessellation evaluation";
    case CompatStage::Compute:
        return "compute";
    }
    return "?";
}

struct Context {
    const std::string& program;
    CompatStage stage;
    std::vector<std::string>& notes;

    [[noreturn]] void fail(int line, const std::string& what) const {
        throw CompatError("sgfx: OSG program '" + program + "', " + stageName(stage) + " shader line " +
                          std::to_string(line) + ": " + what);
    }
    void note(const std::string& text) const {
        if (std::find(notes.begin(), notes.end(), text) == notes.end()) notes.push_back(text);
    }
};

// What one stage reads and writes after the replacement.
struct Stage {
    CompatStage stage = CompatStage::Vertex;
    std::vector<Token> tokens;
    std::set<std::string> used; ///< osg_* names the prologue defines
    int texCoords = 0;          ///< gl_TexCoord entries (largest index + 1; 8 when indexed at run time)
    int version = 110;
    std::string output; ///< fragment: the colour output the wrapper darkens by AO
    std::vector<CompatSampler> samplers;
};

// Built-ins renamed in every stage. The osg_* names are what the prologue defines; OSG's own
// aliased sources use them directly.
const std::unordered_map<std::string_view, std::string_view>& commonNames() {
    static const std::unordered_map<std::string_view, std::string_view> m = {
        {"gl_ModelViewMatrix", "osg_ModelViewMatrix"},
        {"gl_ModelViewProjectionMatrix", "osg_ModelViewProjectionMatrix"},
        {"gl_ProjectionMatrix", "osg_ProjectionMatrix"},
        {"gl_NormalMatrix", "osg_NormalMatrix"},
        {"gl_ModelViewMatrixInverse", "osg_ModelViewMatrixInverse"},
        {"gl_ModelViewMatrixTranspose", "osg_ModelViewMatrixTranspose"},
        {"gl_ModelViewMatrixInverseTranspose", "osg_ModelViewMatrixInverseTranspose"},
        {"gl_ProjectionMatrixInverse", "osg_ProjectionMatrixInverse"},
        {"gl_ModelViewProjectionMatrixInverse", "osg_ModelViewProjectionMatrixInverse"},
        {"gl_TextureMatrix", "osg_TextureMatrix"},
        {"gl_LightSource", "osg_LightSource"},
        {"gl_LightModel", "osg_LightModel"},
        {"gl_FrontMaterial", "osg_FrontMaterial"},
        {"gl_BackMaterial", "osg_BackMaterial"},
        {"gl_FrontLightModelProduct", "osg_FrontLightModelProduct"},
        {"gl_BackLightModelProduct", "osg_BackLightModelProduct"},
        {"gl_FrontLightProduct", "osg_FrontLightProduct"},
        {"gl_BackLightProduct", "osg_BackLightProduct"},
        {"gl_SecondaryColor", "osg_SecondaryColor"},
        {"gl_Fog", "osg_Fog"},
        {"gl_MaxLights", "8"},
        {"gl_MaxTextureCoords", "8"},
        {"gl_MaxTextureUnits", "8"},
        {"gl_MaxClipPlanes", "8"},
        {"texture1D", "texture"},
        {"texture2D", "texture"},
        {"texture3D", "texture"},
        {"textureCube", "texture"},
        {"texture2DRect", "texture"},
        {"texture1DProj", "textureProj"},
        {"texture2DProj", "textureProj"},
        {"texture3DProj", "textureProj"},
        {"texture2DRectProj", "textureProj"},
        {"texture1DLod", "textureLod"},
        {"texture2DLod", "textureLod"},
        {"texture3DLod", "textureLod"},
        {"textureCubeLod", "textureLod"},
        {"texture2DProjLod", "textureProjLod"},
        {"texture1DProjLod", "textureProjLod"},
        {"texture3DProjLod", "textureProjLod"},
        {"shadow1D", "osg_shadow"},
        {"shadow2D", "osg_shadow"},
        {"shadow2DRect", "osg_shadow"},
        {"shadow1DProj", "osg_shadowProj"},
        {"shadow2DProj", "osg_shadowProj"},
    };
    return m;
}

const std::unordered_map<std::string_view, std::string_view>& stageNames(CompatStage stage) {
    static const std::unordered_map<std::string_view, std::string_view> vertex = {
        {"attribute", "in"},
        {"varying", "out"},
        {"ftransform", "osg_ftransform"},
        {"gl_Vertex", "osg_Vertex"},
        {"gl_Normal", "osg_Normal"},
        {"gl_Color", "osg_Color"},
        {"gl_MultiTexCoord0", "osg_MultiTexCoord0"},
        {"gl_MultiTexCoord1", "osg_MultiTexCoord1"},
        {"gl_MultiTexCoord2", "osg_MultiTexCoord2"},
        {"gl_MultiTexCoord3", "osg_MultiTexCoord3"},
        {"gl_MultiTexCoord4", "osg_MultiTexCoord4"},
        {"gl_MultiTexCoord5", "osg_MultiTexCoord5"},
        {"gl_MultiTexCoord6", "osg_MultiTexCoord6"},
        {"gl_MultiTexCoord7", "osg_MultiTexCoord7"},
        {"gl_FrontColor", "osg_FrontColor"},
        {"gl_BackColor", "osg_BackColor"},
        {"gl_FrontSecondaryColor", "osg_FrontSecondaryColor"},
        {"gl_BackSecondaryColor", "osg_BackSecondaryColor"},
        {"gl_TexCoord", "osg_TexCoord"},
        {"gl_ClipVertex", "osg_ClipVertex"},
        {"gl_FogFragCoord", "osg_FogFragCoord"},
    };
    static const std::unordered_map<std::string_view, std::string_view> fragment = {
        {"varying", "in"},
        {"gl_Color", "osg_FrontColor"},
        {"gl_TexCoord", "osg_TexCoord"},
        {"gl_FragColor", "osg_FragColor"},
    };
    return stage == CompatStage::Vertex ? vertex : fragment;
}

// Built-ins that GLSL 450 core still has.
bool coreBuiltin(std::string_view n) {
    static const std::set<std::string_view> names = {
        "gl_Position",    "gl_PointSize",     "gl_ClipDistance",     "gl_CullDistance", "gl_VertexID",
        "gl_InstanceID",  "gl_FragCoord",     "gl_FrontFacing",      "gl_PointCoord",   "gl_FragDepth",
        "gl_PrimitiveID", "gl_SampleID",      "gl_SamplePosition",   "gl_SampleMask",   "gl_SampleMaskIn",
        "gl_Layer",       "gl_ViewportIndex", "gl_HelperInvocation", "gl_DepthRange",   "gl_NumSamples",
        "gl_PerVertex"};
    return names.contains(n) || (n.starts_with("gl_Max") && n != "gl_MaxVaryingFloats");
}

// Words that later GLSL versions reserve or give built-in meaning, which 1.10/1.20 sources may use
// as names (a variable `texture` would hide the texture() the translation calls).
bool laterReserved(std::string_view n, int version) {
    static const std::set<std::string_view> words = {
        "texture",    "textureLod", "textureProj", "textureProjLod", "textureGrad",   "textureSize",
        "texelFetch", "sample",     "smooth",      "flat",           "noperspective", "patch",
        "subroutine", "buffer",     "shared",      "coherent",       "restrict",      "readonly",
        "writeonly",  "resource",   "common",      "partition",      "active",        "filter",
        "precise",    "layout",     "uint"};
    return (version < 130 && words.contains(n)) || (version < 140 && n == "inverse");
}

// gl_FragData[0] becomes the colour output; other draw buffers have no sgfx equivalent.
void replaceFragData(const Context& ctx, Stage& st, std::size_t i) {
    auto& t = st.tokens;
    const std::size_t open = nextCode(t, i), index = nextCode(t, open), close = nextCode(t, index);
    if (close >= t.size() || t[open].text != "[" || t[index].text != "0" || t[close].text != "]")
        ctx.fail(t[i].line, "`gl_FragData` other than `gl_FragData[0]` cannot be translated (sgfx draws one "
                            "colour output)");
    t[i].text = "osg_FragColor";
    for (std::size_t k = i + 1; k <= close; ++k)
        blank(t[k]);
}

// gl_TexCoord[i]: the interface array is as long as the largest constant index needs.
void countTexCoords(Stage& st, std::size_t i) {
    const auto& t = st.tokens;
    const std::size_t open = nextCode(t, i), index = nextCode(t, open), close = nextCode(t, index);
    const bool constant = close < t.size() && t[open].text == "[" && t[close].text == "]" &&
                          std::all_of(t[index].text.begin(), t[index].text.end(), ::isdigit);
    st.texCoords = std::max(st.texCoords, constant ? std::min(std::stoi(t[index].text), 7) + 1 : 8);
}

// Renames the built-ins (step 1 of OSG's aliasing: text replaced at identifier boundaries).
void replaceBuiltins(const Context& ctx, Stage& st) {
    const auto& common = commonNames();
    const auto& own = stageNames(st.stage);
    for (std::size_t i = 0; i < st.tokens.size(); ++i) {
        Token& t = st.tokens[i];
        if (t.kind != Tok::Ident) continue;
        if (laterReserved(t.text, st.version)) {
            t.text += "_osg";
            continue;
        }
        if (t.text == "gl_FragData" && st.stage == CompatStage::Fragment) {
            replaceFragData(ctx, st, i);
            st.used.insert("osg_FragColor");
            continue;
        }
        if (t.text == "gl_TexCoord") countTexCoords(st, i);
        if (t.text == "attribute" && st.stage != CompatStage::Vertex)
            ctx.fail(t.line, "`attribute` in a fragment shader");
        const auto o = own.find(t.text);
        const auto c = common.find(t.text);
        if (o != own.end()) {
            t.text = std::string(o->second);
        } else if (c != common.end()) {
            t.text = std::string(c->second);
        } else if (t.text.starts_with("gl_") && !coreBuiltin(t.text)) {
            ctx.fail(t.line, "`" + t.text + "` cannot be translated (no sgfx equivalent in the " +
                                 stageName(st.stage) + " stage)");
        }
        if (t.text.starts_with("osg_")) st.used.insert(t.text);
    }
}

// A declaration at file scope: `[layout(...)] [qualifiers] storage type name [N], ...;`.
struct Declaration {
    std::size_t begin = 0, end = 0; ///< tokens, end = the `;`
    std::string storage, type;      ///< storage: in, out, uniform, const or empty
    std::vector<std::pair<std::string, int>> names;
    bool located = false; ///< has a layout qualifier
    int line = 0;
};

Declaration parseDeclaration(const std::vector<Token>& t, std::size_t begin, std::size_t end) {
    static const std::set<std::string_view> qualifiers = {
        "flat", "smooth", "noperspective", "centroid", "invariant", "highp", "mediump", "lowp", "precise"};
    static const std::set<std::string_view> storages = {"in", "out", "uniform", "const"};
    Declaration d;
    d.begin = begin;
    d.end = end;
    std::size_t i = begin;
    if (!isCode(t[i])) i = nextCode(t, i);
    d.line = i < end ? t[i].line : 0;
    for (; i < end; i = nextCode(t, i)) {
        if (t[i].text == "layout") {
            d.located = true;
            while (i < end && t[i].text != ")")
                ++i;
        } else if (storages.contains(t[i].text) && d.storage.empty()) {
            d.storage = t[i].text;
        } else if (!qualifiers.contains(t[i].text)) {
            break;
        }
    }
    if (i >= end || t[i].kind != Tok::Ident) return d;
    d.type = t[i].text;
    int parens = 0;
    bool expectName = true;
    for (i = nextCode(t, i); i < end; i = nextCode(t, i)) {
        const std::string& x = t[i].text;
        parens += (x == "(") - (x == ")");
        if (parens) continue;
        if (expectName && t[i].kind == Tok::Ident) {
            d.names.emplace_back(x, 0);
            expectName = false;
        } else if (x == "[" && !d.names.empty() && d.names.back().second == 0) {
            const std::size_t n = nextCode(t, i);
            if (n < end && std::isdigit(static_cast<unsigned char>(t[n].text[0])))
                d.names.back().second = std::atoi(t[n].text.c_str());
        } else if (x == ",") {
            expectName = true;
        } else if (x == "=") {
            expectName = false;
        }
    }
    return d;
}

// The file-scope declarations, preprocessor lines skipped.
std::vector<Declaration> declarations(const std::vector<Token>& t) {
    std::vector<Declaration> out;
    int depth = 0;
    std::size_t start = 0;
    for (std::size_t i = 0; i < t.size(); ++i) {
        const std::string& x = t[i].text;
        if ((t[i].kind == Tok::Other && x == "#" && t[i].lineStart) || t[i].kind == Tok::Directive) {
            while (i + 1 < t.size() && t[i + 1].text.find('\n') == std::string::npos)
                ++i;
            start = i + 1;
        } else if (x == "{" || x == "}") {
            depth += x == "{" ? 1 : -1;
            start = i + 1;
        } else if (x == ";") {
            if (depth == 0 && start < i) out.push_back(parseDeclaration(t, start, i));
            start = i + 1;
        }
    }
    return out;
}

// Names the prologue defines that a source may declare itself (OSG's aliased sources do).
bool provided(std::string_view n) {
    static const std::set<std::string_view> names = {"osg_Vertex",
                                                     "osg_Normal",
                                                     "osg_Color",
                                                     "osg_SecondaryColor",
                                                     "osg_MultiTexCoord0",
                                                     "osg_MultiTexCoord1",
                                                     "osg_MultiTexCoord2",
                                                     "osg_MultiTexCoord3",
                                                     "osg_MultiTexCoord4",
                                                     "osg_MultiTexCoord5",
                                                     "osg_MultiTexCoord6",
                                                     "osg_MultiTexCoord7",
                                                     "osg_ModelViewMatrix",
                                                     "osg_ModelViewProjectionMatrix",
                                                     "osg_ProjectionMatrix",
                                                     "osg_NormalMatrix",
                                                     "osg_ViewMatrix",
                                                     "osg_ViewMatrixInverse",
                                                     "osg_FrameTime",
                                                     "osg_SimulationTime"};
    return names.contains(n);
}

// Drops the sources' own declarations of provided names, lists samplers and outputs, and locates
// the vertex stage's own attributes from osg::Program's bindings.
void scanDeclarations(const Context& ctx, Stage& st, const CompatOptions& options) {
    for (const Declaration& d : declarations(st.tokens)) {
        const bool declaresProvided =
            std::any_of(d.names.begin(), d.names.end(), [](const auto& n) { return provided(n.first); });
        if (declaresProvided && (d.storage == "in" || d.storage == "uniform")) {
            for (std::size_t k = d.begin; k <= d.end; ++k)
                blank(st.tokens[k]);
            continue;
        }
        for (const auto& [name, size] : d.names) {
            if (d.storage == "uniform" && d.type.find("sampler") != std::string::npos) {
                const CompatSampler s{name, d.type, size};
                if (std::find(st.samplers.begin(), st.samplers.end(), s) == st.samplers.end())
                    st.samplers.push_back(s);
            }
            if (st.stage == CompatStage::Fragment && d.storage == "out" && d.type == "vec4" &&
                st.output.empty())
                st.output = name;
            if (st.stage != CompatStage::Vertex || d.storage != "in" || d.located) continue;
            const auto binding = options.attributeLocations.find(name);
            if (binding == options.attributeLocations.end()) {
                ctx.note("vertex attribute '" + name + "' (line " + std::to_string(d.line) +
                         ") has no location binding: it reads the renderer's current value");
                continue;
            }
            const std::size_t first = isCode(st.tokens[d.begin]) ? d.begin : nextCode(st.tokens, d.begin);
            st.tokens[first].text =
                "layout(location = " + std::to_string(binding->second) + ") " + st.tokens[first].text;
        }
    }
}

// `void main(` becomes `void osg_main(`: the wrapper main calls it.
void renameMain(const Context& ctx, Stage& st) {
    auto& t = st.tokens;
    std::size_t previous = t.size();
    int renamed = 0;
    for (std::size_t i = 0; i < t.size(); ++i) {
        if (!isCode(t[i])) continue;
        if (t[i].text == "main" && previous < t.size() && t[previous].text == "void") {
            const std::size_t open = nextCode(t, i);
            if (open < t.size() && t[open].text == "(") t[i].text = "osg_main", ++renamed;
        }
        previous = i;
    }
    if (!renamed) ctx.fail(1, "no `void main()`");
}

// The version, extensions dropped (their features are core in 4.50 or absent anyway).
void dropDirectives(const Context& ctx, Stage& st) {
    for (Token& t : st.tokens) {
        if (t.kind != Tok::Directive) continue;
        const std::size_t word = t.text.find_first_not_of("# \t");
        if (word != std::string::npos && t.text.compare(word, 7, "version") == 0) {
            const std::size_t digit = t.text.find_first_of("0123456789");
            if (digit != std::string::npos) st.version = std::atoi(t.text.c_str() + digit);
        } else {
            ctx.note(std::string(stageName(st.stage)) + " shader line " + std::to_string(t.line) + ": `" +
                     t.text + "` dropped");
        }
        blank(t);
    }
}

Stage prepare(const Context& ctx, std::string_view source, const CompatOptions& options) {
    Stage st;
    st.stage = ctx.stage;
    st.tokens = tokenize(source);
    dropDirectives(ctx, st);
    replaceBuiltins(ctx, st);
    if (st.used.contains("osg_ftransform")) st.used.insert("osg_Vertex"); // what it transforms
    scanDeclarations(ctx, st, options);
    renameMain(ctx, st);
    if (st.stage == CompatStage::Fragment) {
        if (st.used.contains("osg_FragColor")) st.output = "osg_FragColor";
        if (st.output.empty())
            ctx.fail(1, "writes no colour (neither gl_FragColor, gl_FragData[0] nor an `out vec4`)");
    }
    return st;
}

// What both stages agree on: the varyings standing in for gl_FrontColor and gl_TexCoord.
struct Interface {
    int texCoords = 0;         ///< length of osg_TexCoord (both stages)
    bool frontColor = false;   ///< the fragment stage reads gl_Color
    bool defaultFront = false; ///< the vertex stage never writes gl_FrontColor: the wrapper copies gl_Color
};

constexpr const char* kFrameBlock = R"(layout(std140, binding = 0) uniform SgfxFrame {
    mat4 sgfx_view; mat4 sgfx_projection; mat4 sgfx_viewProjection; mat4 sgfx_invViewProjection;
    vec4 sgfx_eye; vec4 sgfx_viewport; vec4 sgfx_ambientLight; vec4 sgfx_time; ivec4 sgfx_lightCount;
    vec4 sgfx_lightVector[8]; vec4 sgfx_lightColor[8];
};
uniform mat4 sgfx_model;
uniform mat3 sgfx_normalMatrix;
)";

// GL's fixed-function state that gl_LightSource, gl_FrontMaterial and their products read, filled
// by the wrapper main: sgfx's lights of the view in eye space, the material from uniforms.
constexpr const char* kLightingState = R"(struct osg_LightSourceParameters {
    vec4 ambient; vec4 diffuse; vec4 specular; vec4 position; vec4 halfVector; vec3 spotDirection;
    float spotExponent; float spotCutoff; float spotCosCutoff;
    float constantAttenuation; float linearAttenuation; float quadraticAttenuation;
};
struct osg_MaterialParameters { vec4 emission; vec4 ambient; vec4 diffuse; vec4 specular; float shininess; };
struct osg_LightModelParameters { vec4 ambient; };
struct osg_LightModelProducts { vec4 sceneColor; };
struct osg_LightProducts { vec4 ambient; vec4 diffuse; vec4 specular; };
uniform vec4 osg_FrontMaterialAmbient = vec4(0.2, 0.2, 0.2, 1.0);
uniform vec4 osg_FrontMaterialDiffuse = vec4(0.8, 0.8, 0.8, 1.0);
uniform vec4 osg_FrontMaterialSpecular = vec4(0.0, 0.0, 0.0, 1.0);
uniform vec4 osg_FrontMaterialEmission = vec4(0.0, 0.0, 0.0, 1.0);
uniform float osg_FrontMaterialShininess = 0.0;
uniform vec4 osg_BackMaterialAmbient = vec4(0.2, 0.2, 0.2, 1.0);
uniform vec4 osg_BackMaterialDiffuse = vec4(0.8, 0.8, 0.8, 1.0);
uniform vec4 osg_BackMaterialSpecular = vec4(0.0, 0.0, 0.0, 1.0);
uniform vec4 osg_BackMaterialEmission = vec4(0.0, 0.0, 0.0, 1.0);
uniform float osg_BackMaterialShininess = 0.0;
osg_LightSourceParameters osg_LightSource[8];
osg_MaterialParameters osg_FrontMaterial, osg_BackMaterial;
osg_LightModelParameters osg_LightModel;
osg_LightModelProducts osg_FrontLightModelProduct, osg_BackLightModelProduct;
osg_LightProducts osg_FrontLightProduct[8], osg_BackLightProduct[8];
#ifdef SGFX_LIGHT_VISIBILITY
float sgfx_lightVisibility(int light, vec3 worldPos, vec3 worldNormal);
#endif
void osg_fillState() {
    osg_FrontMaterial = osg_MaterialParameters(osg_FrontMaterialEmission, osg_FrontMaterialAmbient,
        osg_FrontMaterialDiffuse, osg_FrontMaterialSpecular, osg_FrontMaterialShininess);
    osg_BackMaterial = osg_MaterialParameters(osg_BackMaterialEmission, osg_BackMaterialAmbient,
        osg_BackMaterialDiffuse, osg_BackMaterialSpecular, osg_BackMaterialShininess);
    osg_LightModel.ambient = vec4(sgfx_ambientLight.rgb, 1.0);
    osg_FrontLightModelProduct.sceneColor = osg_FrontMaterial.emission + osg_FrontMaterial.ambient * osg_LightModel.ambient;
    osg_BackLightModelProduct.sceneColor = osg_BackMaterial.emission + osg_BackMaterial.ambient * osg_LightModel.ambient;
#ifdef SGFX_LIGHT_VISIBILITY
    vec4 osg_ndc = vec4((gl_FragCoord.xy - sgfx_viewport.xy) / sgfx_viewport.zw * 2.0 - 1.0, gl_FragCoord.z * 2.0 - 1.0, 1.0);
    vec4 osg_world = sgfx_invViewProjection * osg_ndc;
#endif
    for (int i = 0; i < 8; ++i) {
        bool on = i < sgfx_lightCount.x;
        vec4 c = on ? vec4(sgfx_lightColor[i].rgb, 1.0) : vec4(0.0, 0.0, 0.0, 1.0);
#ifdef SGFX_LIGHT_VISIBILITY
        if (on) c.rgb *= sgfx_lightVisibility(i, osg_world.xyz / osg_world.w, vec3(0.0));
#endif
        vec4 p = on ? sgfx_view * sgfx_lightVector[i] : vec4(0.0, 0.0, 1.0, 0.0);
        vec3 h = normalize((p.w == 0.0 ? normalize(p.xyz) : vec3(0.0, 0.0, 1.0)) + vec3(0.0, 0.0, 1.0));
        osg_LightSource[i] = osg_LightSourceParameters(vec4(0.0, 0.0, 0.0, 1.0), c, c, p, vec4(h, 0.0),
            vec3(0.0, 0.0, -1.0), 0.0, 180.0, -1.0, 1.0, 0.0, 0.0);
        osg_FrontLightProduct[i] = osg_LightProducts(osg_FrontMaterial.ambient * osg_LightSource[i].ambient,
            osg_FrontMaterial.diffuse * c, osg_FrontMaterial.specular * c);
        osg_BackLightProduct[i] = osg_LightProducts(osg_BackMaterial.ambient * osg_LightSource[i].ambient,
            osg_BackMaterial.diffuse * c, osg_BackMaterial.specular * c);
    }
}
)";

bool usesLightingState(const Stage& st) {
    static const char* const names[] = {"osg_LightSource",
                                        "osg_LightModel",
                                        "osg_FrontMaterial",
                                        "osg_BackMaterial",
                                        "osg_FrontLightModelProduct",
                                        "osg_BackLightModelProduct",
                                        "osg_FrontLightProduct",
                                        "osg_BackLightProduct"};
    return std::any_of(std::begin(names), std::end(names),
                       [&](const char* n) { return st.used.contains(n); });
}

bool usesMaterial(const Stage& st) {
    return usesLightingState(st) && !(st.used.size() == 1 && st.used.contains("osg_LightSource")) &&
           std::any_of(st.used.begin(), st.used.end(), [](const std::string& n) {
               return n.find("Material") != std::string::npos || n.find("Product") != std::string::npos;
           });
}

// Definitions of the osg_* names a stage uses, in dependency order.
std::string definitions(const Stage& st, const Interface& io) {
    const bool vertex = st.stage == CompatStage::Vertex;
    static const std::pair<const char*, const char*> vertexInputs[] = {
        {"osg_Vertex", "layout(location = 0) in vec4 osg_Vertex;\n"},
        {"osg_Normal", "layout(location = 1) in vec3 osg_Normal;\n"},
        {"osg_MultiTexCoord0", "layout(location = 3) in vec4 osg_MultiTexCoord0;\n"},
        {"osg_Color", "layout(location = 4) in vec4 osg_Color;\n"},
        {"osg_MultiTexCoord1", "layout(location = 5) in vec4 osg_MultiTexCoord1;\n"}};
    static const std::pair<const char*, const char*> macros[] = {
        {"osg_ModelViewMatrix", "(sgfx_view * sgfx_model)"},
        {"osg_ModelViewProjectionMatrix", "(sgfx_viewProjection * sgfx_model)"},
        {"osg_ProjectionMatrix", "sgfx_projection"},
        // (V·M)^-T = V^-T·M^-T = V·M^-T for a rigid view: the world normal matrix turned by the view.
        {"osg_NormalMatrix", "(mat3(sgfx_view) * sgfx_normalMatrix)"},
        {"osg_ModelViewMatrixInverse", "inverse(sgfx_view * sgfx_model)"},
        {"osg_ModelViewMatrixTranspose", "transpose(sgfx_view * sgfx_model)"},
        {"osg_ModelViewMatrixInverseTranspose", "transpose(inverse(sgfx_view * sgfx_model))"},
        {"osg_ProjectionMatrixInverse", "inverse(sgfx_projection)"},
        {"osg_ModelViewProjectionMatrixInverse", "inverse(sgfx_viewProjection * sgfx_model)"},
        {"osg_ViewMatrix", "sgfx_view"},
        {"osg_ViewMatrixInverse", "inverse(sgfx_view)"},
        {"osg_FrameTime", "(sgfx_time.x)"},
        {"osg_SimulationTime", "(sgfx_time.x)"},
        {"osg_SecondaryColor", "vec4(0.0, 0.0, 0.0, 1.0)"}};
    std::string out;
    auto uses = [&](const std::string& n) { return st.used.contains(n); };
    if (vertex)
        for (const auto& [name, decl] : vertexInputs)
            if (uses(name) || (io.defaultFront && std::string_view(name) == "osg_Color")) out += decl;
    for (int k = 2; k < 8; ++k)
        if (uses("osg_MultiTexCoord" + std::to_string(k)))
            out += "#define osg_MultiTexCoord" + std::to_string(k) + " vec4(0.0, 0.0, 0.0, 1.0)\n";
    for (const auto& [name, value] : macros)
        if (uses(name)) out += std::string("#define ") + name + " " + value + "\n";
    if (uses("osg_TextureMatrix"))
        out += "const mat4 osg_TextureMatrix[8] = mat4[8](mat4(1.0), mat4(1.0), mat4(1.0), mat4(1.0), "
               "mat4(1.0), mat4(1.0), mat4(1.0), mat4(1.0));\n";
    const char* inOut = vertex ? "out" : "in";
    if (uses("osg_FrontColor") || (vertex && io.frontColor))
        out += std::string(inOut) + " vec4 osg_FrontColor;\n";
    if (io.texCoords && (uses("osg_TexCoord") || vertex))
        out += std::string(inOut) + " vec4 osg_TexCoord[" + std::to_string(io.texCoords) + "];\n";
    for (const char* name :
         {"osg_BackColor", "osg_FrontSecondaryColor", "osg_BackSecondaryColor", "osg_ClipVertex"})
        if (uses(name)) out += std::string("vec4 ") + name + ";\n"; // written, never read by sgfx
    if (uses("osg_FogFragCoord")) out += "float osg_FogFragCoord;\n";
    if (uses("osg_Fog")) // a fog that fogs nothing: sgfx's FogNode fogs the program's output instead
        out +=
            "struct osg_FogParameters { vec4 color; float density; float start; float end; float scale; };\n"
            "const osg_FogParameters osg_Fog = osg_FogParameters(vec4(0.0), 0.0, 0.0, 1e30, 1e-30);\n";
    if (uses("osg_FragColor")) out += "layout(location = 0) out vec4 osg_FragColor;\n";
    if (uses("osg_ftransform"))
        out += "vec4 osg_ftransform() { return sgfx_viewProjection * sgfx_model * osg_Vertex; }\n";
    if (uses("osg_shadow"))
        out += "vec4 osg_shadow(sampler1DShadow s, vec3 c) { return vec4(texture(s, c)); }\n"
               "vec4 osg_shadow(sampler2DShadow s, vec3 c) { return vec4(texture(s, c)); }\n"
               "vec4 osg_shadow(sampler2DRectShadow s, vec3 c) { return vec4(texture(s, c)); }\n";
    if (uses("osg_shadowProj"))
        out += "vec4 osg_shadowProj(sampler1DShadow s, vec4 c) { return vec4(textureProj(s, c)); }\n"
               "vec4 osg_shadowProj(sampler2DShadow s, vec4 c) { return vec4(textureProj(s, c)); }\n";
    if (usesLightingState(st)) out += kLightingState;
    return out;
}

// The stage's text: version, frame block, definitions, the source on its own lines, the wrapper main.
std::string emit(const Stage& st, const Interface& io) {
    const bool vertex = st.stage == CompatStage::Vertex;
    std::string out = "#version 450 core\n";
    out += kFrameBlock;
    if (!vertex) out += "#ifdef SGFX_AMBIENT_OCCLUSION\nfloat sgfx_ambientOcclusion();\n#endif\n";
    out += definitions(st, io);
    out += "#line 1 0\n";
    for (const Token& t : st.tokens)
        out += t.text;
    out += "\nvoid main() {\n";
    if (usesLightingState(st)) out += "    osg_fillState();\n";
    if (vertex && io.defaultFront) out += "    osg_FrontColor = osg_Color;\n";
    out += "    osg_main();\n";
    // Ambient occlusion darkens the whole colour: OSG's shaders have no separate ambient term.
    if (!vertex)
        out += "#if defined(SGFX_AMBIENT_OCCLUSION) && !defined(SGFX_BLEND)\n    " + st.output +
               ".rgb *= 1.0 - sgfx_ambientOcclusion();\n#endif\n";
    return out + "}\n";
}

// The fixed-function stand-in for a missing vertex stage, writing the coordinates the fragment reads.
std::string standInVertex(int texCoords) {
    std::string s = "void main() {\n    gl_Position = ftransform();\n    gl_FrontColor = gl_Color;\n"
                    "    gl_TexCoord[0] = gl_MultiTexCoord0;\n";
    if (texCoords > 1) s += "    gl_TexCoord[1] = gl_MultiTexCoord1;\n";
    return s + "}\n";
}

constexpr const char* kStandInFragment = "void main() {\n    gl_FragColor = gl_Color;\n}\n";

// One line each for what the translation approximates.
void addNotes(const Context& ctx, const Stage& st) {
    auto uses = [&](const char* n) { return st.used.contains(n); };
    for (int k = 2; k < 8; ++k)
        if (st.used.contains("osg_MultiTexCoord" + std::to_string(k)))
            ctx.note("gl_MultiTexCoord" + std::to_string(k) +
                     " reads (0, 0, 0, 1): sgfx geometries carry texture coordinate sets 0 and 1");
    if (uses("osg_SecondaryColor")) ctx.note("gl_SecondaryColor reads (0, 0, 0, 1)");
    if (uses("osg_TextureMatrix"))
        ctx.note("gl_TextureMatrix[i] reads the identity (osg::TexMat is not carried)");
    if (uses("osg_BackColor") || uses("osg_BackSecondaryColor"))
        ctx.note("gl_BackColor is ignored: both faces get gl_FrontColor (no two-sided vertex colour)");
    if (uses("osg_ClipVertex")) ctx.note("gl_ClipVertex is ignored (no user clip planes)");
    if (uses("osg_FogFragCoord")) ctx.note("gl_FogFragCoord is ignored (fog comes from sgfx's FogNode)");
    if (uses("osg_Fog"))
        ctx.note("gl_Fog is a fog of density 0 reaching to 1e30 (the program's own fog fogs nothing; "
                 "sgfx's FogNode fogs its output)");
    if (uses("osg_LightSource"))
        ctx.note(
            "gl_LightSource[i] holds the view's sgfx lights in eye space (colour as diffuse and specular, "
            "no ambient, attenuation or spot cone)");
    for (const char* n : {"osg_DeltaFrameTime", "osg_DeltaSimulationTime", "osg_FrameNumber"})
        if (uses(n)) ctx.note(std::string(n) + " is an ordinary uniform here: the application sets it");
}

} // namespace

CompatProgram translateCompatibilityProgram(std::string name, std::span<const CompatShader> shaders,
                                            const CompatOptions& options) {
    CompatProgram result;
    std::string sources[2];
    int counts[2] = {};
    for (const CompatShader& s : shaders) {
        if (s.stage != CompatStage::Vertex && s.stage != CompatStage::Fragment)
            Context{name, s.stage, result.notes}.fail(1, std::string(stageName(s.stage)) +
                                                             " shaders cannot be translated (sgfx foreign "
                                                             "programs have a vertex and a fragment stage)");
        const int k = s.stage == CompatStage::Fragment;
        if (counts[k]++) sources[k] += '\n'; // several shaders of one stage: joined in order
        sources[k] += s.source;
    }
    if (!counts[0] && !counts[1])
        throw CompatError("sgfx: OSG program '" + name + "' has no vertex or fragment shader");
    for (int k = 0; k < 2; ++k)
        if (counts[k] > 1)
            result.notes.push_back(std::to_string(counts[k]) + " " + (k ? "fragment" : "vertex") +
                                   " shaders joined into one (line numbers count through the joined text)");
    const Context fctx{name, CompatStage::Fragment, result.notes},
        vctx{name, CompatStage::Vertex, result.notes};
    if (!counts[1])
        result.notes.push_back("no fragment shader: the fixed-function stand-in gl_FragColor = gl_Color");
    Stage frag = prepare(fctx, counts[1] ? std::string_view(sources[1]) : kStandInFragment, options);
    if (!counts[0])
        result.notes.push_back("no vertex shader: the fixed-function stand-in (ftransform, gl_FrontColor = "
                               "gl_Color, gl_TexCoord[0] = gl_MultiTexCoord0)");
    const std::string vertexSource = counts[0] ? sources[0] : standInVertex(frag.texCoords);
    Stage vert = prepare(vctx, vertexSource, options);
    Interface io;
    io.texCoords = std::max(vert.texCoords, frag.texCoords);
    io.frontColor = frag.used.contains("osg_FrontColor");
    io.defaultFront = io.frontColor && !vert.used.contains("osg_FrontColor");
    if (io.defaultFront)
        result.notes.push_back("the vertex shader writes no gl_FrontColor: gl_Color is passed");
    addNotes(vctx, vert);
    addNotes(fctx, frag);
    result.samplers = vert.samplers;
    for (const CompatSampler& s : frag.samplers)
        if (std::find(result.samplers.begin(), result.samplers.end(), s) == result.samplers.end())
            result.samplers.push_back(s);
    result.usesMaterial = usesMaterial(vert) || usesMaterial(frag);
    result.program = ShaderProgram::create(std::move(name), emit(vert, io), emit(frag, io));
    return result;
}

CompatProgram translateCompatibilityProgram(std::string name, std::string_view vertex,
                                            std::string_view fragment) {
    std::vector<CompatShader> shaders;
    auto present = [](std::string_view s) {
        return s.find_first_not_of(" \t\r\n") != std::string_view::npos;
    };
    if (present(vertex)) shaders.push_back({CompatStage::Vertex, std::string(vertex)});
    if (present(fragment)) shaders.push_back({CompatStage::Fragment, std::string(fragment)});
    return translateCompatibilityProgram(std::move(name), shaders);
}

std::vector<std::pair<std::string, UniformValue>> compatMaterialUniforms(const CompatMaterial& front,
                                                                         const CompatMaterial& back) {
    using namespace compat_uniforms;
    return {{kFrontAmbient, front.ambient},     {kFrontDiffuse, front.diffuse},
            {kFrontSpecular, front.specular},   {kFrontEmission, front.emission},
            {kFrontShininess, front.shininess}, {kBackAmbient, back.ambient},
            {kBackDiffuse, back.diffuse},       {kBackSpecular, back.specular},
            {kBackEmission, back.emission},     {kBackShininess, back.shininess}};
}

} // namespace sgfx

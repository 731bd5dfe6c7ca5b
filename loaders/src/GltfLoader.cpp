#include "sgfx/GltfLoader.h"

#include "GltfAccessors.h"
#include "GltfLights.h"
#include "GltfSkins.h"

#include <sgfx/Animation.h>
#include <sgfx/Geometry.h>
#include <sgfx/Image.h>
#include <sgfx/Material.h>
#include <sgfx/MeshOptimize.h>
#include <sgfx/MeshTools.h>
#include <sgfx/StateSet.h>
#include <sgfx/Texture.h>

#include <tiny_gltf.h>

#include <nlohmann/json.hpp>

#include <stb_image.h>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <sstream>

namespace sgfx {

namespace {

using namespace gltf;

// Debian's stb_image (2022 snapshot) trusts PNG chunk lengths and reads past the end of a
// buffer whose chunks claim more than it holds, so the chunk layout is checked first; and only
// the formats glTF allows reach stb: its other decoders (PSD, TGA, HDR, ...) never see hostile
// bytes. Returns why the bytes are refused, or nothing.
std::string refuseImageBytes(const unsigned char* bytes, std::size_t n) {
    static const unsigned char png[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    if (n >= 3 && bytes[0] == 0xFF && bytes[1] == 0xD8 && bytes[2] == 0xFF) return {}; // JPEG
    if (n < 8 || std::memcmp(bytes, png, 8) != 0) return "not a PNG or JPEG image";
    for (std::size_t at = 8;;) {
        if (n - at < 12) return "truncated PNG: no IEND chunk before byte " + std::to_string(n);
        const std::size_t length = (std::size_t(bytes[at]) << 24) | (std::size_t(bytes[at + 1]) << 16) |
                                   (std::size_t(bytes[at + 2]) << 8) | std::size_t(bytes[at + 3]);
        if (length > n - at - 12)
            return "truncated PNG: the chunk at byte " + std::to_string(at) + " claims " +
                   std::to_string(length) + " bytes, " + std::to_string(n - at - 12) + " are left";
        const bool end = std::memcmp(bytes + at + 4, "IEND", 4) == 0;
        at += 12 + length;
        if (end) return {};
    }
}

// Decodes a PNG or JPEG into RGBA8. The header's size is charged to the budget first: stb
// allocates what the header declares before it reads the pixels. Returns why it failed, or nothing.
std::string decodePixels(const unsigned char* bytes, std::size_t size, Budget& budget,
                         tinygltf::Image& image) {
    if (size == 0 || size > std::size_t(std::numeric_limits<int>::max())) return "empty or over 2 GiB";
    if (std::string why = refuseImageBytes(bytes, size); !why.empty()) return why;
    int w = 0, h = 0, comp = 0;
    if (!stbi_info_from_memory(bytes, int(size), &w, &h, &comp) || w <= 0 || h <= 0)
        return "not a PNG or JPEG image";
    if (!budget.take(std::size_t(w) * std::size_t(h) * 8))
        return std::to_string(w) + "x" + std::to_string(h) + " pixels are more than the load's memory limit";
    stbi_uc* data = stbi_load_from_memory(bytes, int(size), &w, &h, &comp, 4);
    if (!data) return stbi_failure_reason();
    image.width = w;
    image.height = h;
    image.component = 4;
    image.bits = 8;
    image.pixel_type = TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE;
    image.image.assign(data, data + std::size_t(w) * std::size_t(h) * 4);
    stbi_image_free(data);
    return {};
}

// tinygltf's image callback. Images in a buffer view are left for later (decodeDeferred):
// tinygltf 2.7 hands them over without checking the view against its buffer, so `size` may run
// past the data. Images from a URI arrive as exactly the bytes read.
bool decodeImage(tinygltf::Image* image, const int index, std::string* err, std::string*, int, int,
                 const unsigned char* bytes, int size, void* budget) {
    if (image->bufferView >= 0) return true;
    const std::string why =
        decodePixels(bytes, std::size_t(std::max(size, 0)), *static_cast<Budget*>(budget), *image);
    if (!why.empty() && err) *err += "images[" + std::to_string(index) + "]: cannot decode: " + why + "\n";
    return why.empty();
}

// Decodes the images stored in buffer views, once their views are checked against the buffers.
void decodeDeferred(tinygltf::Model& model, Budget& budget,
                    const std::function<void(const std::string&, const std::string&)>& fail) {
    for (std::size_t i = 0; i < model.images.size(); ++i) {
        tinygltf::Image& image = model.images[i];
        if (image.bufferView < 0 || !image.image.empty()) continue;
        const std::string element = at("images", i);
        if (std::size_t(image.bufferView) >= model.bufferViews.size())
            fail(element, "buffer view " + std::to_string(image.bufferView) + " does not exist");
        const tinygltf::BufferView& view = model.bufferViews[std::size_t(image.bufferView)];
        if (view.buffer < 0 || std::size_t(view.buffer) >= model.buffers.size())
            fail(element, "the buffer view's buffer " + std::to_string(view.buffer) + " does not exist");
        const std::vector<unsigned char>& data = model.buffers[std::size_t(view.buffer)].data;
        if (view.byteOffset > data.size() || view.byteLength > data.size() - view.byteOffset)
            fail(element, "its buffer view (" + std::to_string(view.byteLength) + " bytes at " +
                              std::to_string(view.byteOffset) + ") runs past the buffer's " +
                              std::to_string(data.size()) + " bytes");
        if (const std::string why =
                decodePixels(data.data() + view.byteOffset, view.byteLength, budget, image);
            !why.empty())
            fail(element, "cannot decode: " + why);
    }
}

std::shared_ptr<Texture> loadTexture(const Context& c, int index, bool srgb, const std::string& element,
                                     std::map<std::pair<int, bool>, std::shared_ptr<Texture>>& cache) {
    if (index < 0) return nullptr;
    if (std::size_t(index) >= c.model.textures.size())
        c.fail(element, "texture " + std::to_string(index) + " does not exist");
    if (auto it = cache.find({index, srgb}); it != cache.end()) return it->second;
    const tinygltf::Texture& t = c.model.textures[std::size_t(index)];
    if (t.source < 0 || std::size_t(t.source) >= c.model.images.size())
        c.fail(at("textures", std::size_t(index)),
               "source image " + std::to_string(t.source) + " does not exist");
    const tinygltf::Image& src = c.model.images[std::size_t(t.source)];
    if (src.width <= 0 || src.height <= 0 ||
        src.image.size() != std::size_t(src.width) * std::size_t(src.height) * 4)
        c.fail(at("images", std::size_t(t.source)), "the image did not decode");
    c.charge(src.image.size(), 1, at("images", std::size_t(t.source)));
    auto img = Image::create(src.width, src.height, 4);
    img->pixels = src.image;
    auto tex = Texture::create(img, srgb);
    if (t.sampler >= 0 && std::size_t(t.sampler) < c.model.samplers.size()) {
        const tinygltf::Sampler& s = c.model.samplers[std::size_t(t.sampler)];
        auto wrap = [](int w) {
            return w == TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE     ? Wrap::ClampToEdge
                   : w == TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT ? Wrap::MirroredRepeat
                                                                : Wrap::Repeat;
        };
        tex->wrapS = wrap(s.wrapS);
        tex->wrapT = wrap(s.wrapT);
        if (s.magFilter == TINYGLTF_TEXTURE_FILTER_NEAREST) tex->magFilter = Filter::Nearest;
        if (s.minFilter == TINYGLTF_TEXTURE_FILTER_NEAREST) tex->minFilter = Filter::Nearest;
        if (s.minFilter == TINYGLTF_TEXTURE_FILTER_LINEAR) tex->minFilter = Filter::Linear;
    }
    cache[{index, srgb}] = tex;
    return tex;
}

glm::vec4 vec4Of(const Context& c, const std::vector<double>& v, const std::string& element) {
    if (v.size() != 4) c.fail(element, "must have 4 numbers");
    return {float(v[0]), float(v[1]), float(v[2]), float(v[3])};
}

glm::vec3 vec3Of(const Context& c, const std::vector<double>& v, const std::string& element) {
    if (v.size() != 3) c.fail(element, "must have 3 numbers");
    return {float(v[0]), float(v[1]), float(v[2])};
}

// A number as a message shows it ("2", "-0.5").
std::string numberText(double v) {
    std::ostringstream s;
    s << v;
    return s.str();
}

// A number member of an extension object, `fallback` when absent.
float numberOf(const Context& c, const tinygltf::Value& object, const char* key, double fallback,
               const std::string& element) {
    if (!object.IsObject()) c.fail(element, "must be an object");
    if (!object.Has(key)) return float(fallback);
    const tinygltf::Value& v = object.Get(key);
    if (!v.IsNumber()) c.fail(element + "." + key, "must be a number");
    const double d = v.GetNumberAsDouble();
    // Finite as a float too: 1e39 would become infinity after the checks.
    if (!std::isfinite(d) || !std::isfinite(float(d)))
        c.fail(element + "." + key, numberText(d) + " must be a finite number within float range");
    return float(d);
}

glm::vec2 pairOf(const Context& c, const tinygltf::Value& object, const char* key, glm::vec2 fallback,
                 const std::string& element) {
    if (!object.Has(key)) return fallback;
    const tinygltf::Value& v = object.Get(key);
    if (!v.IsArray() || v.ArrayLen() != 2 || !v.Get(0).IsNumber() || !v.Get(1).IsNumber())
        c.fail(element + "." + key, "must be an array of 2 numbers");
    return {float(v.Get(0).GetNumberAsDouble()), float(v.Get(1).GetNumberAsDouble())};
}

// EXT_mesh_gpu_instancing: TRANSLATION, ROTATION (quaternion, float or normalised) and SCALE
// accessors of one count, as T * R * S per instance.
std::vector<glm::mat4> instanceMatrices(const Context& c, const tinygltf::Value& ext,
                                        const std::string& element) {
    if (!ext.IsObject() || !ext.Has("attributes") || !ext.Get("attributes").IsObject())
        c.fail(element, "needs an `attributes` object");
    const tinygltf::Value& attrs = ext.Get("attributes");
    std::size_t count = 0;
    auto read = [&](const char* key, int type) {
        if (!attrs.Has(key)) return std::vector<float>{};
        const tinygltf::Value& v = attrs.Get(key);
        if (!v.IsInt()) c.fail(element + ".attributes." + key, "must be an accessor index");
        std::size_t n = 0;
        auto values = readAccessor(c, v.GetNumberAsInt(), element + ".attributes." + key, {type}, &n);
        if (count && n != count)
            c.fail(element + ".attributes." + key,
                   std::to_string(n) + " values where the other attributes have " + std::to_string(count));
        count = n;
        for (float f : values)
            if (!std::isfinite(f)) c.fail(element + ".attributes." + key, "has a NaN or infinite value");
        return values;
    };
    const auto tr = read("TRANSLATION", TINYGLTF_TYPE_VEC3);
    const auto rot = read("ROTATION", TINYGLTF_TYPE_VEC4);
    const auto sc = read("SCALE", TINYGLTF_TYPE_VEC3);
    if (!count) c.fail(element + ".attributes", "has none of TRANSLATION, ROTATION, SCALE");
    std::vector<glm::mat4> out(count, glm::mat4(1.0f));
    for (std::size_t i = 0; i < count; ++i) {
        glm::mat4& m = out[i];
        if (!tr.empty()) m = glm::translate(m, glm::vec3(tr[3 * i], tr[3 * i + 1], tr[3 * i + 2]));
        if (!rot.empty()) {
            const glm::quat q(rot[4 * i + 3], rot[4 * i], rot[4 * i + 1], rot[4 * i + 2]);
            if (glm::length(q) < 1e-6f) c.fail(element + ".attributes.ROTATION", "has a zero quaternion");
            m *= glm::mat4_cast(glm::normalize(q));
        }
        if (!sc.empty()) m = glm::scale(m, glm::vec3(sc[3 * i], sc[3 * i + 1], sc[3 * i + 2]));
    }
    return out;
}

// A textureInfo's coordinate set and KHR_texture_transform.
TextureMapping mappingOf(const Context& c, int texCoord, const tinygltf::ExtensionMap& extensions,
                         const std::string& element) {
    TextureMapping t;
    t.texCoord = texCoord;
    if (const auto e = extensions.find("KHR_texture_transform"); e != extensions.end()) {
        const std::string name = element + ".extensions.KHR_texture_transform";
        t.offset = pairOf(c, e->second, "offset", glm::vec2(0.0f), name);
        t.rotation = numberOf(c, e->second, "rotation", 0.0, name);
        t.scale = pairOf(c, e->second, "scale", glm::vec2(1.0f), name);
        if (e->second.Has("texCoord")) {
            const tinygltf::Value& v = e->second.Get("texCoord");
            if (!v.IsInt()) c.fail(name + ".texCoord", "must be an integer");
            t.texCoord = v.GetNumberAsInt();
        }
    }
    if (t.texCoord != 0 && t.texCoord != 1)
        c.fail(element + ".texCoord",
               "TEXCOORD_" + std::to_string(t.texCoord) + " is not supported (0 or 1)");
    return t;
}

// A number member of an extension object that must lie in [0, 1].
float unitOf(const Context& c, const tinygltf::Value& object, const char* key, double fallback,
             const std::string& element) {
    const float v = numberOf(c, object, key, fallback, element);
    if (!(v >= 0.0f && v <= 1.0f)) c.fail(element + "." + key, numberText(v) + " is outside [0, 1]");
    return v;
}

// A textureInfo (or normalTextureInfo) member of an extension object, as tinygltf gives the core's.
struct ExtensionTexture {
    int index = -1;
    int texCoord = 0;
    double scale = 1.0;
    tinygltf::ExtensionMap extensions;
};

ExtensionTexture textureInfoOf(const Context& c, const tinygltf::Value& object, const char* key,
                               const std::string& element) {
    ExtensionTexture t;
    if (!object.Has(key)) return t;
    const tinygltf::Value& v = object.Get(key);
    const std::string name = element + "." + key;
    if (!v.IsObject()) c.fail(name, "must be a textureInfo object");
    if (!v.Has("index") || !v.Get("index").IsInt() || v.Get("index").GetNumberAsInt() < 0)
        c.fail(name + ".index", "must be a texture index (an integer >= 0)");
    t.index = v.Get("index").GetNumberAsInt();
    if (v.Has("texCoord")) {
        if (!v.Get("texCoord").IsInt()) c.fail(name + ".texCoord", "must be an integer");
        t.texCoord = v.Get("texCoord").GetNumberAsInt();
    }
    t.scale = numberOf(c, v, "scale", 1.0, name);
    if (v.Has("extensions")) {
        const tinygltf::Value& e = v.Get("extensions");
        if (!e.IsObject()) c.fail(name + ".extensions", "must be an object");
        for (const std::string& k : e.Keys())
            t.extensions[k] = e.Get(k);
    }
    return t;
}

// KHR_materials_ior, _transmission and _volume of a material (`prefix`: "<material>.extensions.").
template <class LoadTexture>
void readTransmission(const Context& c, const tinygltf::Material& m, Material& mat, const std::string& prefix,
                      LoadTexture&& texture) {
    if (const auto e = m.extensions.find("KHR_materials_ior"); e != m.extensions.end()) {
        const std::string ext = prefix + "KHR_materials_ior";
        mat.ior = numberOf(c, e->second, "ior", 1.5, ext);
        if (!(mat.ior == 0.0f || mat.ior >= 1.0f))
            c.fail(ext + ".ior", numberText(mat.ior) + " must be 0 or >= 1");
    }
    if (const auto e = m.extensions.find("KHR_materials_transmission"); e != m.extensions.end()) {
        const std::string ext = prefix + "KHR_materials_transmission";
        mat.transmission = unitOf(c, e->second, "transmissionFactor", 0.0, ext);
        mat.transmissionTexture = texture(textureInfoOf(c, e->second, "transmissionTexture", ext), false,
                                          MaterialMap::Transmission, ext + ".transmissionTexture");
    }
    if (const auto e = m.extensions.find("KHR_materials_volume"); e != m.extensions.end()) {
        const std::string ext = prefix + "KHR_materials_volume";
        const tinygltf::Value& v = e->second;
        mat.thickness = numberOf(c, v, "thicknessFactor", 0.0, ext);
        if (!(mat.thickness >= 0.0f))
            c.fail(ext + ".thicknessFactor", numberText(mat.thickness) + " must be >= 0");
        mat.thicknessTexture = texture(textureInfoOf(c, v, "thicknessTexture", ext), false,
                                       MaterialMap::Thickness, ext + ".thicknessTexture");
        // Absent: infinity (the medium absorbs nothing).
        if (v.Has("attenuationDistance")) {
            mat.attenuationDistance = numberOf(c, v, "attenuationDistance", 0.0, ext);
            if (!(mat.attenuationDistance > 0.0f))
                c.fail(ext + ".attenuationDistance", numberText(mat.attenuationDistance) + " must be > 0");
        }
        if (v.Has("attenuationColor")) {
            const tinygltf::Value& a = v.Get("attenuationColor");
            if (!a.IsArray() || a.ArrayLen() != 3) c.fail(ext + ".attenuationColor", "must have 3 numbers");
            for (int k = 0; k < 3; ++k) {
                const tinygltf::Value& n = a.Get(k);
                const double d = n.IsNumber() ? n.GetNumberAsDouble() : -1.0;
                // 0 would absorb everything at any depth (log 0): the smallest float stands in.
                if (!(d >= 0.0 && d <= 1.0))
                    c.fail(ext + ".attenuationColor",
                           "[" + std::to_string(k) + "] must be a number in [0, 1], not " +
                               (n.IsNumber() ? numberText(d) : std::string("a non-number")));
                mat.attenuationColor[k] = std::max(float(d), std::numeric_limits<float>::min());
            }
        }
    }
}

// KHR_materials_unlit, _clearcoat and _specular of material `name` (emissive_strength is read
// with the emissive factor). `texture(info, srgb, map, element)` loads a map and its mapping.
template <class LoadTexture>
void readMaterialExtensions(const Context& c, const tinygltf::Material& m, Material& mat,
                            const std::string& name, LoadTexture&& texture) {
    const std::string prefix = name + ".extensions.";
    if (const auto e = m.extensions.find("KHR_materials_unlit"); e != m.extensions.end()) {
        if (!e->second.IsObject()) c.fail(prefix + "KHR_materials_unlit", "must be an object");
        mat.model = ShadingModel::Unlit;
        return; // the spec excludes the others with unlit
    }
    if (const auto e = m.extensions.find("KHR_materials_clearcoat"); e != m.extensions.end()) {
        const std::string ext = prefix + "KHR_materials_clearcoat";
        const tinygltf::Value& v = e->second;
        mat.clearcoat = unitOf(c, v, "clearcoatFactor", 0.0, ext);
        mat.clearcoatRoughness = unitOf(c, v, "clearcoatRoughnessFactor", 0.0, ext);
        mat.clearcoatTexture = texture(textureInfoOf(c, v, "clearcoatTexture", ext), false,
                                       MaterialMap::Clearcoat, ext + ".clearcoatTexture");
        mat.clearcoatRoughnessTexture =
            texture(textureInfoOf(c, v, "clearcoatRoughnessTexture", ext), false,
                    MaterialMap::ClearcoatRoughness, ext + ".clearcoatRoughnessTexture");
        const ExtensionTexture normal = textureInfoOf(c, v, "clearcoatNormalTexture", ext);
        mat.clearcoatNormalTexture =
            texture(normal, false, MaterialMap::ClearcoatNormal, ext + ".clearcoatNormalTexture");
        mat.clearcoatNormalScale = float(normal.scale);
    }
    if (const auto e = m.extensions.find("KHR_materials_specular"); e != m.extensions.end()) {
        const std::string ext = prefix + "KHR_materials_specular";
        const tinygltf::Value& v = e->second;
        mat.specularFactor = unitOf(c, v, "specularFactor", 1.0, ext);
        if (v.Has("specularColorFactor")) {
            const tinygltf::Value& a = v.Get("specularColorFactor");
            if (!a.IsArray() || a.ArrayLen() != 3)
                c.fail(ext + ".specularColorFactor", "must have 3 numbers");
            for (int k = 0; k < 3; ++k) {
                const tinygltf::Value& n = a.Get(k);
                if (!n.IsNumber()) c.fail(ext + ".specularColorFactor", "must have 3 numbers");
                const double d = n.GetNumberAsDouble();
                if (!(d >= 0.0 && std::isfinite(d)))
                    c.fail(ext + ".specularColorFactor",
                           "[" + std::to_string(k) + "] = " + numberText(d) + " must be finite and >= 0");
                mat.specularColorFactor[k] = float(d);
            }
        }
        mat.specularTexture = texture(textureInfoOf(c, v, "specularTexture", ext), false,
                                      MaterialMap::Specular, ext + ".specularTexture");
        mat.specularColorTexture = texture(textureInfoOf(c, v, "specularColorTexture", ext), true,
                                           MaterialMap::SpecularColor, ext + ".specularColorTexture");
    }
    readTransmission(c, m, mat, prefix, texture);
}

bool isGlb(std::span<const std::byte> bytes) {
    return bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0;
}

// The deepest nesting of arrays and objects in JSON text (strings skipped). tinygltf 2.7 copies
// `extras` and `extensions` into tinygltf::Value recursively, so a file nested a few hundred
// thousand deep overflows the stack inside tinygltf: such a file is refused before it gets there.
std::size_t jsonDepth(const unsigned char* p, std::size_t n) {
    std::size_t depth = 0, deepest = 0;
    bool inString = false;
    for (std::size_t i = 0; i < n; ++i) {
        const unsigned char ch = p[i];
        if (inString) {
            if (ch == '\\')
                ++i;
            else if (ch == '"')
                inString = false;
        } else if (ch == '"') {
            inString = true;
        } else if (ch == '[' || ch == '{') {
            deepest = std::max(deepest, ++depth);
        } else if ((ch == ']' || ch == '}') && depth > 0) {
            --depth;
        }
    }
    return deepest;
}

// Where tinygltf may look for external buffers and images. Loads from memory have no directory:
// every external URI fails. Loads from a file read regular files only, up to the memory limit.
struct FsData {
    bool allowed = false;
    std::size_t maxBytes = 0;
};

tinygltf::FsCallbacks fsCallbacks(FsData* data) {
    tinygltf::FsCallbacks fs{};
    fs.FileExists = [](const std::string& path, void* user) {
        std::error_code ec;
        // From memory every name "exists", so that ReadWholeFile's refusal is what the error says.
        return !static_cast<FsData*>(user)->allowed || std::filesystem::is_regular_file(path, ec);
    };
    fs.ExpandFilePath = [](const std::string& path, void*) { return path; };
    fs.ReadWholeFile = [](std::vector<unsigned char>* out, std::string* err, const std::string& path,
                          void* user) {
        const auto* d = static_cast<const FsData*>(user);
        auto refuse = [&](const std::string& why) {
            if (err) *err += why;
            return false;
        };
        if (!d->allowed) return refuse("external files cannot be read when loading from memory");
        std::error_code ec;
        const auto size = std::filesystem::file_size(path, ec);
        if (ec || !std::filesystem::is_regular_file(path, ec)) return refuse("not a readable file");
        if (size > d->maxBytes) return refuse("larger than the load's memory limit");
        std::ifstream in(path, std::ios::binary);
        out->resize(std::size_t(size));
        if (!in.read(reinterpret_cast<char*>(out->data()), std::streamsize(size)))
            return refuse("cannot read it");
        return true;
    };
    fs.WriteWholeFile = [](std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
        if (err) *err += "the loader writes no files";
        return false;
    };
    fs.user_data = data;
    return fs;
}

using Json = nlohmann::json;

// A value from the file as a message shows it: its JSON text, cut short.
std::string shown(const Json& v) {
    std::string text = v.dump(-1, ' ', true, Json::error_handler_t::replace);
    return text.size() > 40 ? text.substr(0, 37) + "..." : text;
}

// glTF's "MAJOR.MINOR" (the schema's ^[0-9]+\.[0-9]+$), numbers past 10^9 held at 10^9; nothing
// when `text` is not of that form.
std::optional<std::pair<std::uint64_t, std::uint64_t>> versionOf(const std::string& text) {
    const auto dot = text.find('.');
    auto number = [&](std::size_t from, std::size_t to) -> std::optional<std::uint64_t> {
        if (from >= to) return std::nullopt;
        std::uint64_t n = 0;
        for (std::size_t i = from; i < to; ++i) {
            if (text[i] < '0' || text[i] > '9') return std::nullopt;
            n = std::min<std::uint64_t>(n * 10 + std::uint64_t(text[i] - '0'), 1000000000);
        }
        return n;
    };
    if (dot == std::string::npos) return std::nullopt;
    const auto major = number(0, dot), minor = number(dot + 1, text.size());
    if (!major || !minor) return std::nullopt;
    return std::pair{*major, *minor};
}

// Checks made on the JSON before tinygltf reads it. tinygltf 2.7 does not look at asset.version;
// it drops a byteStride that is not an unsigned integer (the view then reads as tightly packed)
// and refuses other bad strides and a primitive's missing indices accessor without naming the
// element; it takes a negative `indices` for none. Text that is not a JSON object is left to it.
void checkJson(const unsigned char* text, std::size_t size, const std::string& path) {
    const Refusal fail{path};
    // Only the members checked here are kept (not the buffers' and images' data: URIs).
    const auto keep = [](int depth, Json::parse_event_t event, Json& parsed) {
        if (event != Json::parse_event_t::key || depth != 1) return true;
        const auto& key = parsed.get_ref<const std::string&>();
        return key == "asset" || key == "bufferViews" || key == "meshes" || key == "accessors";
    };
    const Json doc = Json::parse(text, text + size, keep, false);
    if (!doc.is_object()) return;

    // asset.version "2.x"; asset.minVersion, when given, no newer than 2.0.
    const auto asset = doc.find("asset");
    if (asset == doc.end() || !asset->is_object())
        fail("asset", "is missing or not an object (a glTF 2.0 file has \"asset\": {\"version\": \"2.0\"})");
    auto version = [&](const char* key) -> std::optional<std::pair<std::uint64_t, std::uint64_t>> {
        const auto v = asset->find(key);
        const std::string element = std::string("asset.") + key;
        if (v == asset->end()) return std::nullopt;
        if (!v->is_string()) fail(element, shown(*v) + " is not a string such as \"2.0\"");
        const auto parsed = versionOf(v->get_ref<const std::string&>());
        if (!parsed) fail(element, shown(*v) + " is not of the form MAJOR.MINOR (such as \"2.0\")");
        return parsed;
    };
    const auto v = version("version");
    if (!v) fail("asset.version", "is missing (a glTF 2.0 file says \"2.0\")");
    if (v->first != 2)
        fail("asset.version", shown(asset->at("version")) + " is not supported: this loader reads glTF 2.x");
    if (const auto min = version("minVersion"); min && *min > std::pair<std::uint64_t, std::uint64_t>{2, 0})
        fail("asset.minVersion", asset->at("minVersion").get_ref<const std::string&>().substr(0, 40) +
                                     " is newer than the 2.0 this loader reads");

    // bufferViews[i].byteStride: an integer in 4..252, a multiple of 4.
    const auto views = doc.find("bufferViews");
    const std::size_t viewCount = views != doc.end() && views->is_array() ? views->size() : 0;
    for (std::size_t i = 0; i < viewCount; ++i) {
        const Json& view = (*views)[i];
        if (!view.is_object() || !view.contains("byteStride")) continue;
        const Json& stride = view["byteStride"];
        const std::string element = at("bufferViews", i) + ".byteStride";
        if (!stride.is_number_integer()) fail(element, shown(stride) + " is not an integer");
        if (!stride.is_number_unsigned() || stride.get<std::uint64_t>() < 4 ||
            stride.get<std::uint64_t>() > 252)
            fail(element, shown(stride) + " is outside 4..252");
        if (stride.get<std::uint64_t>() % 4) fail(element, shown(stride) + " is not a multiple of 4");
    }

    // meshes[i].primitives[j].indices: an accessor that exists and has a buffer view.
    const auto accessors = doc.find("accessors");
    const std::size_t accessorCount = accessors != doc.end() && accessors->is_array() ? accessors->size() : 0;
    const auto meshes = doc.find("meshes");
    if (meshes == doc.end() || !meshes->is_array()) return;
    for (std::size_t i = 0; i < meshes->size(); ++i) {
        const Json& mesh = (*meshes)[i];
        if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array()) continue;
        for (std::size_t j = 0; j < mesh["primitives"].size(); ++j) {
            const Json& primitive = mesh["primitives"][j];
            if (!primitive.is_object() || !primitive.contains("indices")) continue;
            const Json& indices = primitive["indices"];
            const std::string element = at("meshes", i) + "." + at("primitives", j) + ".indices";
            if (!indices.is_number_unsigned()) fail(element, shown(indices) + " is not an accessor index");
            const auto a = indices.get<std::uint64_t>();
            if (a >= accessorCount)
                fail(element, "accessor " + std::to_string(a) + " does not exist (" +
                                  std::to_string(accessorCount) + " accessors)");
            const Json& accessor = (*accessors)[a];
            if (!accessor.is_object()) continue;
            const std::string name = at("accessors", std::size_t(a));
            if (!accessor.contains("bufferView"))
                fail(element, name + " has no bufferView (indices without one are not supported)");
            const Json& view = accessor["bufferView"];
            if (!view.is_number_unsigned() || view.get<std::uint64_t>() >= viewCount)
                fail(element, name + ".bufferView " + shown(view) + " does not exist (" +
                                  std::to_string(viewCount) + " buffer views)");
        }
    }
}

// Both entry points: `baseDir` is null for bytes from memory.
// The geometry a node's use of a mesh primitive draws: the shared one, or for a skinned or morphed
// node (whose pose is its own) a copy after the first use, with the node's morph weights.
// Bytes a copy of `g` holds: vertices with joints and weights, indices, morph displacements.
std::size_t copyBytes(const Geometry& g) {
    std::size_t morph = 0;
    for (const MorphTarget& t : g.morphTargets)
        morph += (t.positions.size() + t.normals.size() + t.tangents.size()) * sizeof(glm::vec3);
    return g.positions.size() * (vertexBytes + 2 * (sizeof(glm::u16vec4) + sizeof(glm::vec4))) +
           g.indices.size() * sizeof(std::uint32_t) + morph;
}

std::shared_ptr<Geometry> posedUse(const Context& c, const tinygltf::Node& n, const std::string& name,
                                   const std::shared_ptr<Geometry>& shared) {
    const bool posed = n.skin >= 0 || !shared->morphTargets.empty();
    if (n.skin >= 0 && shared->joints0.empty())
        c.fail(name + ".skin", "is set but mesh primitive '" + shared->name + "' has no JOINTS_0/WEIGHTS_0");
    if (!posed) return shared;
    // Always a copy of the untouched shared primitive: an unposed use of the same mesh keeps the
    // shared one, and this node's skin and weights stay its own.
    c.charge(1, copyBytes(*shared), name + ".mesh");
    const auto g = shared->clone();
    if (!n.weights.empty() && !g->morphTargets.empty()) {
        if (n.weights.size() != g->morphTargets.size())
            c.fail(name + ".weights", std::to_string(n.weights.size()) + " weights for " +
                                          std::to_string(g->morphTargets.size()) + " morph targets");
        const std::vector<float> w(n.weights.begin(), n.weights.end());
        try {
            g->setMorphWeights(w);
        } catch (const std::invalid_argument& e) {
            c.fail(name + ".weights", e.what());
        }
    }
    return g;
}

// Skins resolved now that every joint node exists, the first pose computed (so bounds are right
// before any update), and the animations read into the root's player.
void finishPose(const Context& c, const NodeInstances& nodes,
                const std::vector<std::pair<std::shared_ptr<Geometry>, int>>& skinUses,
                const std::shared_ptr<Group>& root, GltfStats& st) {
    const auto skins = readSkins(c, nodes, root);
    for (const auto& [g, skin] : skinUses) {
        if (std::size_t(skin) >= skins.size())
            c.fail("nodes (mesh '" + g->name + "').skin", "skin " + std::to_string(skin) +
                                                              " does not exist (" +
                                                              std::to_string(skins.size()) + " skins)");
        g->skin = skins[std::size_t(skin)];
        try {
            g->validate();
        } catch (const std::invalid_argument& e) {
            c.fail(at("skins", std::size_t(skin)), e.what());
        }
    }
    st.skins = skins.size();
    if (auto* player = animationPlayer(*root)) {
        readAnimations(c, nodes, *player);
        st.animations = player->animations.size();
        try {
            player->play(0);
            player->update(0.0);
        } catch (const std::exception& e) { // a pose that is not finite
            c.fail("animations[0]", std::string("cannot pose the model at time 0: ") + e.what());
        }
    }
    // The joint matrices of the first pose, so the bounds are right before any update.
    for (const auto& [g, skin] : skinUses)
        g->updateSkin();
}

std::shared_ptr<Group> load(std::span<const std::byte> bytes, const std::string& path,
                            const std::string& rootName, const std::filesystem::path* baseDir,
                            const GltfOptions& options, GltfStats* stats) {
    auto refuse = [&](const std::string& why) { return LoadError("sgfx: glTF '" + path + "': " + why); };
    if (bytes.size() > std::numeric_limits<unsigned int>::max() / 2) throw refuse("larger than 2 GiB");
    const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
    const bool binary = isGlb(bytes);
    // The JSON of a .glb is its first chunk (length at byte 12); a bad header is tinygltf's to report.
    std::size_t jsonBegin = 0, jsonLength = bytes.size();
    if (binary && bytes.size() >= 20) {
        std::uint32_t chunk = 0;
        std::memcpy(&chunk, data + 12, 4);
        jsonBegin = 20;
        jsonLength = std::min<std::size_t>(chunk, bytes.size() - 20);
    }
    if (jsonDepth(data + jsonBegin, jsonLength) > 256) throw refuse("JSON is nested more than 256 deep");
    checkJson(data + jsonBegin, jsonLength, path);
    const gltf::PunctualLights punctual = gltf::readPunctualLights(data + jsonBegin, jsonLength, path);

    Budget budget{options.memoryLimit};
    FsData fsData{baseDir != nullptr, options.memoryLimit};
    tinygltf::TinyGLTF loader;
    loader.SetImageLoader(decodeImage, &budget);
    loader.SetFsCallbacks(fsCallbacks(&fsData));
    tinygltf::Model model;
    std::string err, warn;
    const std::string dir = baseDir ? baseDir->string() : std::string();
    bool ok = false;
    try {
        ok = binary ? loader.LoadBinaryFromMemory(&model, &err, &warn, data, unsigned(bytes.size()), dir)
                    : loader.LoadASCIIFromString(&model, &err, &warn, reinterpret_cast<const char*>(data),
                                                 unsigned(bytes.size()), dir);
    } catch (const std::exception& e) {
        // tinygltf 2.7 throws on some bad files (std::out_of_range for a GLB buffer of byteLength 0).
        err = e.what();
    }
    if (!ok) throw refuse(err.empty() ? std::string("not a glTF file") : err);
    decodeDeferred(model, budget, [&](const std::string& element, const std::string& why) {
        throw refuse(element + ": " + why);
    });
    const Context c{path, model, &budget, options.memoryLimit};
    GltfStats st;
    static const std::set<std::string> supported = {
        "KHR_texture_transform",      "KHR_materials_emissive_strength",
        "KHR_materials_unlit",        "KHR_materials_clearcoat",
        "KHR_materials_specular",     "EXT_mesh_gpu_instancing",
        "KHR_mesh_quantization",      "KHR_lights_punctual",
        "KHR_materials_transmission", "KHR_materials_volume",
        "KHR_materials_ior"};
    for (const std::string& required : model.extensionsRequired)
        if (!supported.count(required))
            c.fail("extensionsRequired",
                   "extension '" + required + "' is required but not supported (supported: " +
                       "KHR_texture_transform, KHR_materials_emissive_strength, " +
                       "KHR_materials_unlit, KHR_materials_clearcoat, " +
                       "KHR_materials_specular, EXT_mesh_gpu_instancing, " +
                       "KHR_mesh_quantization, KHR_lights_punctual, KHR_materials_transmission, " +
                       "KHR_materials_volume, KHR_materials_ior)");
    for (const std::string& used : model.extensionsUsed)
        if (!supported.count(used))
            st.warnings.push_back("extension '" + used + "' is not supported; the model is shown without it");
    std::istringstream tinyWarnings(warn);
    for (std::string line; std::getline(tinyWarnings, line);)
        if (!line.empty()) st.warnings.push_back(line);
    // Materials.
    std::map<std::pair<int, bool>, std::shared_ptr<Texture>> textures;
    std::vector<std::shared_ptr<StateSet>> materials;
    for (std::size_t i = 0; i < model.materials.size(); ++i) {
        const tinygltf::Material& m = model.materials[i];
        const std::string name = at("materials", i);
        auto mat = Material::create();
        mat->model = ShadingModel::MetallicRoughness;
        const tinygltf::PbrMetallicRoughness& pbr = m.pbrMetallicRoughness;
        const std::string pbrName = name + ".pbrMetallicRoughness";
        mat->diffuse = vec4Of(c, pbr.baseColorFactor, pbrName + ".baseColorFactor");
        if (!m.emissiveFactor.empty()) mat->emissive = vec3Of(c, m.emissiveFactor, name + ".emissiveFactor");
        if (const auto e = m.extensions.find("KHR_materials_emissive_strength"); e != m.extensions.end())
            mat->emissive *= numberOf(c, e->second, "emissiveStrength", 1.0,
                                      name + ".extensions.KHR_materials_emissive_strength");
        mat->metallic = float(pbr.metallicFactor);
        mat->roughness = float(pbr.roughnessFactor);
        auto texture = [&](const auto& info, bool srgb, MaterialMap map, const std::string& element) {
            if (info.index < 0) return std::shared_ptr<Texture>();
            mat->mapping(map) = mappingOf(c, info.texCoord, info.extensions, element);
            return loadTexture(c, info.index, srgb, element, textures);
        };
        mat->baseColorTexture =
            texture(pbr.baseColorTexture, true, MaterialMap::BaseColor, pbrName + ".baseColorTexture");
        mat->metallicRoughnessTexture =
            texture(pbr.metallicRoughnessTexture, false, MaterialMap::MetallicRoughness,
                    pbrName + ".metallicRoughnessTexture");
        mat->normalTexture = texture(m.normalTexture, false, MaterialMap::Normal, name + ".normalTexture");
        mat->normalScale = float(m.normalTexture.scale);
        mat->occlusionTexture =
            texture(m.occlusionTexture, false, MaterialMap::Occlusion, name + ".occlusionTexture");
        mat->occlusionStrength = float(m.occlusionTexture.strength);
        mat->emissiveTexture =
            texture(m.emissiveTexture, true, MaterialMap::Emissive, name + ".emissiveTexture");
        readMaterialExtensions(c, m, *mat, name, texture);
        auto state = std::make_shared<StateSet>();
        state->material.set(mat);
        if (m.doubleSided) state->cullFace.set(CullFace::None);
        if (m.alphaMode == "MASK") {
            mat->alphaCutoff = float(m.alphaCutoff);
            ++st.masked;
        } else if (m.alphaMode == "BLEND") {
            state->blend.set(BlendMode::Alpha);
            ++st.blended;
        } else if (m.alphaMode == "OPAQUE" || m.alphaMode.empty()) {
            ++st.opaque;
        } else {
            c.fail(name + ".alphaMode", "'" + m.alphaMode + "' is not OPAQUE, MASK or BLEND");
        }
        try {
            mat->validate();
        } catch (const std::invalid_argument& e) {
            c.fail(name, e.what()); // negative or overflowing factors
        }
        materials.push_back(state);
    }
    st.materials = model.materials.size();

    // Meshes: one Geometry per primitive, shared by every node that uses the mesh.
    std::vector<std::vector<std::shared_ptr<Geometry>>> meshes(model.meshes.size());
    std::vector<bool> meshUsed(model.meshes.size(), false);
    std::size_t unweighted = 0; // skinned vertices without weights
    auto buildMesh = [&](std::size_t mi) {
        const tinygltf::Mesh& mesh = model.meshes[mi];
        for (std::size_t pi = 0; pi < mesh.primitives.size(); ++pi) {
            const tinygltf::Primitive& p = mesh.primitives[pi];
            const std::string name = at("meshes", mi) + "." + at("primitives", pi);
            const auto pos = p.attributes.find("POSITION");
            if (pos == p.attributes.end()) c.fail(name + ".attributes", "has no POSITION");
            std::size_t n = 0;
            const std::vector<float> positions =
                readAccessor(c, pos->second, name + ".attributes.POSITION", {TINYGLTF_TYPE_VEC3}, &n);
            for (float v : positions)
                if (!std::isfinite(v))
                    c.fail(name + ".attributes.POSITION", "has a NaN or infinite coordinate");
            auto attribute = [&](const char* key, std::initializer_list<int> types) {
                const auto it = p.attributes.find(key);
                if (it == p.attributes.end()) return std::vector<float>{};
                std::size_t count = 0;
                auto values = readAccessor(c, it->second, name + ".attributes." + key, types, &count);
                if (count != n)
                    c.fail(name + ".attributes." + key,
                           std::to_string(count) + " values for " + std::to_string(n) + " positions");
                return values;
            };
            const auto normals = attribute("NORMAL", {TINYGLTF_TYPE_VEC3});
            const auto uvs = attribute("TEXCOORD_0", {TINYGLTF_TYPE_VEC2});
            const auto uvs1 = attribute("TEXCOORD_1", {TINYGLTF_TYPE_VEC2});
            const auto colors = attribute("COLOR_0", {TINYGLTF_TYPE_VEC3, TINYGLTF_TYPE_VEC4});
            const auto tangents = attribute("TANGENT", {TINYGLTF_TYPE_VEC4});
            std::vector<std::uint32_t> indices;
            if (p.indices >= 0) {
                if (std::size_t(p.indices) >= model.accessors.size())
                    c.fail(name + ".indices", "accessor " + std::to_string(p.indices) + " does not exist");
                const auto& a = model.accessors[std::size_t(p.indices)];
                if (a.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT ||
                    a.componentType == TINYGLTF_COMPONENT_TYPE_BYTE ||
                    a.componentType == TINYGLTF_COMPONENT_TYPE_SHORT)
                    c.fail(name + ".indices", "must be an accessor of unsigned integers");
                for (float v : readAccessor(c, p.indices, name + ".indices", {TINYGLTF_TYPE_SCALAR})) {
                    if (v >= float(n))
                        c.fail(name + ".indices", "index " + std::to_string(std::uint64_t(v)) + " (entry " +
                                                      std::to_string(indices.size()) + " of " +
                                                      at("accessors", std::size_t(p.indices)) +
                                                      ") is out of range for " + std::to_string(n) +
                                                      " vertices");
                    indices.push_back(std::uint32_t(v));
                }
            }
            // Positions, normals, texcoords, tangents, colours as the Geometry stores them.
            c.charge(n, vertexBytes, name);
            auto g = Geometry::create();
            g->name = mesh.name.empty() ? name : mesh.name + "." + std::to_string(pi);
            for (std::size_t i = 0; i < n; ++i) {
                g->positions.emplace_back(positions[3 * i], positions[3 * i + 1], positions[3 * i + 2]);
                if (!normals.empty())
                    g->normals.emplace_back(normals[3 * i], normals[3 * i + 1], normals[3 * i + 2]);
                if (!uvs.empty()) g->texcoords.emplace_back(uvs[2 * i], uvs[2 * i + 1]);
                if (!uvs1.empty()) g->texcoords1.emplace_back(uvs1[2 * i], uvs1[2 * i + 1]);
                if (!tangents.empty())
                    g->tangents.emplace_back(tangents[4 * i], tangents[4 * i + 1], tangents[4 * i + 2],
                                             tangents[4 * i + 3]);
                if (!colors.empty()) {
                    const std::size_t k = colors.size() / n;
                    g->colors.emplace_back(colors[k * i], colors[k * i + 1], colors[k * i + 2],
                                           k == 4 ? colors[k * i + 3] : 1.0f);
                }
            }
            g->indices = std::move(indices);
            readSkinAttributes(c, p, name, n, *g, unweighted);
            readMorphTargets(c, p, name, n, *g);
            if (!g->morphTargets.empty() && !mesh.weights.empty()) {
                if (mesh.weights.size() != g->morphTargets.size())
                    c.fail(at("meshes", mi) + ".weights",
                           std::to_string(mesh.weights.size()) + " weights for " +
                               std::to_string(g->morphTargets.size()) + " targets");
                const std::vector<float> w(mesh.weights.begin(), mesh.weights.end());
                try {
                    g->setMorphWeights(w);
                } catch (const std::invalid_argument& e) {
                    c.fail(at("meshes", mi) + ".weights", e.what());
                }
            }
            switch (p.mode) {
            case TINYGLTF_MODE_POINTS:
                g->mode = PrimitiveMode::Points;
                break;
            case TINYGLTF_MODE_LINE:
                g->mode = PrimitiveMode::Lines;
                break;
            case TINYGLTF_MODE_LINE_LOOP: {
                g->mode = PrimitiveMode::LineStrip; // closed by repeating the first vertex
                if (g->indices.empty())
                    for (std::uint32_t i = 0; i < n; ++i)
                        g->indices.push_back(i);
                g->indices.push_back(g->indices.front());
                break;
            }
            case TINYGLTF_MODE_LINE_STRIP:
                g->mode = PrimitiveMode::LineStrip;
                break;
            case TINYGLTF_MODE_TRIANGLE_STRIP:
                g->mode = PrimitiveMode::TriangleStrip;
                break;
            case TINYGLTF_MODE_TRIANGLE_FAN:
                g->mode = PrimitiveMode::TriangleFan;
                break;
            case TINYGLTF_MODE_TRIANGLES:
            case -1:
                g->mode = PrimitiveMode::Triangles;
                break;
            default:
                c.fail(name + ".mode", std::to_string(p.mode) + " is not a glTF primitive mode");
            }
            // Normals where the file has none (flat by default, as the spec asks), and tangents
            // where a normal map needs them.
            const bool triangles = g->mode == PrimitiveMode::Triangles ||
                                   g->mode == PrimitiveMode::TriangleStrip ||
                                   g->mode == PrimitiveMode::TriangleFan;
            if (g->normals.empty() && triangles && g->elementCount() >= 3) {
                c.charge(g->elementCount(), vertexBytes, name); // at most one vertex per corner
                computeNormals(*g, options.creaseAngle);
            }
            if (p.material >= 0 && std::size_t(p.material) < model.materials.size() && g->tangents.empty() &&
                !g->texcoords.empty() && !g->normals.empty() && triangles && g->elementCount() >= 3 &&
                model.materials[std::size_t(p.material)].normalTexture.index >= 0) {
                c.charge(g->elementCount(), vertexBytes, name);
                computeTangents(*g);
                ++st.tangentsMade;
            }
            if (p.material >= 0) {
                if (std::size_t(p.material) >= materials.size())
                    c.fail(name + ".material", "material " + std::to_string(p.material) + " does not exist");
                g->setStateSet(materials[std::size_t(p.material)]);
            }
            try {
                g->validate();
            } catch (const std::invalid_argument& e) {
                c.fail(name, e.what());
            }
            st.triangles += g->triangleCount();
            ++st.primitives;
            meshes[mi].push_back(g);
        }
        ++st.meshes;
    };

    // Nodes, depth first; a node met again on its own path is a cycle.
    NodeInstances nodes;
    nodes.transforms.resize(model.nodes.size());
    nodes.geometry.resize(model.nodes.size());
    std::vector<std::pair<std::shared_ptr<Geometry>, int>> skinUses; // resolved once every node exists
    std::vector<int> ancestors;
    std::function<std::shared_ptr<Node>(int, const std::string&)> buildNode = [&](int index,
                                                                                  const std::string& from) {
        if (index < 0 || std::size_t(index) >= model.nodes.size())
            c.fail(from, "node " + std::to_string(index) + " does not exist (" +
                             std::to_string(model.nodes.size()) + " nodes)");
        const std::string name = at("nodes", std::size_t(index));
        if (std::find(ancestors.begin(), ancestors.end(), index) != ancestors.end())
            c.fail(name, "is its own ancestor (a cycle)");
        if (ancestors.size() > 1000) c.fail(name, "is nested more than 1000 deep");
        ancestors.push_back(index);
        const tinygltf::Node& n = model.nodes[std::size_t(index)];
        glm::mat4 m(1.0f);
        if (n.matrix.size() == 16) {
            m = glm::make_mat4(std::vector<float>(n.matrix.begin(), n.matrix.end()).data());
        } else if (!n.matrix.empty()) {
            c.fail(name + ".matrix", "must have 16 numbers");
        } else {
            if (!n.translation.empty() && n.translation.size() != 3)
                c.fail(name + ".translation", "must have 3 numbers");
            if (!n.rotation.empty() && n.rotation.size() != 4)
                c.fail(name + ".rotation", "must have 4 numbers");
            if (!n.scale.empty() && n.scale.size() != 3) c.fail(name + ".scale", "must have 3 numbers");
            if (n.translation.size() == 3)
                m = glm::translate(
                    m, glm::vec3(float(n.translation[0]), float(n.translation[1]), float(n.translation[2])));
            if (n.rotation.size() == 4)
                m *= glm::mat4_cast(glm::quat(float(n.rotation[3]), float(n.rotation[0]),
                                              float(n.rotation[1]), float(n.rotation[2])));
            if (n.scale.size() == 3)
                m = glm::scale(m, glm::vec3(float(n.scale[0]), float(n.scale[1]), float(n.scale[2])));
        }
        for (int k = 0; k < 16; ++k)
            if (!std::isfinite(glm::value_ptr(m)[k])) c.fail(name, "has a NaN or infinite transform");
        auto t = Transform::create(m);
        t->name = n.name.empty() ? name : n.name;
        nodes.transforms[std::size_t(index)].push_back(t);
        if (n.mesh < 0) nodes.geometry[std::size_t(index)].emplace_back();
        // A node may be listed as a child many times over: each use is an instance, so a small
        // file can describe exponentially many. Every instance and child link is charged.
        c.charge(1, 256, name);
        ++st.nodes;
        if (n.mesh >= 0) {
            if (std::size_t(n.mesh) >= model.meshes.size())
                c.fail(name + ".mesh", "mesh " + std::to_string(n.mesh) + " does not exist");
            if (!meshUsed[std::size_t(n.mesh)]) {
                meshUsed[std::size_t(n.mesh)] = true;
                buildMesh(std::size_t(n.mesh));
            }
            const auto inst = n.extensions.find("EXT_mesh_gpu_instancing");
            const std::vector<glm::mat4> instances =
                inst == n.extensions.end()
                    ? std::vector<glm::mat4>{}
                    : instanceMatrices(c, inst->second, name + ".extensions.EXT_mesh_gpu_instancing");
            c.charge(meshes[std::size_t(n.mesh)].size(), 32, name + ".mesh");
            auto& attached = nodes.geometry[std::size_t(index)].emplace_back();
            for (const auto& shared : meshes[std::size_t(n.mesh)]) {
                // A skinned or morphed use owns its geometry: its pose is its own.
                const auto g = posedUse(c, n, name, shared);
                if (instances.empty()) {
                    t->addChild(g);
                    attached.push_back(g);
                    if (n.skin >= 0) skinUses.emplace_back(g, n.skin);
                    continue;
                }
                // The instances belong to this node: an instanced copy of the shared primitive.
                c.charge(1, copyBytes(*g) + instances.size() * 2 * sizeof(glm::mat4), name + ".mesh");
                auto copy = g->clone();
                copy->instances = instances;
                t->addChild(copy);
                attached.push_back(copy);
                if (n.skin >= 0) skinUses.emplace_back(copy, n.skin);
                st.instances += instances.size();
            }
        }
        // KHR_lights_punctual: the light at the node's origin, along its -Z (Light's defaults).
        if (auto light = punctual.of(std::size_t(index))) {
            t->addChild(light);
            ++st.lights;
        }
        for (std::size_t k = 0; k < n.children.size(); ++k)
            t->addChild(buildNode(n.children[k], name + ".children"));
        ancestors.pop_back();
        return t;
    };

    // A file with animations loads as an AnimatedGroup, playing its first animation.
    std::shared_ptr<Group> root = model.animations.empty() ? Group::create() : AnimatedGroup::create();
    root->name = rootName;
    std::vector<int> roots;
    const int sceneIndex = options.scene >= 0 ? options.scene : std::max(model.defaultScene, 0);
    if (!model.scenes.empty()) {
        if (std::size_t(sceneIndex) >= model.scenes.size())
            c.fail("scene", "scene " + std::to_string(sceneIndex) + " does not exist");
        roots = model.scenes[std::size_t(sceneIndex)].nodes;
    } else {
        std::set<int> children;
        for (const auto& n : model.nodes)
            children.insert(n.children.begin(), n.children.end());
        for (std::size_t i = 0; i < model.nodes.size(); ++i)
            if (!children.count(int(i))) roots.push_back(int(i));
    }
    std::shared_ptr<Group> parent = root;
    if (options.zUp) {
        auto up = Transform::create(glm::rotate(glm::mat4(1.0f), glm::radians(90.0f), glm::vec3(1, 0, 0)));
        up->name = "glTF Y up to Z up";
        root->addChild(up);
        parent = up;
    }
    for (int r : roots)
        parent->addChild(buildNode(r, at("scenes", std::size_t(sceneIndex)) + ".nodes"));
    finishPose(c, nodes, skinUses, root, st);
    if (options.optimizeOrder) st.reordered = optimizeMeshes(*root);
    if (options.autoLod.enabled) st.autoLods = addAutoLods(*root, options.autoLod);
    if (unweighted)
        st.warnings.push_back(std::to_string(unweighted) +
                              " skinned vertices have no weight; bound to joint 0");
    std::set<int> texturesUsed;
    for (const auto& [key, tex] : textures)
        texturesUsed.insert(key.first);
    st.textures = texturesUsed.size();
    if (stats)
        *stats = st;
    else
        for (const std::string& w : st.warnings)
            std::fprintf(stderr, "sgfx: glTF '%s': warning: %s\n", path.c_str(), w.c_str());
    return root;
}

} // namespace

std::shared_ptr<Group> loadGltf(const std::filesystem::path& file, const GltfOptions& options,
                                GltfStats* stats) {
    const std::string path = file.string();
    std::error_code ec;
    if (!std::filesystem::is_regular_file(file, ec))
        throw LoadError("sgfx: glTF '" + path + "': no such file");
    const auto size = std::filesystem::file_size(file, ec);
    if (ec || size > options.memoryLimit)
        throw LoadError("sgfx: glTF '" + path + "': " + (ec ? ec.message() : "larger than the memory limit"));
    std::vector<std::byte> bytes(static_cast<std::size_t>(size));
    std::ifstream in(file, std::ios::binary);
    if (!in.read(reinterpret_cast<char*>(bytes.data()), std::streamsize(bytes.size())))
        throw LoadError("sgfx: glTF '" + path + "': cannot read it");
    const std::filesystem::path dir = file.parent_path();
    return load(bytes, path, file.filename().string(), &dir, options, stats);
}

std::shared_ptr<Group> loadGltfFromMemory(std::span<const std::byte> bytes, std::string_view nameForErrors,
                                          const GltfOptions& options, GltfStats* stats) {
    const std::string name(nameForErrors);
    return load(bytes, name, name, nullptr, options, stats);
}

} // namespace sgfx

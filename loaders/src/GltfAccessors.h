#pragma once
// Checked reads of a glTF document for the loader: the memory budget, the load's context (file,
// model, errors naming the element) and accessors read as floats after every index, offset,
// count and stride was checked (tinygltf 2.7 checks few of them).
#include <sgfx/GltfLoader.h>

#include <tiny_gltf.h>

#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <string>
#include <vector>

namespace sgfx::gltf {

// What a load may still allocate (GltfOptions::memoryLimit), charged before each allocation that
// the file's declared sizes drive.
struct Budget {
    std::size_t left = 0;
    bool take(std::size_t bytes) {
        if (bytes > left) return false;
        left -= bytes;
        return true;
    }
};

// Bytes a vertex may take in a Geometry: position, normal, tangent, two texcoords, colour.
constexpr std::size_t vertexBytes = (3 + 3 + 4 + 2 + 2 + 4) * sizeof(float);

// A LoadError naming the file, the element and the reason.
struct Refusal {
    const std::string& file;
    [[noreturn]] void operator()(const std::string& element, const std::string& why) const {
        throw LoadError("sgfx: glTF '" + file + "': " + element + ": " + why);
    }
};

struct Context {
    std::string file;
    const tinygltf::Model& model;
    Budget* budget;
    std::size_t limit;
    [[noreturn]] void fail(const std::string& element, const std::string& why) const {
        throw LoadError("sgfx: glTF '" + file + "': " + element + ": " + why);
    }
    // `note` ends the message (" (used by meshes[0]...)" where an accessor is read for an element).
    void charge(std::size_t count, std::size_t bytesEach, const std::string& element,
                const std::string& note = {}) const {
        if ((bytesEach && count > SIZE_MAX / bytesEach) || !budget->take(count * bytesEach))
            fail(element, "needs more memory than the load's limit of " + std::to_string(limit) +
                              " bytes (GltfOptions::memoryLimit)" + note);
    }
};

// "meshes[2]"
inline std::string at(const char* array, std::size_t i) {
    return std::string(array) + "[" + std::to_string(i) + "]";
}

// An accessor as floats (count × components), sparse values applied. `element` is what reads it
// (meshes[0].primitives[1].attributes.POSITION): errors in the accessor name both.
std::vector<float> readAccessor(const Context& c, int index, const std::string& element,
                                std::initializer_list<int> types, std::size_t* countOut = nullptr);

} // namespace sgfx::gltf

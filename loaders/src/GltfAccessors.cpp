#include "GltfAccessors.h"

#include <algorithm>
#include <cstring>

namespace sgfx::gltf {

namespace {
int componentBytes(int type) {
    switch (type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
        return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
        return 2;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT:
        return 4;
    default:
        return 0;
    }
}

const char* typeName(int type) {
    switch (type) {
    case TINYGLTF_TYPE_SCALAR:
        return "SCALAR";
    case TINYGLTF_TYPE_VEC2:
        return "VEC2";
    case TINYGLTF_TYPE_VEC3:
        return "VEC3";
    case TINYGLTF_TYPE_VEC4:
        return "VEC4";
    case TINYGLTF_TYPE_MAT2:
        return "MAT2";
    case TINYGLTF_TYPE_MAT3:
        return "MAT3";
    case TINYGLTF_TYPE_MAT4:
        return "MAT4";
    default:
        return "unknown";
    }
}

int componentsOf(int type) {
    switch (type) {
    case TINYGLTF_TYPE_SCALAR:
        return 1;
    case TINYGLTF_TYPE_VEC2:
        return 2;
    case TINYGLTF_TYPE_VEC3:
        return 3;
    case TINYGLTF_TYPE_VEC4:
    case TINYGLTF_TYPE_MAT2:
        return 4;
    case TINYGLTF_TYPE_MAT3:
        return 9;
    case TINYGLTF_TYPE_MAT4:
        return 16;
    default:
        return 0;
    }
}

// One component at `p` as float, normalised integers mapped as the spec says.
float component(const unsigned char* p, int type, bool normalized) {
    switch (type) {
    case TINYGLTF_COMPONENT_TYPE_FLOAT: {
        float f;
        std::memcpy(&f, p, 4);
        return f;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
        return normalized ? float(*p) / 255.0f : float(*p);
    case TINYGLTF_COMPONENT_TYPE_BYTE: {
        const auto v = float(static_cast<std::int8_t>(*p));
        return normalized ? std::max(v / 127.0f, -1.0f) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
        std::uint16_t v;
        std::memcpy(&v, p, 2);
        return normalized ? float(v) / 65535.0f : float(v);
    }
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
        std::int16_t v;
        std::memcpy(&v, p, 2);
        return normalized ? std::max(float(v) / 32767.0f, -1.0f) : float(v);
    }
    default: {
        std::uint32_t v;
        std::memcpy(&v, p, 4);
        return float(v);
    }
    }
}

// The bytes of `count` elements of `elementBytes` from a buffer view, checked against its buffer.
// `element` reads them (accessors[2], accessors[2].sparse.indices); `note` ends each message.
struct View {
    const unsigned char* data = nullptr;
    std::size_t stride = 0;
};
View checkedView(const Context& c, int viewIndex, std::size_t offset, std::size_t count,
                 std::size_t elementBytes, const std::string& element, const std::string& note) {
    const auto& views = c.model.bufferViews;
    if (viewIndex < 0 || std::size_t(viewIndex) >= views.size())
        c.fail(element, "bufferView " + std::to_string(viewIndex) + " does not exist (" +
                            std::to_string(views.size()) + " buffer views)" + note);
    const tinygltf::BufferView& v = views[std::size_t(viewIndex)];
    const std::string viewName = at("bufferViews", std::size_t(viewIndex));
    if (v.buffer < 0 || std::size_t(v.buffer) >= c.model.buffers.size())
        c.fail(viewName, "buffer " + std::to_string(v.buffer) + " does not exist" + note);
    const std::size_t bufferSize = c.model.buffers[std::size_t(v.buffer)].data.size();
    if (v.byteOffset > bufferSize || v.byteLength > bufferSize - v.byteOffset)
        c.fail(viewName, "bytes " + std::to_string(v.byteOffset) + ".." +
                             std::to_string(v.byteOffset + v.byteLength) + " lie outside its buffer of " +
                             std::to_string(bufferSize) + " bytes" + note);
    // 4..252 and a multiple of 4 is checked on the JSON (checkJson); here, against the element.
    const std::size_t stride = v.byteStride ? v.byteStride : elementBytes;
    if (v.byteStride > 252)
        c.fail(viewName + ".byteStride", std::to_string(v.byteStride) + " is outside 4..252" + note);
    if (v.byteStride && v.byteStride < elementBytes)
        c.fail(viewName + ".byteStride", std::to_string(v.byteStride) + " is less than the " +
                                             std::to_string(elementBytes) + " bytes of each element of " +
                                             element + note);
    if (count > 0 && (offset > v.byteLength || (count - 1) > (v.byteLength - offset) / stride ||
                      offset + (count - 1) * stride + elementBytes > v.byteLength))
        c.fail(element, std::to_string(count) + " elements of " + std::to_string(elementBytes) +
                            " bytes from offset " + std::to_string(offset) + " (stride " +
                            std::to_string(stride) + ") run past the " + std::to_string(v.byteLength) +
                            " bytes of " + viewName + note);
    return {c.model.buffers[std::size_t(v.buffer)].data.data() + v.byteOffset + offset, stride};
}

} // namespace

std::vector<float> readAccessor(const Context& c, int index, const std::string& element,
                                std::initializer_list<int> types, std::size_t* countOut) {
    const auto& accessors = c.model.accessors;
    if (index < 0 || std::size_t(index) >= accessors.size())
        c.fail(element, "accessor " + std::to_string(index) + " does not exist (" +
                            std::to_string(accessors.size()) + " accessors)");
    const tinygltf::Accessor& a = accessors[std::size_t(index)];
    const std::string name = at("accessors", std::size_t(index));
    const std::string note = " (used by " + element + ")";
    const int bytes = componentBytes(a.componentType), n = componentsOf(a.type);
    if (!bytes)
        c.fail(name,
               "componentType " + std::to_string(a.componentType) + " is not a glTF component type" + note);
    if (!n || std::find(types.begin(), types.end(), a.type) == types.end())
        c.fail(element, "accessor " + std::to_string(index) + " has type " + typeName(a.type) +
                            ", which this attribute cannot take");
    if (a.count == 0 || a.count > (std::size_t(1) << 28))
        c.fail(name, "count " + std::to_string(a.count) + " is out of range" + note);
    // The view is checked before anything is allocated: the count must fit in the file's bytes.
    View v;
    if (a.bufferView >= 0)
        v = checkedView(c, a.bufferView, a.byteOffset, a.count, std::size_t(bytes * n), name, note);
    c.charge(a.count, std::size_t(n) * sizeof(float), name, note);
    std::vector<float> out(a.count * std::size_t(n), 0.0f);
    if (a.bufferView >= 0) {
        for (std::size_t i = 0; i < a.count; ++i)
            for (int k = 0; k < n; ++k)
                out[i * std::size_t(n) + std::size_t(k)] =
                    component(v.data + i * v.stride + std::size_t(k * bytes), a.componentType, a.normalized);
    }
    if (a.sparse.isSparse) {
        const auto sc = std::size_t(std::max(a.sparse.count, 0));
        if (sc == 0 || sc > a.count)
            c.fail(name + ".sparse", "count " + std::to_string(a.sparse.count) + " is out of range" + note);
        const int ib = componentBytes(a.sparse.indices.componentType);
        if (ib == 0 || a.sparse.indices.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT ||
            a.sparse.indices.componentType == TINYGLTF_COMPONENT_TYPE_BYTE ||
            a.sparse.indices.componentType == TINYGLTF_COMPONENT_TYPE_SHORT)
            c.fail(name + ".sparse.indices", "componentType must be an unsigned integer type" + note);
        const View iv = checkedView(c, a.sparse.indices.bufferView, std::size_t(a.sparse.indices.byteOffset),
                                    sc, std::size_t(ib), name + ".sparse.indices", note);
        const View vv = checkedView(c, a.sparse.values.bufferView, std::size_t(a.sparse.values.byteOffset),
                                    sc, std::size_t(bytes * n), name + ".sparse.values", note);
        for (std::size_t s = 0; s < sc; ++s) {
            const auto target =
                std::size_t(component(iv.data + s * std::size_t(ib), a.sparse.indices.componentType, false));
            if (target >= a.count)
                c.fail(name + ".sparse.indices", "index " + std::to_string(target) + " is not below count " +
                                                     std::to_string(a.count) + note);
            for (int k = 0; k < n; ++k)
                out[target * std::size_t(n) + std::size_t(k)] =
                    component(vv.data + s * std::size_t(bytes * n) + std::size_t(k * bytes), a.componentType,
                              a.normalized);
        }
    }
    if (countOut) *countOut = a.count;
    return out;
}

} // namespace sgfx::gltf

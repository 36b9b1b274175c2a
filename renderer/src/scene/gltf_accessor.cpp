#include "scene/gltf_accessor.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "glint/image/error.h"

namespace glint::render::detail {

namespace {

/// The bytes of a buffer read at a time from its file: so much of it is in memory at most while
/// an accessor is read.
constexpr std::size_t kReadBytes = std::size_t(1) << 20;

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
        default:
            return "a matrix";
    }
}

const char* componentName(int componentType) {
    switch (componentType) {
        case TINYGLTF_COMPONENT_TYPE_BYTE:
            return "byte";
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
            return "unsigned byte";
        case TINYGLTF_COMPONENT_TYPE_SHORT:
            return "short";
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
            return "unsigned short";
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
            return "unsigned int";
        case TINYGLTF_COMPONENT_TYPE_FLOAT:
            return "float";
        default:
            return "an unknown type";
    }
}

std::size_t componentSize(int componentType) {
    switch (componentType) {
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

int componentCount(int type) {
    switch (type) {
        case TINYGLTF_TYPE_SCALAR:
            return 1;
        case TINYGLTF_TYPE_VEC2:
            return 2;
        case TINYGLTF_TYPE_VEC3:
            return 3;
        case TINYGLTF_TYPE_VEC4:
            return 4;
        default:
            return 0;
    }
}

/// Component c of the element at p as a float (normalised integers mapped to [0, 1]).
float component(const unsigned char* p, int c, int componentType) {
    switch (componentType) {
        case TINYGLTF_COMPONENT_TYPE_FLOAT: {
            float v;
            std::memcpy(&v, p + 4 * c, 4);
            return v;
        }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
            return float(p[c]) / 255.0f;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
            std::uint16_t v;
            std::memcpy(&v, p + 2 * c, 2);
            return float(v) / 65535.0f;
        }
        default:
            return 0.0f;
    }
}

/// An unsigned integer component (indices).
std::uint32_t readIndex(const unsigned char* p, int componentType) {
    switch (componentType) {
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
            return p[0];
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
            std::uint16_t v;
            std::memcpy(&v, p, 2);
            return v;
        }
        default: {
            std::uint32_t v;
            std::memcpy(&v, p, 4);
            return v;
        }
    }
}

}  // namespace

std::string accessorPlace(int index) {
    return "accessors[" + std::to_string(index) + "]";
}

void GltfAccessors::fail(const std::string& place, const std::string& what) const {
    throw Error(ErrorKind::Format, what, m_file.string(), place);
}

std::size_t GltfAccessors::count(int index, const std::string& use) const {
    if (index < 0 || std::size_t(index) >= m_model.accessors.size())
        fail(use, "names accessor " + std::to_string(index) + ", but the asset has " +
                      std::to_string(m_model.accessors.size()));
    return m_model.accessors[std::size_t(index)].count;
}

std::size_t GltfAccessors::readableCount(int index) const {
    if (index < 0 || std::size_t(index) >= m_model.accessors.size()) return 0;
    const tinygltf::Accessor& a = m_model.accessors[std::size_t(index)];
    const std::size_t elementSize =
        componentSize(a.componentType) * std::size_t(componentCount(a.type));
    if (a.count > (std::size_t(1) << 31) || elementSize == 0) return 0;
    if (a.bufferView < 0) return a.count;
    // The bounds layout() checks, without naming what is wrong.
    if (std::size_t(a.bufferView) >= m_model.bufferViews.size()) return 0;
    const tinygltf::BufferView& view = m_model.bufferViews[std::size_t(a.bufferView)];
    if (view.buffer < 0 || std::size_t(view.buffer) >= m_buffers.count()) return 0;
    const std::size_t size = m_buffers.size(std::size_t(view.buffer));
    const std::size_t stride = view.byteStride != 0 ? view.byteStride : elementSize;
    const std::size_t span = a.count == 0 ? 0 : (a.count - 1) * stride + elementSize;
    if (view.byteOffset > size || view.byteLength > size - view.byteOffset ||
        a.byteOffset > view.byteLength || span > view.byteLength - a.byteOffset)
        return 0;
    return a.count;
}

template <typename Read>
void GltfAccessors::forEachElement(const Layout& l, Read&& read) const {
    // A megabyte of the buffer at a time: a file's bytes are read into `scratch`, tinygltf's
    // (and a sparse copy) are used in place.
    std::vector<unsigned char> scratch;
    const std::size_t perRead = std::max<std::size_t>(1, kReadBytes / l.stride);
    for (std::size_t first = 0; first < l.count; first += perRead) {
        const std::size_t last = std::min(l.count, first + perRead);
        const std::size_t from = first * l.stride, to = (last - 1) * l.stride + l.elementSize;
        const unsigned char* p = l.data ? l.data + from
                                        : m_buffers.bytes(std::size_t(l.buffer), l.offset + from,
                                                          l.offset + to, scratch);
        for (std::size_t i = first; i < last; ++i) read(i, p + (i - first) * l.stride);
    }
}

GltfAccessors::Layout GltfAccessors::layout(int index, int type,
                                            std::initializer_list<int> componentTypes,
                                            const std::string& use,
                                            std::vector<unsigned char>& sparseCopy) const {
    count(index, use);
    const tinygltf::Accessor& a = m_model.accessors[std::size_t(index)];
    const std::string place = accessorPlace(index);
    if (a.type != type)
        fail(place,
             std::string("is ") + typeName(a.type) + ", but " + use + " needs " + typeName(type));
    bool allowed = false;
    for (int t : componentTypes) allowed = allowed || a.componentType == t;
    if (!allowed) {
        std::string list;
        for (int t : componentTypes)
            list += (list.empty() ? "" : " or ") + std::string(componentName(t));
        fail(place, std::string("holds ") + componentName(a.componentType) + " components, but " +
                        use + " needs " + list);
    }
    const std::size_t elementSize =
        componentSize(a.componentType) * std::size_t(componentCount(type));
    // An accessor can claim any count: no more elements than 2^31 (a mesh Glint can index).
    if (a.count > (std::size_t(1) << 31))
        fail(place, "claims " + std::to_string(a.count) + " elements");
    Layout out;
    out.componentType = a.componentType;
    out.normalized = a.normalized;
    out.count = a.count;
    out.stride = out.elementSize = elementSize;
    if (a.bufferView >= 0) {
        if (std::size_t(a.bufferView) >= m_model.bufferViews.size())
            fail(place, "names bufferView " + std::to_string(a.bufferView) +
                            ", but the asset has " + std::to_string(m_model.bufferViews.size()));
        const tinygltf::BufferView& view = m_model.bufferViews[std::size_t(a.bufferView)];
        const std::string viewPlace = "bufferViews[" + std::to_string(a.bufferView) + "]";
        if (view.buffer < 0 || std::size_t(view.buffer) >= m_buffers.count())
            fail(viewPlace, "names buffer " + std::to_string(view.buffer) + ", but the asset has " +
                                std::to_string(m_buffers.count()));
        const std::size_t bufferSize = m_buffers.size(std::size_t(view.buffer));
        if (view.byteOffset > bufferSize || view.byteLength > bufferSize - view.byteOffset)
            fail(viewPlace, "bytes " + std::to_string(view.byteOffset) + " + " +
                                std::to_string(view.byteLength) + " go past the end of buffer " +
                                std::to_string(view.buffer) + " (" + std::to_string(bufferSize) +
                                " bytes)");
        if (view.byteStride != 0) {
            if (view.byteStride < elementSize || view.byteStride > 252)
                fail(viewPlace, "byteStride " + std::to_string(view.byteStride) +
                                    " is not in [element size " + std::to_string(elementSize) +
                                    ", 252]");
            out.stride = view.byteStride;
        }
        // The last element must end inside the view.
        const std::size_t span = a.count == 0 ? 0 : (a.count - 1) * out.stride + elementSize;
        if (a.byteOffset > view.byteLength || span > view.byteLength - a.byteOffset)
            fail(place, std::to_string(a.count) + " elements from byte " +
                            std::to_string(a.byteOffset) + " go past the end of its bufferView (" +
                            std::to_string(view.byteLength) + " bytes)");
        out.buffer = view.buffer;
        out.offset = view.byteOffset + a.byteOffset;
    }
    if (!a.sparse.isSparse) return out;

    // Sparse: the base (or zeros) packed into a copy, then the substitutions.
    const std::string sparsePlace = place + ".sparse";
    sparseCopy.assign(a.count * elementSize, 0);
    if (out.buffer >= 0)
        forEachElement(out, [&](std::size_t i, const unsigned char* p) {
            std::memcpy(&sparseCopy[i * elementSize], p, elementSize);
        });
    const int n = a.sparse.count;
    if (n < 1 || std::size_t(n) > a.count)
        fail(sparsePlace,
             "count " + std::to_string(n) + " is not in [1, " + std::to_string(a.count) + "]");
    std::vector<unsigned char> indexBytes, valueBytes;
    auto span = [&](int viewIndex, std::size_t offset, std::size_t bytes, const std::string& what,
                    std::vector<unsigned char>& scratch) -> const unsigned char* {
        if (viewIndex < 0 || std::size_t(viewIndex) >= m_model.bufferViews.size())
            fail(sparsePlace + "." + what, "names bufferView " + std::to_string(viewIndex) +
                                               ", but the asset has " +
                                               std::to_string(m_model.bufferViews.size()));
        const tinygltf::BufferView& view = m_model.bufferViews[std::size_t(viewIndex)];
        if (view.buffer < 0 || std::size_t(view.buffer) >= m_buffers.count())
            fail(sparsePlace + "." + what, "its bufferView names a missing buffer");
        const std::size_t bufferSize = m_buffers.size(std::size_t(view.buffer));
        if (view.byteOffset > bufferSize || view.byteLength > bufferSize - view.byteOffset ||
            offset > view.byteLength || bytes > view.byteLength - offset)
            fail(sparsePlace + "." + what, "goes past the end of its bufferView or buffer");
        const std::size_t from = view.byteOffset + offset;
        return m_buffers.bytes(std::size_t(view.buffer), from, from + bytes, scratch);
    };
    const int indexType = a.sparse.indices.componentType;
    const std::size_t indexSize = componentSize(indexType);
    if (indexSize == 0 || indexType == TINYGLTF_COMPONENT_TYPE_FLOAT ||
        indexType == TINYGLTF_COMPONENT_TYPE_BYTE || indexType == TINYGLTF_COMPONENT_TYPE_SHORT)
        fail(sparsePlace + ".indices", "needs unsigned byte, short or int indices");
    const unsigned char* indices =
        span(a.sparse.indices.bufferView, std::size_t(std::max(a.sparse.indices.byteOffset, 0)),
             std::size_t(n) * indexSize, "indices", indexBytes);
    const unsigned char* values =
        span(a.sparse.values.bufferView, std::size_t(std::max(a.sparse.values.byteOffset, 0)),
             std::size_t(n) * elementSize, "values", valueBytes);
    for (int k = 0; k < n; ++k) {
        const std::uint32_t i = readIndex(indices + std::size_t(k) * indexSize, indexType);
        if (i >= a.count)
            fail(sparsePlace + ".indices", "index " + std::to_string(i) + " is past the " +
                                               std::to_string(a.count) + " elements");
        std::memcpy(&sparseCopy[i * elementSize], values + std::size_t(k) * elementSize,
                    elementSize);
    }
    out.buffer = -1;
    out.data = sparseCopy.data();
    out.stride = elementSize;
    return out;
}

std::size_t GltfAccessors::appendVec3(int index, const std::string& use, bool finite,
                                      std::vector<Vec3>& out) const {
    std::vector<unsigned char> copy;
    const Layout l = layout(index, TINYGLTF_TYPE_VEC3, {TINYGLTF_COMPONENT_TYPE_FLOAT}, use, copy);
    const std::size_t first = out.size();
    out.resize(first + l.count);
    if (l.zero()) return l.count;
    Vec3* to = out.data() + first;
    forEachElement(l, [&](std::size_t i, const unsigned char* p) {
        Vec3& v = to[i];
        std::memcpy(&v.x, p, 4), std::memcpy(&v.y, p + 4, 4), std::memcpy(&v.z, p + 8, 4);
        if (finite && !isFinite(v))
            fail(accessorPlace(index), "element " + std::to_string(i) + " of " + use +
                                           " is not finite (NaN or infinity)");
    });
    return l.count;
}

std::size_t GltfAccessors::appendVec4(int index, const std::string& use,
                                      std::vector<Vec4>& out) const {
    std::vector<unsigned char> copy;
    const Layout l = layout(index, TINYGLTF_TYPE_VEC4, {TINYGLTF_COMPONENT_TYPE_FLOAT}, use, copy);
    const std::size_t first = out.size();
    out.resize(first + l.count);
    if (l.zero()) return l.count;
    Vec4* to = out.data() + first;
    forEachElement(l, [&](std::size_t i, const unsigned char* p) {
        Vec4& v = to[i];
        std::memcpy(&v.x, p, 4), std::memcpy(&v.y, p + 4, 4), std::memcpy(&v.z, p + 8, 4);
        std::memcpy(&v.w, p + 12, 4);
        if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z) ||
            !std::isfinite(v.w))
            fail(accessorPlace(index), "element " + std::to_string(i) + " of " + use +
                                           " is not finite (NaN or infinity)");
    });
    return l.count;
}

GltfAccessors::Layout GltfAccessors::unitLayout(int index, int type, const std::string& use,
                                                std::vector<unsigned char>& sparseCopy) const {
    const Layout l = layout(index, type,
                            {TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE,
                             TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT},
                            use, sparseCopy);
    if (l.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT && !l.normalized)
        fail(accessorPlace(index), use + " of integer type must be normalized");
    return l;
}

std::size_t GltfAccessors::appendVec2(int index, const std::string& use,
                                      std::vector<Vec2>& out) const {
    std::vector<unsigned char> copy;
    const Layout l = unitLayout(index, TINYGLTF_TYPE_VEC2, use, copy);
    const std::size_t first = out.size();
    out.resize(first + l.count);
    if (l.zero()) return l.count;
    Vec2* to = out.data() + first;
    forEachElement(l, [&](std::size_t i, const unsigned char* p) {
        to[i] = {component(p, 0, l.componentType), component(p, 1, l.componentType)};
        if (!std::isfinite(to[i].x) || !std::isfinite(to[i].y))
            fail(accessorPlace(index), "element " + std::to_string(i) + " of " + use +
                                           " is not finite (NaN or infinity)");
    });
    return l.count;
}

std::size_t GltfAccessors::appendColor(int index, const std::string& use,
                                       std::vector<Vec4>& out) const {
    count(index, use);
    const int type = m_model.accessors[std::size_t(index)].type;
    if (type != TINYGLTF_TYPE_VEC3 && type != TINYGLTF_TYPE_VEC4)
        fail(accessorPlace(index),
             std::string("is ") + typeName(type) + ", but " + use + " needs VEC3 or VEC4");
    std::vector<unsigned char> copy;
    const Layout l = unitLayout(index, type, use, copy);
    const int channels = type == TINYGLTF_TYPE_VEC4 ? 4 : 3;
    const std::size_t first = out.size();
    out.resize(first + l.count, Vec4{0.0f, 0.0f, 0.0f, channels == 4 ? 0.0f : 1.0f});
    if (l.zero()) return l.count;
    Vec4* to = out.data() + first;
    forEachElement(l, [&](std::size_t i, const unsigned char* p) {
        float v[4] = {0.0f, 0.0f, 0.0f, 1.0f};
        for (int c = 0; c < channels; ++c) {
            v[c] = component(p, c, l.componentType);
            if (!std::isfinite(v[c]))
                fail(accessorPlace(index), "element " + std::to_string(i) + " of " + use +
                                               " is not finite (NaN or infinity)");
            // A reflectance: exporters' values past [0, 1] are clamped into it.
            v[c] = std::clamp(v[c], 0.0f, 1.0f);
        }
        to[i] = {v[0], v[1], v[2], v[3]};
    });
    return l.count;
}

std::size_t GltfAccessors::appendIndices(int index, const std::string& use, std::size_t vertices,
                                         std::uint32_t base,
                                         std::vector<std::uint32_t>& out) const {
    std::vector<unsigned char> copy;
    const Layout l =
        layout(index, TINYGLTF_TYPE_SCALAR,
               {TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT,
                TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT},
               use, copy);
    const std::size_t first = out.size();
    out.resize(first + l.count, base);
    if (l.zero()) return l.count;
    std::uint32_t* to = out.data() + first;
    forEachElement(l, [&](std::size_t i, const unsigned char* p) {
        const std::uint32_t v = readIndex(p, l.componentType);
        if (v >= vertices)
            fail(accessorPlace(index),
                 "index " + std::to_string(v) + " (element " + std::to_string(i) + " of " + use +
                     ") is past the vertex count, " + std::to_string(vertices));
        to[i] = base + v;
    });
    return l.count;
}

/// A triangle strip's or fan's indices as a triangle list (glTF 2.0 spec, 3.7.2.1: strip
/// triangle i is (i, i + 1 + i % 2, i + 2 − i % 2), fan triangle i is (i + 1, i + 2, 0)).
/// Triangles that repeat an index (a strip's restarts) are left out.
std::vector<std::uint32_t> unrollTriangles(const std::vector<std::uint32_t>& in, bool strip) {
    std::vector<std::uint32_t> out;
    if (in.size() < 3) return out;
    out.reserve(3 * (in.size() - 2));
    for (std::size_t i = 0; i + 2 < in.size(); ++i) {
        const std::uint32_t a = strip ? in[i] : in[i + 1];
        const std::uint32_t b = strip ? in[i + 1 + i % 2] : in[i + 2];
        const std::uint32_t c = strip ? in[i + 2 - i % 2] : in[0];
        if (a == b || b == c || a == c) continue;
        out.insert(out.end(), {a, b, c});
    }
    return out;
}

}  // namespace glint::render::detail

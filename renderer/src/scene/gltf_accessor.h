// Checked reading of glTF 2.0 accessors: every byte an accessor names must lie inside its buffer
// view and buffer, its type and component type must be what the attribute allows, and the values
// must be usable (finite positions, indices inside the vertex count). Errors name the asset file
// and the glTF place (`accessors[3]`, `meshes[0].primitives[1].indices`). Triangle strips' and
// fans' indices are unrolled into triangle lists here too.
#pragma once

#include <cstdint>
#include <filesystem>
#include <initializer_list>
#include <string>
#include <vector>

#include "scene/gltf_buffers.h"
#include "vecmath.h"

namespace tinygltf {
class Model;
}

namespace glint::render::detail {

/// Reads accessors of one parsed asset from its buffers (gltf_buffers.h), a megabyte at a time.
/// Each reader appends to an array the caller has sized, so that a mesh's arrays are allocated
/// once.
class GltfAccessors {
  public:
    GltfAccessors(const tinygltf::Model& model, const GltfBuffers& buffers,
                  std::filesystem::path file)
        : m_model(model), m_buffers(buffers), m_file(std::move(file)) {}

    /// Number of elements of accessor `index` (checked to exist); `use` names the referrer.
    std::size_t count(int index, const std::string& use) const;
    /// The number of elements of accessor `index` when it exists and every byte of them lies in
    /// its bufferView and buffer (or it has no bufferView), else 0: a count to reserve for,
    /// before the readers check the accessor and name what is wrong.
    std::size_t readableCount(int index) const;

    /// Appends a float VEC3 accessor to `out`; with `finite`, a NaN or infinite element is an
    /// error. Returns the number of elements appended.
    std::size_t appendVec3(int index, const std::string& use, bool finite,
                           std::vector<Vec3>& out) const;
    /// Appends a float VEC4 accessor (tangents).
    std::size_t appendVec4(int index, const std::string& use, std::vector<Vec4>& out) const;
    /// Appends a VEC2 accessor of floats or normalised unsigned bytes or shorts (texture
    /// coordinates).
    std::size_t appendVec2(int index, const std::string& use, std::vector<Vec2>& out) const;
    /// Appends a VEC3 or VEC4 accessor of floats or normalised unsigned bytes or shorts (vertex
    /// colours) as RGBA, alpha 1 for VEC3; values are clamped to [0, 1].
    std::size_t appendColor(int index, const std::string& use, std::vector<Vec4>& out) const;
    /// Appends a SCALAR accessor of unsigned bytes, shorts or ints (indices), each below
    /// `vertices`, plus `base`.
    std::size_t appendIndices(int index, const std::string& use, std::size_t vertices,
                              std::uint32_t base, std::vector<std::uint32_t>& out) const;

    /// Throws glint::Error(Format) naming the asset and `place`.
    [[noreturn]] void fail(const std::string& place, const std::string& what) const;

  private:
    /// Where accessor `index`'s elements lie, checked against its buffer view and buffer:
    /// the buffer and first byte, the stride between elements, their count; `type`
    /// (TINYGLTF_TYPE_*) and the allowed component types are checked too. A sparse accessor's
    /// substitutions are applied to `sparseCopy`, which then holds every element tightly packed.
    struct Layout {
        int buffer = -1;                      ///< the buffer holding the elements, or -1
        std::size_t offset = 0;               ///< where the first starts in it
        const unsigned char* data = nullptr;  ///< else the elements (a sparse copy)
        std::size_t stride = 0, count = 0, elementSize = 0;
        int componentType = 0;
        bool normalized = false;
        /// Neither in a buffer nor copied: every element is zero.
        bool zero() const { return buffer < 0 && !data; }
    };
    Layout layout(int index, int type, std::initializer_list<int> componentTypes,
                  const std::string& use, std::vector<unsigned char>& sparseCopy) const;
    /// layout() of values in [0, 1] as glTF stores texture coordinates and colours: floats, or
    /// unsigned bytes or shorts that must be normalized.
    Layout unitLayout(int index, int type, const std::string& use,
                      std::vector<unsigned char>& sparseCopy) const;
    /// Calls read(i, p) for every element i of `l` (not zero()) in order, p pointing at its
    /// bytes; a buffer is read a megabyte at a time.
    template <typename Read>
    void forEachElement(const Layout& l, Read&& read) const;

    const tinygltf::Model& m_model;
    const GltfBuffers& m_buffers;
    std::filesystem::path m_file;
};

/// "accessors[i]".
std::string accessorPlace(int index);

/// A triangle strip's (`strip`) or fan's indices as a triangle list (none for fewer than 3);
/// triangles that repeat an index (a strip's restarts) are left out.
std::vector<std::uint32_t> unrollTriangles(const std::vector<std::uint32_t>& in, bool strip);

}  // namespace glint::render::detail

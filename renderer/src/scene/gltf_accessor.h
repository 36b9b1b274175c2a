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

#include "vecmath.h"

namespace tinygltf {
class Model;
}

namespace glint::render::detail {

/// Reads accessors of one parsed asset.
class GltfAccessors {
  public:
    GltfAccessors(const tinygltf::Model& model, std::filesystem::path file)
        : m_model(model), m_file(std::move(file)) {}

    /// Number of elements of accessor `index` (checked to exist); `use` names the referrer.
    std::size_t count(int index, const std::string& use) const;
    /// A float VEC3 accessor; with `finite`, a NaN or infinite element is an error.
    std::vector<Vec3> vec3(int index, const std::string& use, bool finite) const;
    /// A float VEC4 accessor (tangents).
    std::vector<Vec4> vec4(int index, const std::string& use) const;
    /// A VEC2 accessor of floats or normalised unsigned bytes or shorts (texture coordinates).
    std::vector<Vec2> vec2(int index, const std::string& use) const;
    /// A VEC3 or VEC4 accessor of floats or normalised unsigned bytes or shorts (vertex
    /// colours) as RGBA, alpha 1 for VEC3; values are clamped to [0, 1].
    std::vector<Vec4> color(int index, const std::string& use) const;
    /// A SCALAR accessor of unsigned bytes, shorts or ints (indices), each below `vertices`.
    std::vector<std::uint32_t> indices(int index, const std::string& use,
                                       std::size_t vertices) const;

    /// Throws glint::Error(Format) naming the asset and `place`.
    [[noreturn]] void fail(const std::string& place, const std::string& what) const;

  private:
    /// Where accessor `index`'s elements lie, checked against its buffer view and buffer:
    /// the first byte, the stride between elements, their count; `type` (TINYGLTF_TYPE_*) and
    /// the allowed component types are checked too. A sparse accessor's substitutions are
    /// applied to `sparseCopy`, which then holds every element tightly packed.
    struct Layout {
        const unsigned char* data = nullptr;  ///< null: every element is zero
        std::size_t stride = 0, count = 0;
        int componentType = 0;
        bool normalized = false;
    };
    Layout layout(int index, int type, std::initializer_list<int> componentTypes,
                  const std::string& use, std::vector<unsigned char>& sparseCopy) const;
    /// layout() of values in [0, 1] as glTF stores texture coordinates and colours: floats, or
    /// unsigned bytes or shorts that must be normalized.
    Layout unitLayout(int index, int type, const std::string& use,
                      std::vector<unsigned char>& sparseCopy) const;

    const tinygltf::Model& m_model;
    std::filesystem::path m_file;
};

/// "accessors[i]".
std::string accessorPlace(int index);

/// A triangle strip's (`strip`) or fan's indices as a triangle list (none for fewer than 3);
/// triangles that repeat an index (a strip's restarts) are left out.
std::vector<std::uint32_t> unrollTriangles(const std::vector<std::uint32_t>& in, bool strip);

}  // namespace glint::render::detail

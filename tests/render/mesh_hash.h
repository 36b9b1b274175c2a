// A hash of a loaded scene's mesh arrays: what the reader tests (glTF buffers, OBJ) compare with
// the arrays an earlier reader gave.
#pragma once

#include <cstdint>
#include <vector>

#include "glint/render/scene.h"
#include "scene/scene_access.h"
#include "scene/scene_data.h"

namespace glint::render::test {

/// FNV-1a over an array's bytes and its length.
template <typename T>
void hashArrayInto(std::uint64_t& h, const std::vector<T>& v) {
    const auto* p = reinterpret_cast<const unsigned char*>(v.data());
    for (std::size_t i = 0; i < v.size() * sizeof(T); ++i) h = (h ^ p[i]) * 1099511628211ull;
    h = (h ^ v.size()) * 1099511628211ull;
}

/// A hash of every mesh array of a loaded scene, in order.
inline std::uint64_t meshArraysHash(const Scene& scene) {
    std::uint64_t h = 14695981039346656037ull;
    for (const detail::Mesh& m : detail::sceneData(scene).meshes) {
        hashArrayInto(h, m.positions), hashArrayInto(h, m.normals), hashArrayInto(h, m.tangents);
        hashArrayInto(h, m.uvs), hashArrayInto(h, m.uvs1), hashArrayInto(h, m.colors);
        hashArrayInto(h, m.indices), hashArrayInto(h, m.materials);
    }
    return h;
}

}  // namespace glint::render::test

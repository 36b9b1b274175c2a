// What a scene needs in memory besides the film, before its ray-tracing structures are built
// (docs/renderer.md, "Memory"): the meshes and images it holds since loading, the BVH the
// renderer will build over clusters or Embree's triangles, and the texture tile cache.
#include <algorithm>
#include <cstdint>
#include <vector>

#include "embree/embree_scene.h"
#include "glint/image/memory.h"
#include "glint/render/renderer.h"
#include "scene/load_memory.h"
#include "scene/scene_access.h"
#include "scene/scene_data.h"

namespace glint::render {

namespace {

/// Bytes of an image's floats.
std::uint64_t imageBytes(const Image& image) {
    return std::uint64_t(image.data().size()) * sizeof(float);
}

/// The images the scene holds, and (cacheBytes) the texels its tile cache may hold: every MIP
/// level of every tiled texture file as RGBA floats, at most `textureCacheMb` megabytes.
std::uint64_t heldImageBytes(const detail::SceneData& data, int textureCacheMb,
                             std::uint64_t& cacheBytes) {
    std::uint64_t held = 0, texels = 0;
    std::vector<bool> counted;
    for (const detail::Texture& t : data.textures) {
        held = saturatingAdd(held, saturatingAdd(imageBytes(t.image), t.levels.residentBytes()));
        if (!t.store || t.file < 0) continue;
        if (counted.size() <= std::size_t(t.file)) counted.resize(std::size_t(t.file) + 1, false);
        if (counted[std::size_t(t.file)]) continue;  // a file shared by several textures
        counted[std::size_t(t.file)] = true;
        for (const auto& [w, h] : t.store->levelSizes(t.file))
            texels = saturatingAdd(texels, std::uint64_t(w) * std::uint64_t(h));
    }
    const std::uint64_t cacheLimit = std::uint64_t(textureCacheMb) << 20;
    cacheBytes = std::min(saturatingMul(texels, 4 * sizeof(float)), cacheLimit);
    held = saturatingAdd(held, imageBytes(data.environment.source));
    return saturatingAdd(held, imageBytes(data.environment.image));
}

/// Bytes of the scene's mesh arrays and instances.
std::uint64_t meshBytes(const detail::SceneData& data) {
    std::uint64_t bytes = std::uint64_t(data.meshes.size()) * sizeof(detail::Mesh) +
                          std::uint64_t(data.instances.size()) * sizeof(detail::Instance);
    for (const detail::Mesh& mesh : data.meshes) bytes = saturatingAdd(bytes, mesh.bytes());
    return bytes;
}

}  // namespace

std::uint64_t detail::heldBytes(const detail::SceneData& data) {
    std::uint64_t cache = 0;
    return saturatingAdd(meshBytes(data), heldImageBytes(data, 0, cache));
}

std::uint64_t SceneMemory::held() const {
    return saturatingAdd(meshes, images);
}

std::uint64_t SceneMemory::added() const {
    return saturatingAdd(structures, textureCache);
}

std::uint64_t SceneMemory::total() const {
    return saturatingAdd(held(), added());
}

SceneMemory estimateSceneMemory(const Scene& scene, Accel accel, int textureCacheMb) {
    const detail::SceneData& data = detail::sceneData(scene);
    SceneMemory m;
    const bool clusters = EmbreeScene::buildsClusters(data, accel);
    m.accel = clusters ? Accel::Clusters : Accel::Triangles;
    m.meshes = meshBytes(data);
    m.images = heldImageBytes(data, textureCacheMb, m.textureCache);
    m.structures = EmbreeScene::estimateBytes(data, clusters);
    return m;
}

}  // namespace glint::render

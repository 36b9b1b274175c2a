// scene.json → SceneData. scene_loader.cpp reads the JSON (camera, film, render block,
// materials, environment, shapes and their transforms), builds the scene around a bare asset and
// reads textures and environment images; each asset format (asset_format.h, one registration
// line in asset_formats.cpp) imports its files through the loader's ImportContext.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <tuple>
#include <vector>

#include <nlohmann/json.hpp>

#include "glint/image/image.h"
#include "scene/asset_format.h"
#include "scene/json_reader.h"
#include "scene/scene_data.h"
#include "scene/transform.h"

namespace glint::render {
struct MaterialParameter;
}

namespace glint::render::detail {

/// Loads one scene file into a SceneData; textures are opened once per path (files through the
/// scene's TextureStore, embedded images decoded into memory). Asset formats see it as their
/// ImportContext only.
class Loader final : private ImportContext {
  public:
    /// With `memoryLimit` > 0, each asset is refused before it is read when the scene so far
    /// and the asset's predicted load peak exceed it (load_memory.h).
    Loader(const std::filesystem::path& file, SceneData& scene, std::uint64_t memoryLimit = 0);

    /// Reads the whole document.
    void load(const nlohmann::json& root);
    /// Builds a scene around the asset `file` of a registered format (a bare asset:
    /// loadScene("model.glb")): film 640 pixels wide, the asset's first camera or one framing its
    /// bounding sphere, a constant environment of radiance 1 when the asset has no light.
    /// Records an equivalent scene.json as the scene's source.
    void loadAsset(const std::filesystem::path& file);

  private:
    // ImportContext (asset_format.h), what an asset format's import uses.
    SceneData& scene() override { return m_scene; }
    const JsonReader& reader() const override { return m_reader; }
    int sceneMaterial(const nlohmann::json& value, const std::string& place) const override;
    int materialIndex(const std::string& name) const override {
        const auto it = m_materialIndex.find(name);
        return it == m_materialIndex.end() ? -1 : it->second;
    }
    int addMaterial(Material material) override;
    void applyLookEdits(Material& m, const nlohmann::json& edits,
                        const std::string& where) const override;
    int loadTexture(const Texture& source, const std::string& where) override;
    void placeMesh(std::uint32_t mesh, const AssetShape& shape) override;

    void readCamera(const nlohmann::json& j, const std::string& where);
    void readFilm(const nlohmann::json& j, const std::string& where);
    void readRender(const nlohmann::json& j, const std::string& where);
    Material readMaterial(const std::string& name, const nlohmann::json& j,
                          const std::string& where);
    void readEnvironment(const nlohmann::json& j, const std::string& where);
    TransformDesc readTransform(const nlohmann::json& j, const std::string& where,
                                const TransformDesc& base);
    /// Reads the shape /shapes/shapeIndex at JSON place `where`.
    void readShape(const nlohmann::json& j, const std::string& where, int shapeIndex);
    /// Reads parameter `p` of a material into `m` where the object `j` (at `where`) gives it.
    void readParameter(Material& m, const MaterialParameter& p, const nlohmann::json& j,
                       const std::string& where) const;
    /// The shape keys scene.json takes: every format's key, then the common and the formats'
    /// own keys, in the order the unknown-key message lists them.
    static std::vector<std::string> shapeKeys();
    /// Fails unless the asset of `format` at `shape.file` is a regular file whose predicted
    /// load fits the memory limit.
    void checkAsset(const AssetFormat& format, const AssetShape& shape) const;
    /// Sets the camera from SceneData::assetCameras[index] (film unchanged).
    void useAssetCamera(std::size_t index);

    /// Loads (or finds) the colour texture at `path` (relative to the scene folder), repeating;
    /// returns its index.
    int loadTexture(const std::filesystem::path& path, const std::string& where);
    /// Opens a texture file in the scene's TextureStore (made on first need), checking it as
    /// loadTexture promises; returns its index there.
    int openTextureFile(const std::filesystem::path& path, bool linearize,
                        const std::string& where);
    /// An RGB radiance in [0, kMaxRadiance].
    Vec3 radiance(const nlohmann::json& value, const std::string& where) const;

    JsonReader m_reader;
    SceneData& m_scene;
    std::filesystem::path m_dir;
    std::map<std::string, int> m_materialIndex;
    std::map<std::tuple<std::filesystem::path, int, int, int>, int> m_textureIndex;
    bool m_hasCamera = false;         ///< the document has a "camera" block
    std::uint64_t m_memoryLimit = 0;  ///< bytes the load may take (0: no limit)
};

/// Ends loading, after SceneData::finishMeshes: the bounding box of every vertex at shutter open
/// (SceneData::bounds) and the largest side of the box of every vertex in every pose
/// (SceneData::extent). What needs the scene's size reads them.
void computeBounds(SceneData& scene);

/// Reads an image file as linear RGB (grey replicated) multiplied by `scale`.
/// Every value must be finite and >= 0: otherwise glint::Error(Format) names the image, the
/// pixel, and the scene file and JSON place that referenced it (`what`: "texture",
/// "environment image").
Image readLinearRgb(const std::filesystem::path& image, float scale, const std::string& what,
                    const std::filesystem::path& sceneFile, const std::string& where);

/// An image as RGBA (grey replicated, alpha 1 where there is none), every value
/// finite and in [0, kMaxRadiance]; errors name `file` (the texture) and `where`.
Image textureRgba(const Image& raw, const std::string& what, const std::filesystem::path& file,
                  const std::string& where);

/// `source` × `scale` with the same checks as readLinearRgb (for look edits).
Image scaledRgb(const Image& source, float scale, const std::string& what,
                const std::filesystem::path& sceneFile, const std::string& where);

}  // namespace glint::render::detail

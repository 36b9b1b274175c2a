// scene.json → SceneData. One loader, three files by concern: scene_loader.cpp reads the JSON
// (camera, film, render block, materials, environment, shapes and their transforms),
// obj_import.cpp imports OBJ/MTL geometry through tinyobjloader, image_import.cpp reads textures
// and environment images.
#pragma once

#include <filesystem>
#include <map>
#include <tuple>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "glint/image/image.h"
#include "scene/json_reader.h"
#include "scene/scene_data.h"
#include "scene/transform.h"

namespace glint::render::detail {

/// Loads one scene file into a SceneData; textures are read once per path.
class Loader {
  public:
    Loader(const std::filesystem::path& file, SceneData& scene);

    /// Reads the whole document.
    void load(const nlohmann::json& root);

  private:
    void readCamera(const nlohmann::json& j, const std::string& where);
    void readFilm(const nlohmann::json& j, const std::string& where);
    void readRender(const nlohmann::json& j, const std::string& where);
    Material readMaterial(const std::string& name, const nlohmann::json& j,
                          const std::string& where);
    void readEnvironment(const nlohmann::json& j, const std::string& where);
    TransformDesc readTransform(const nlohmann::json& j, const std::string& where,
                                const TransformDesc& base);
    void readShape(const nlohmann::json& j, const std::string& where);

    /// obj_import.cpp: adds the OBJ file as one mesh in its object space and returns its index,
    /// adding its MTL materials unless JSON overrides them by name. Every vertex must stay within
    /// the coordinate range in each of `poses` (the shape's transform, or every time step of
    /// its motion). With `overrideMaterial` >= 0 the caller's instance replaces every material
    /// (the mesh's own are then 0).
    std::uint32_t importObj(const std::filesystem::path& objPath, const std::vector<Affine>& poses,
                            int overrideMaterial, const std::string& where);

    /// Loads (or finds) the colour texture at `path` (relative to the scene folder), repeating;
    /// returns its index.
    int loadTexture(const std::filesystem::path& path, const std::string& where);
    /// Loads (or finds) a texture from a file or embedded bytes; returns its index.
    int loadTexture(const Texture& source, const std::string& where);
    int materialIndex(const std::string& name) const {
        const auto it = m_materialIndex.find(name);
        return it == m_materialIndex.end() ? -1 : it->second;
    }
    int addMaterial(Material material);
    /// An RGB radiance in [0, kMaxRadiance].
    Vec3 radiance(const nlohmann::json& value, const std::string& where) const;

    JsonReader m_reader;
    SceneData& m_scene;
    std::filesystem::path m_dir;
    std::map<std::string, int> m_materialIndex;
    std::map<std::tuple<std::filesystem::path, int, int, int>, int> m_textureIndex;
};

/// The largest side of the bounding box of every vertex of every instance in every pose
/// (SceneData::extent).
void computeExtent(SceneData& scene);

/// image_import.cpp: reads an image file as linear RGB (grey replicated) multiplied by `scale`.
/// Every value must be finite and >= 0: otherwise glint::Error(Format) names the image, the
/// pixel, and the scene file and JSON place that referenced it (`what`: "texture",
/// "environment image").
Image readLinearRgb(const std::filesystem::path& image, float scale, const std::string& what,
                    const std::filesystem::path& sceneFile, const std::string& where);

/// image_import.cpp: an image as RGBA (grey replicated, alpha 1 where there is none), every value
/// finite and in [0, kMaxRadiance]; errors name `file` (the texture) and `where`.
Image textureRgba(const Image& raw, const std::string& what, const std::filesystem::path& file,
                  const std::string& where);

/// image_import.cpp: `source` × `scale` with the same checks as readLinearRgb (for look edits).
Image scaledRgb(const Image& source, float scale, const std::string& what,
                const std::filesystem::path& sceneFile, const std::string& where);

}  // namespace glint::render::detail

// scene.json → SceneData. One loader, three files by concern: scene_loader.cpp reads the JSON
// (camera, film, render block, materials, environment, shapes and their transforms),
// obj_import.cpp imports OBJ/MTL geometry through tinyobjloader, image_import.cpp reads textures
// and environment images.
#pragma once

#include <filesystem>
#include <map>
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
    void addMotion(const TransformDesc& start, const TransformDesc& end, std::size_t firstTriangle,
                   const std::vector<Vec3>& objectPositions, const std::vector<Vec3>& objectNormals,
                   const std::string& where);
    void readShape(const nlohmann::json& j, const std::string& where);

    /// obj_import.cpp: appends the triangles of the OBJ file (transformed by `xf`), adding its
    /// MTL materials unless JSON overrides them (or `overrideMaterial` >= 0 replaces them all).
    /// For a moving shape, fills the object-space positions and normals.
    void importObj(const std::filesystem::path& objPath, const Affine& xf, bool moving,
                   int overrideMaterial, const std::string& where,
                   std::vector<Vec3>& objectPositions, std::vector<Vec3>& objectNormals);

    /// Loads (or finds) the texture at `path` (relative to the scene folder); returns its index.
    int loadTexture(const std::filesystem::path& path, const std::string& where);
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
    std::map<std::filesystem::path, int> m_textureIndex;
    bool m_hasNormals = false, m_hasUvs = false;
};

/// image_import.cpp: reads an image file as linear RGB (grey replicated) multiplied by `scale`.
/// Every value must be finite and >= 0: otherwise glint::Error(Format) names the image, the
/// pixel, and the scene file and JSON place that referenced it (`what`: "texture",
/// "environment image").
Image readLinearRgb(const std::filesystem::path& image, float scale, const std::string& what,
                    const std::filesystem::path& sceneFile, const std::string& where);

/// image_import.cpp: `source` × `scale` with the same checks as readLinearRgb (for look edits).
Image scaledRgb(const Image& source, float scale, const std::string& what,
                const std::filesystem::path& sceneFile, const std::string& where);

}  // namespace glint::render::detail

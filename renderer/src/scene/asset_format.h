// What the loader asks of an asset format (OBJ/MTL, glTF), and the registry of them
// (asset_formats.cpp). A format is its own file, which defines its AssetFormat, plus one line in
// the registry; the loader, saveScene, the memory check and the public list
// (glint/render/asset_formats.h) read only what the format describes, never which one it is.
#pragma once

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "scene/load_memory.h"
#include "scene/transform.h"

namespace glint::render::detail {

class Loader;

/// One shape of scene.json (or the bare asset, as shape 0) as its format's import sees it.
struct AssetShape {
    const nlohmann::json& object;  ///< the shape's JSON object
    std::string where;             ///< its JSON place ("/shapes/2")
    int index = -1;                ///< its index in /shapes
    std::filesystem::path file;    ///< the asset, a regular file within the memory limit
    /// The shape's transform, or every time step of its motion; every vertex must stay within
    /// the coordinate range in each.
    std::vector<Affine> poses;
    bool moving = false;  ///< the shape moves during the shutter (poses has the steps)
    int material = -1;    ///< "material": the scene material replacing the asset's (-1: none)
};

/// An asset format: its names, extensions and entry points.
struct AssetFormat {
    std::string name;  ///< for users: "Wavefront OBJ"
    std::string key;   ///< a scene.json shape's key: "obj"
    /// What a shape's key names, in the message of a shape with none or two: "a Wavefront OBJ
    /// file".
    std::string shapeDescription;
    /// The file's name in requireRegularFile's messages ("OBJ" file 'x' not found) and what was
    /// expected there ("an OBJ file").
    std::string fileWord, expected;
    std::vector<std::string> extensions;  ///< lower case with the dot: ".obj"
    /// The shape keys beyond the common ones ("material", "transform", "motion") that a shape
    /// of this format takes, which the import reads from AssetShape::object.
    std::vector<std::string> shapeKeys;
    /// Why a shape of this format refuses another format's shape key (key → message); a key
    /// without one is refused in general words.
    std::vector<std::pair<std::string, std::string>> refusedKeys;
    /// Predicts the load's peak from what is cheap to read (load_memory.h), for the memory
    /// limit; called before import.
    LoadPrediction (*predictLoad)(const std::filesystem::path& file) = nullptr;
    /// Adds the asset to the loader's scene: meshes placed by instances, materials (unless
    /// AssetShape::material overrides them), cameras and lights.
    void (*import)(Loader& loader, const AssetShape& shape) = nullptr;
};

/// Every registered format, in the order messages and dialogs list them.
const std::vector<const AssetFormat*>& assetFormatRegistry();

/// The format whose extensions include `path`'s (in any case); null when none does.
const AssetFormat* findAssetFormat(const std::filesystem::path& path);

/// Test hook: registers `format` after the others for the guard's lifetime (not while a scene
/// loads on another thread).
class ScopedAssetFormat {
  public:
    explicit ScopedAssetFormat(const AssetFormat& format);
    ~ScopedAssetFormat();
    ScopedAssetFormat(const ScopedAssetFormat&) = delete;
    ScopedAssetFormat& operator=(const ScopedAssetFormat&) = delete;

  private:
    const AssetFormat* m_format;
};

}  // namespace glint::render::detail

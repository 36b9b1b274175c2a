// What the loader asks of an asset format (OBJ/MTL, glTF), what a format's import may ask of the
// loader (ImportContext), and the registry of formats (asset_formats.cpp). A format is its own
// files, which define its AssetFormat, plus one line in the registry; the loader, saveScene, the
// memory check and the public list (glint/render/asset_formats.h) read only what the format
// describes, never which one it is, and a format sees the loader only through ImportContext.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "scene/json_reader.h"
#include "scene/load_memory.h"
#include "scene/transform.h"

namespace glint::render::detail {

struct Material;
struct SceneData;
struct Texture;

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

/// What an asset format's import takes from the loader (scene_loader.cpp): the scene being
/// loaded, the scene file's reader, and the loader's tables of materials (by name, so that
/// scene.json's materials override an asset's) and textures (each file opened once).
class ImportContext {
  public:
    /// The scene being loaded (meshes, cameras, lights, warnings and inputs are added to it).
    virtual SceneData& scene() = 0;
    /// The reader of the scene file, whose fail() names the file and a JSON place.
    virtual const JsonReader& reader() const = 0;
    /// The scene material a JSON string at `place` names; fails when /materials lacks it.
    virtual int sceneMaterial(const nlohmann::json& value, const std::string& place) const = 0;
    /// The index of the scene material named `name`, or -1.
    virtual int materialIndex(const std::string& name) const = 0;
    /// Adds `material` to the scene under its name; returns its index.
    virtual int addMaterial(Material material) = 0;
    /// Applies look edits (the keys the look panel edits for the material's kind, as saveScene
    /// writes them into a shape's "edits", at JSON place `where`) over `material`'s values.
    virtual void applyLookEdits(Material& material, const nlohmann::json& edits,
                                const std::string& where) const = 0;
    /// Loads (or finds) a texture from a file or embedded bytes; returns its index.
    virtual int loadTexture(const Texture& source, const std::string& where) = 0;
    /// Places scene mesh `mesh` as one instance with the shape's poses and material (a moving
    /// shape must not be emissive); a mesh without triangles is not placed.
    virtual void placeMesh(std::uint32_t mesh, const AssetShape& shape) = 0;

  protected:
    ~ImportContext() = default;
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
    void (*import)(ImportContext& loader, const AssetShape& shape) = nullptr;
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

// One glTF 2.0 asset being imported into a scene (the glTF format's import, gltfAssetFormat): the
// parsed tinygltf model, the asset's file and buffers, the shape's overrides, and what has been
// converted so far (meshes, materials, textures), so that everything the asset shares stays
// shared. It reaches the loader through its ImportContext (asset_format.h) only.
// gltf_import.cpp reads the file, the node hierarchy, cameras and lights; gltf_mesh.cpp the
// meshes; gltf_material.cpp the materials and textures.
#pragma once

#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "scene/asset_format.h"
#include "scene/gltf_accessor.h"
#include "scene/gltf_buffers.h"
#include "scene/gltf_file.h"
#include "scene/load_memory.h"
#include "scene/scene_data.h"

namespace tinygltf {
class Model;
class Value;
}  // namespace tinygltf

namespace glint::render::detail {

/// Candela (lumen per steradian) and lux per W/sr and W/m²: the luminous efficacy Blender's
/// glTF importer converts punctual lights with.
inline constexpr double kLumensPerWatt = 683.0;

/// What a scene.json shape asks of the glTF asset it places.
struct GltfOverrides {
    int material = -1;  ///< "material": replaces every material of the asset (scene index)
    /// "materials": a glTF material name → the scene material that replaces it.
    std::map<std::string, int> byName;
    std::string byNamePlace;  ///< the JSON place of "materials" (for a name the asset lacks)
    /// "edits": a glTF material name → its look edits (albedo, metallic, roughness, ior,
    /// transmission, emission), as saveScene writes them; applied over the asset's values.
    std::map<std::string, nlohmann::json> edits;
    std::string editsPlace;  ///< the JSON place of "edits"
    int shape = -1;          ///< index of the shape in /shapes (-1: a bare asset)
};

/// Converts one parsed asset into scene meshes, materials, textures, cameras and lights.
class GltfImport {
  public:
    GltfImport(ImportContext& loader, const tinygltf::Model& model, const GltfBuffers& buffers,
               std::filesystem::path file, const GltfOverrides& overrides, std::string where);

    /// Places the default scene's nodes (or every root node) with each pose of `poses`.
    void importScene(const std::vector<Affine>& poses);

  private:
    // gltf_mesh.cpp
    /// The scene mesh of meshes[index] (converted on first use; -2: it has no triangles).
    int mesh(int index);

    // gltf_import.cpp
    void placeMesh(int node, int glintMesh, const std::vector<Affine>& poses);
    void addCamera(int node, const Affine& world);
    void addLight(int node, const Affine& world);
    void checkExtensions();

    // gltf_material.cpp
    /// The scene material of materials[index] (-1: the glTF default material).
    int material(int index);
    Material convertMaterial(int index);
    /// A texture slot from a textureInfo (index, texCoord, extensions) at `place`.
    TextureSlot textureSlot(int index, int texCoord,
                            const std::map<std::string, tinygltf::Value>& ext, TextureUse use,
                            const std::string& place);
    int texture(int index, TextureUse use, const std::string& place);

    /// Adds "FILE: text" to SceneData::warnings once.
    void warn(const std::string& text);
    /// warn(text) for the first use of `key` only (a text naming the first place of many).
    void warnOnce(const std::string& key, const std::string& text);
    [[noreturn]] void fail(const std::string& place, const std::string& what) const;
    std::string nodeName(int node) const;
    /// The name a shape's "edits" address materials[index] by: its name, else
    /// "materials[index]"; "glTF default" for the default material (index -1).
    std::string editName(int index) const;

    ImportContext& m_loader;
    SceneData& m_scene;
    const tinygltf::Model& m_model;
    const GltfBuffers& m_buffers;
    std::filesystem::path m_file;
    GltfOverrides m_overrides;
    std::string m_where;
    GltfAccessors m_accessors;
    std::vector<int> m_meshes;     ///< glTF mesh → scene mesh (-1: not yet, -2: none)
    std::vector<int> m_materials;  ///< glTF material → scene material (-1: not yet)
    int m_defaultMaterial = -1;
    std::map<std::pair<int, int>, int> m_textures;  ///< (glTF texture, use) → scene texture
    std::set<std::string> m_usedMaterialNames;      ///< glTF material names (for the overrides)
    std::size_t m_instances = 0;
    std::size_t m_skippedPrimitives = 0;  ///< points and lines primitives skipped
    std::set<std::string> m_warnedOnce;   ///< the keys warnOnce has warned for
};

/// The glTF format's predictLoad (gltf_load_memory.cpp): predicts the load of the .gltf or .glb at
/// `path` from its JSON (read a block at a time, never whole): meshes, primitives, nodes,
/// accessors, materials and every other object tinygltf makes, the JSON values both JSON documents
/// hold, the mesh arrays the primitives' accessors become (count × Glint's element size), and the
/// images (width × height from their PNG or JPEG headers). A file whose layout it cannot read
/// predicts 0: its reader says what is wrong.
LoadPrediction predictGltfLoad(const std::filesystem::path& path);

/// "%41" → "A": a glTF uri's percent escapes decoded.
std::string decodeUri(const std::string& uri);

}  // namespace glint::render::detail

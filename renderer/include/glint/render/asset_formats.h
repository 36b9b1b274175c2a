// The asset formats loadScene reads (Wavefront OBJ, glTF 2.0): their names and extensions, for
// the programs that list them (glint-render's help, the studio's open dialog and drag-and-drop).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace glint::render {

/// One asset format: loadScene reads a file of it as a bare asset, and a scene.json shape
/// places one with its key ({"obj": "model.obj"}).
struct AssetFormatInfo {
    std::string name;                     ///< for users: "Wavefront OBJ", "glTF 2.0"
    std::string key;                      ///< a scene.json shape's key: "obj", "gltf"
    std::vector<std::string> extensions;  ///< lower case with the dot: ".gltf", ".glb"
};

/// Every asset format, in the order messages and file dialogs list them.
std::vector<AssetFormatInfo> assetFormats();

/// The extensions of every asset format, in that order (".obj", ".gltf", ".glb").
std::vector<std::string> assetExtensions();

/// True when loadScene reads `path` as a bare asset: its extension, in any case, is an asset
/// format's.
bool isAssetFile(const std::filesystem::path& path);

}  // namespace glint::render

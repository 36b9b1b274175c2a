// The memory limit during loading (docs/renderer.md, "Memory"): before an OBJ or glTF reader
// parses an asset, the peak its load will reach is predicted from what is cheap to read — a
// streaming count of an OBJ's statements, a streaming scan of a glTF's JSON (JsonScan) and its
// images' headers — and an asset that would take the scene past the limit is refused before
// the reader allocates anything.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

namespace glint::render::detail {

struct SceneData;

/// What loading one asset will take at its peak, above what the program holds anyway: an upper
/// bound in practice (docs/research/mesh-memory.md has the measurements it was checked on).
struct LoadPrediction {
    std::uint64_t bytes = 0;   ///< the load's peak
    std::uint64_t meshes = 0;  ///< of which Glint's mesh arrays (held after loading)
    std::uint64_t images = 0;  ///< of which decoded images (held after loading)
    /// of which the reader's own: tinygltf's document and objects, or the OBJ text and
    /// tinyobjloader's arrays (released when the load ends)
    std::uint64_t reader = 0;
    std::string counted;  ///< what was counted, for messages ("1000 meshes, 1000 nodes, ...")
    /// What would make the load smaller, for the message refusing it (empty: nothing to say).
    std::string advice;
};

/// Predicts the load of the .gltf or .glb at `path` from its JSON (read a block at a time, never
/// whole): meshes, primitives, nodes, accessors, materials and every other object tinygltf
/// makes, the JSON values both JSON documents hold, the mesh arrays the primitives' accessors
/// become (count × Glint's element size), and the images (width × height from their PNG or JPEG
/// headers). A file whose layout it cannot read predicts 0: its reader says what is wrong.
LoadPrediction predictGltfLoad(const std::filesystem::path& path);

/// Predicts the load of the OBJ at `path` from one pass over its text (a block at a time)
/// counting its v, vt, vn and f statements and its face corners: the check's copy of the text,
/// tinyobjloader's arrays and the mesh they become.
LoadPrediction predictObjLoad(const std::filesystem::path& path);

/// The bytes a scene being loaded already holds (its meshes and images so far).
std::uint64_t heldBytes(const SceneData& scene);

/// Throws Error(OutOfMemory) when `held` bytes and the prediction exceed `limit` (0: no limit):
/// one line with the predicted peak and what it counts, the limit, and what would help; nothing
/// of the asset has been read then. The error names the asset as its file when it is the scene
/// (`sceneFile`, a bare asset), else the scene file and `where` (the shape's place) and the
/// asset in its text.
void checkLoadMemory(const LoadPrediction& prediction, std::uint64_t held, std::uint64_t limit,
                     const std::filesystem::path& asset, const std::filesystem::path& sceneFile,
                     const std::string& where);

}  // namespace glint::render::detail

// The memory limit during loading (docs/renderer.md, "Memory"): before an asset's reader parses
// it, the peak its load will reach is predicted by its format (AssetFormat::predictLoad, in the
// format's own files) from what is cheap to read, and an asset that would take the scene past
// the limit is refused before the reader allocates anything. Here: the prediction, the measures
// every format's prediction shares, and the check.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <vector>

#include "scene/scene_data.h"

namespace glint::render::detail {

/// What loading one asset will take at its peak, above what the program holds anyway: an upper
/// bound in practice (docs/lab/mesh-memory.md has the measurements it was checked on).
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

/// Glint's Mesh and Instance beside their arrays: the object, its name and the small arrays'
/// allocations (at least 32 bytes each under glibc).
inline constexpr std::uint64_t kMeshObjectBytes = sizeof(Mesh) + 8 * 32;
inline constexpr std::uint64_t kInstanceBytes = sizeof(Instance) + 32;
/// What glibc's heap keeps beyond the objects counted (its chunk headers, rounding and the
/// freed text it holds): measured as up to 12 % on the many-mesh assets; 20 % is kept.
inline constexpr double kHeapSlack = 1.2;
/// Bytes of the file read at a time by the predictions' passes.
inline constexpr std::size_t kPredictionBlock = std::size_t(1) << 20;

/// Reads `count` bytes of the file from `offset` a block at a time into `feed(std::string_view)`;
/// false when the file is shorter or cannot be read.
template <class Feed>
bool readBlocks(const std::filesystem::path& path, std::uint64_t offset, std::uint64_t count,
                Feed&& feed) {
    std::ifstream in(path, std::ios::binary);
    if (!in || !in.seekg(std::streamoff(offset))) return false;
    std::vector<char> block(std::size_t(std::min<std::uint64_t>(count, kPredictionBlock)));
    while (count > 0) {
        const std::size_t n = std::size_t(std::min<std::uint64_t>(count, block.size()));
        if (!in.read(block.data(), std::streamsize(n))) return false;
        feed(std::string_view(block.data(), n));
        count -= n;
    }
    return true;
}

/// "1 node", "3 nodes": a count in a prediction's message.
std::string plural(std::uint64_t n, const char* what);

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

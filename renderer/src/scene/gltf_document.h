// The JSON of a glTF document, checked before tinygltf reads it. tinygltf's readers of `extras`
// and extensions recurse once per level of nesting (30,000 levels overflow the stack), it
// reports a number JSON cannot hold without its place, and it reads some values the glTF 2.0
// specification does not allow as if they were absent or valid (a primitive mode of -1 as
// triangles, a translation of strings as none, an aspect ratio of 0 as none): those are refused
// here, each with its glTF place (`meshes[0].primitives[1].mode`).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string_view>

#include <nlohmann/json.hpp>

namespace glint::render::detail {

/// The deepest nesting of arrays and objects a glTF document may have: far above any real
/// asset (about 10), far below what overflows a reader's stack.
inline constexpr int kMaxGltfNesting = 256;

/// The camera aspect ratios (width / height) Glint accepts: a bare asset's film is 640 pixels
/// wide and 640 / aspectRatio high, so that the widest and tallest real formats (about 4:1) fit
/// and a mistyped ratio cannot ask for a film of gigabytes.
inline constexpr double kMinGltfAspectRatio = 0.1, kMaxGltfAspectRatio = 10.0;

/// Where a document's text lies: a .gltf's whole file, or a .glb's JSON chunk from byte
/// `chunkOffset` of the file.
struct GltfText {
    std::string_view text;
    bool binary = false;            ///< a .glb's JSON chunk
    std::uint64_t chunkOffset = 0;  ///< of the JSON chunk's first byte, in the file
    bool hasBin = false;            ///< a .glb with a BIN chunk of at least one byte
};

/// Refuses a document whose arrays and objects nest deeper than kMaxGltfNesting, found by one
/// pass over the text counting brackets outside strings (no recursion): one Error naming the
/// file, the line and column (of the JSON chunk for a .glb), the byte and the limit.
void checkGltfNesting(const GltfText& text, const std::filesystem::path& file);

/// The document parsed, with each data URI cut to its scheme ("data:") so that a large embedded
/// buffer or image is not copied. Malformed JSON, or a number JSON cannot hold (1e400), is an
/// Error with the line and column, as in scene.json.
nlohmann::json parseGltfDocument(const GltfText& text, const std::filesystem::path& file);

/// Refuses the values of `doc` that glTF 2.0 does not allow and tinygltf would read leniently:
/// extensionsRequired/extensionsUsed that are not arrays of strings; a buffer without a uri in a
/// .gltf, or the first buffer of a .glb without a BIN chunk; a bufferView byteStride outside
/// 4…252 or not a multiple of 4; an accessor whose byteOffset, or whose bufferView's byteOffset
/// plus its own, is not a multiple of its component size; a primitive mode outside 0…6; a node
/// translation, rotation, scale or matrix that is not an array of 3, 4, 3 or 16 numbers; a camera
/// aspectRatio outside [kMinGltfAspectRatio, kMaxGltfAspectRatio]; a material alphaCutoff below 0.
void checkGltfDocument(const nlohmann::json& doc, const GltfText& text,
                       const std::filesystem::path& file);

}  // namespace glint::render::detail

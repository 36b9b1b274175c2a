// Reading a glTF 2.0 file into a tinygltf model: a .gltf with its buffer files, or a .glb whose
// header and chunks are checked before tinygltf sees them. tinygltf parses the document; a .glb's
// BIN chunk and buffer files stay in their files, read by Glint piece by piece as the accessor
// readers need them (gltf_buffers.h), so that a large asset's buffers are never held whole.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace tinygltf {
class Model;
}  // namespace tinygltf

namespace glint::render::detail {

class GltfBuffers;

/// A .glb's header magic and the type of its binary chunk (glTF 2.0, 4.4).
inline constexpr std::uint32_t kGlbMagic = 0x46546C67;     // "glTF"
inline constexpr std::uint32_t kGlbChunkBin = 0x004E4942;  // "BIN\0"

/// The little-endian 32-bit number at `p` (a .glb's header and chunk fields).
inline std::uint32_t le32(const unsigned char* p) {
    return std::uint32_t(p[0]) | std::uint32_t(p[1]) << 8 | std::uint32_t(p[2]) << 16 |
           std::uint32_t(p[3]) << 24;
}

/// The glTF extensions Glint reads (docs/assets.md); any other in extensionsRequired is an
/// error, in extensionsUsed a warning.
inline constexpr const char* kReadGltfExtensions[] = {
    "KHR_texture_transform", "KHR_lights_punctual", "KHR_materials_emissive_strength",
    "KHR_materials_ior", "KHR_materials_transmission"};

/// The first entry of an asset's extensionsRequired that Glint does not read: its index and
/// the message naming it and the extensions Glint reads; nothing when every one is read.
std::optional<std::pair<std::size_t, std::string>> unreadRequiredExtension(
    const std::vector<std::string>& required);

/// Reads `path` into `model` and the bytes of its buffers into `buffers` (bound to `model`: keep
/// both while reading the asset). Throws glint::Error naming the file and the byte, chunk, JSON
/// line or glTF place (e.g. `buffers[0]`) of what is wrong: a missing or truncated file, a damaged
/// binary layout, malformed or too deeply nested JSON, values glTF 2.0 does not allow
/// (gltf_document.h), a buffer file that is missing, not a regular file or of the wrong size, a
/// glTF version other than 2.x. When tinygltf cannot read an asset that requires an extension Glint
/// does not read (a Draco- or meshopt-compressed mesh, whose accessors have no bufferView), the
/// error names that extension.
void readGltfFile(const std::filesystem::path& path, tinygltf::Model& model, GltfBuffers& buffers);

/// When `uri` is a `data:` URI that tinygltf left undecoded (not base64, or a media type other
/// than those it reads), what is wrong with it, naming the URI by its header only (the data of
/// a large one would fill the message); otherwise nothing.
std::optional<std::string> undecodedDataUri(const std::string& uri);

}  // namespace glint::render::detail

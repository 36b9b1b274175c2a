// Reading a glTF 2.0 file into a tinygltf model: a .gltf with its buffer files, or a .glb whose
// header and chunks are checked before tinygltf sees them. A .glb's BIN chunk is read once,
// straight into the buffer that holds it: a large asset is never held twice while loading.
#pragma once

#include <filesystem>
#include <optional>
#include <string>

namespace tinygltf {
class Model;
}  // namespace tinygltf

namespace glint::render::detail {

/// Reads `path` into `model`. Throws glint::Error naming the file and the byte, chunk, JSON line
/// or glTF place (e.g. `buffers[0]`) of what is wrong: a missing or truncated file, a damaged
/// binary layout, malformed JSON, a buffer file that is missing or of the wrong size, a glTF
/// version other than 2.x.
void readGltfFile(const std::filesystem::path& path, tinygltf::Model& model);

/// When `uri` is a `data:` URI that tinygltf left undecoded (not base64, or a media type other
/// than those it reads), what is wrong with it, naming the URI by its header only (the data of
/// a large one would fill the message); otherwise nothing.
std::optional<std::string> undecodedDataUri(const std::string& uri);

}  // namespace glint::render::detail

// The load's memory (load_memory.h): the measures every format's prediction shares and the check
// against the limit. Each format predicts its own load in its own files (predictLoad of its
// AssetFormat: gltf_load_memory.cpp, obj_load_memory.cpp); the rates are the sizes of the
// objects the readers make, checked against the peak resident size of loads of generated assets
// (docs/lab/mesh-memory.md, "The memory limit holds during loading").
#include "scene/load_memory.h"

#include <string>

#include "glint/image/error.h"
#include "glint/image/memory.h"

namespace glint::render::detail {

namespace fs = std::filesystem;

std::string plural(std::uint64_t n, const char* what) {
    return std::to_string(n) + " " + what + (n == 1 ? "" : "s");
}

void checkLoadMemory(const LoadPrediction& prediction, std::uint64_t held, std::uint64_t limit,
                     const fs::path& asset, const fs::path& sceneFile, const std::string& where) {
    const std::uint64_t need = saturatingAdd(held, prediction.bytes);
    if (limit == 0 || need <= limit) return;
    // A bare asset is named as the file; an asset of a scene.json by the shape's place.
    const bool bare = asset == sceneFile;
    std::string text = (bare ? std::string("loading it") : "loading " + asset.string()) +
                       " would take about " + formatBytes(prediction.bytes) +
                       " at its peak (predicted before reading it: " + prediction.counted + ")";
    if (held > 0) text += " on top of the " + formatBytes(held) + " the scene already holds";
    text += " but only " + formatBytes(limit) +
            " is allowed (memory limit); nothing of it was read. A limit of " + formatBytes(need) +
            " would load it";
    if (!prediction.advice.empty()) text += "; " + prediction.advice;
    throw Error(ErrorKind::OutOfMemory, text, sceneFile.string(), bare ? "" : where);
}

}  // namespace glint::render::detail

// What the studio knows of its reference besides the pixels (docs/studio.md, "Sessions"): one
// rendered in the studio by what it was rendered for (the scene, its look, its camera, the render
// settings and spp), one opened from a file by the file's path and content identity. A session
// file keeps it as view-state keys "reference/..." (a rendered reference's pixels as the side
// frame "reference"); the autosave journal keeps the same keys. No widgets here.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "glint/image/frame_buffers.h"
#include "glint/render/look.h"
#include "glint/render/settings.h"

namespace glint::studio {

struct ReferenceInfo {
    enum class Source { Rendered, File };
    Source source = Source::File;
    // Rendered: what it was rendered for.
    std::string scene;                   ///< the scene file, absolute
    std::vector<render::LookItem> look;  ///< the look as edited then
    std::string camera;                  ///< sceneCamera() of the scene then
    render::Settings settings;           ///< spp, seed, integrator, MIS, half buffers
    // File: what was read.
    std::string file;            ///< absolute path
    std::uint64_t identity = 0;  ///< denoise::hashFrame of the frame read
};

/// The session's side frame holding a rendered reference (reference.exr in the side folder).
inline constexpr const char* kReferenceFrame = "reference";

/// Adds the "reference/..." keys describing `info` to `state`.
void writeReferenceState(const ReferenceInfo& info, std::map<std::string, std::string>& state);

/// The reference `state`'s "reference/..." keys describe (nullopt: none, or an unknown source).
/// `look` is the scene's look now: the reference's values are read into its properties (one the
/// state lacks keeps the value of `look`).
std::optional<ReferenceInfo> readReferenceState(const std::map<std::string, std::string>& state,
                                                const std::vector<render::LookItem>& look);

/// The camera of the scene file `path` as compact JSON (its "camera" block), what a rendered
/// reference looked through; "" for an asset the loader frames (glTF, OBJ) or a file without a
/// readable camera.
std::string sceneCamera(const std::filesystem::path& path);

/// The content identity of a reference read from a file (denoise::hashFrame).
std::uint64_t referenceIdentity(const FrameBuffers& frame);

}  // namespace glint::studio

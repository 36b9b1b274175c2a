// What the studio knows of its reference besides the pixels (docs/studio.md, "Sessions"): one
// rendered in the studio by what it was rendered for (the scene, its look, its camera, the render
// settings and spp), one opened from a file by the file's path and content identity and the scene
// its glint:scene attribute names (glint-render's: the file's own look and camera). Whether it
// still fits what is open is referenceMismatch(). A session
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
    // File: what was read; `scene` is its glint:scene attribute ("" for another renderer's).
    std::string file;            ///< absolute path
    std::uint64_t identity = 0;  ///< denoise::hashFrame of the frame read
};

/// What is open now, to hold a reference against.
struct ReferenceTarget {
    std::string scene;                   ///< the scene file, absolute ("" for an EXR)
    std::vector<render::LookItem> look;  ///< the look as edited
    std::vector<render::LookItem>
        fileLook;        ///< the scene file's own look (what glint-render renders)
    std::string camera;  ///< sceneCamera() of the scene
};

/// Why a reference does not show what is open (the first that differs, in this order).
enum class ReferenceMismatch {
    None,     ///< the same scene, look and camera
    Scene,    ///< rendered from another scene file
    Look,     ///< the look was edited since (or differs from the file's, for a file's)
    Camera,   ///< another camera
    Unknown,  ///< a file without glint:scene: what it shows is not known
};

/// The same look: every item and property with the same value.
bool sameLook(const std::vector<render::LookItem>& a, const std::vector<render::LookItem>& b);

/// The same scene file: equal paths, or (for a relative path, as glint-render records the one it
/// was given) the absolute one ends with the relative one's components.
bool sameSceneFile(const std::string& a, const std::string& b);

/// Whether `reference` was rendered for `now`: a rendered one by its scene, look and camera; one
/// read from a file by its glint:scene and the scene file's own look (glint-render renders the
/// file as it is); Unknown for a file that names no scene.
ReferenceMismatch referenceMismatch(const ReferenceInfo& reference, const ReferenceTarget& now);

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

/// The seed a reference of a render with `seed` is rendered with: another one, so that its
/// samples are not the render's first ones (a reference sharing them agrees with the render more
/// than an independent one does, and the metrics flatter it: at equal spp it is the render).
/// Within glint-render's seed range (0 … 2^63 − 1).
std::uint64_t referenceSeed(std::uint64_t seed);

/// The content identity of a reference read from a file (denoise::hashFrame).
std::uint64_t referenceIdentity(const FrameBuffers& frame);

}  // namespace glint::studio

// Where the learned filter finds its weight files: a folder named by the environment, the
// installed copy beside the executable's prefix, or the source tree the library was built from.
#pragma once

#include <filesystem>
#include <string>

namespace glint::denoise::learned {

/// The weights folder, first of: `envDir` when not empty (GLINT_UNET_WEIGHTS_DIR); the installed
/// folder `executable`'s directory / `installedRelative` (e.g. ../share/glint/weights/oidn) when
/// it exists; `sourceDir` (denoise/weights/oidn of the source tree).
std::filesystem::path weightsDir(const std::string& envDir, const std::filesystem::path& executable,
                                 const std::filesystem::path& installedRelative,
                                 const std::filesystem::path& sourceDir);

/// weightsDir() for this process: GLINT_UNET_WEIGHTS_DIR, /proc/self/exe and the folders the
/// build configured.
std::filesystem::path weightsDir();

}  // namespace glint::denoise::learned

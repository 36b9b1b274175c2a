// Lookup of the unet weights folder (docs/learned.md, "Weights"): environment, installed copy,
// source tree, in that order.
#include "learned/weights_dir.h"

#include <cstdlib>
#include <system_error>

namespace glint::denoise::learned {

namespace fs = std::filesystem;

fs::path weightsDir(const std::string& envDir, const fs::path& executable,
                    const fs::path& installedRelative, const fs::path& sourceDir) {
    if (!envDir.empty()) return envDir;
    if (!executable.empty()) {
        std::error_code ec;
        const fs::path installed =
            (executable.parent_path() / installedRelative).lexically_normal();
        if (fs::is_directory(installed, ec)) return installed;
    }
    return sourceDir;
}

fs::path weightsDir() {
    const char* env = std::getenv("GLINT_UNET_WEIGHTS_DIR");
    std::error_code ec;
    const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    return weightsDir(env ? env : "", ec ? fs::path() : exe, GLINT_UNET_WEIGHTS_INSTALLED,
                      GLINT_UNET_WEIGHTS_DIR);
}

}  // namespace glint::denoise::learned

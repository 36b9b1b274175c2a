// The reference a lab bench measures a scene against: lab/references/<scene>.exr where the lab
// keeps a cleaner one than the scene's own, else scenes/<scene>/reference.exr. A scene's own
// reference serves the tests at the spp their bounds assume (cornell: 4,096 spp, whose own error,
// 4.5e-05 relMSE, is most of a denoised 15-s render's); lab/references/README.md says how each
// lab file was made.
#pragma once

#include <filesystem>
#include <string>

namespace glint::bench {

inline std::string labReference(const std::string& scene) {
    const std::filesystem::path root = GLINT_SOURCE_DIR;
    const std::filesystem::path lab = root / "lab/references" / (scene + ".exr");
    if (std::filesystem::exists(lab)) return lab.string();
    return (root / "scenes" / scene / "reference.exr").string();
}

}  // namespace glint::bench

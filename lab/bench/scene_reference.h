// The reference a lab bench measures a scene against: scenes/<scene>/reference.exr (its recipe
// and own error: scenes/README.md, docs/lab/references.md).
#pragma once

#include <filesystem>
#include <string>

namespace glint::bench {

inline std::string sceneReference(const std::string& scene) {
    const std::filesystem::path root = GLINT_SOURCE_DIR;
    return (root / "scenes" / scene / "reference.exr").string();
}

}  // namespace glint::bench

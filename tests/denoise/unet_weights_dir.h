// The weights folder of the learned filter unet in tests: the shipped one, and a scope that points
// GLINT_UNET_WEIGHTS_DIR at another (an empty or a corrupt folder, say).
#pragma once

#include <cstdlib>
#include <filesystem>

namespace glint::denoise::testing {

/// Sets GLINT_UNET_WEIGHTS_DIR for the scope.
class UNetWeightsDir {
  public:
    explicit UNetWeightsDir(const std::filesystem::path& dir) {
        setenv("GLINT_UNET_WEIGHTS_DIR", dir.c_str(), 1);
    }
    ~UNetWeightsDir() { unsetenv("GLINT_UNET_WEIGHTS_DIR"); }
    UNetWeightsDir(const UNetWeightsDir&) = delete;
    UNetWeightsDir& operator=(const UNetWeightsDir&) = delete;
};

/// The weights Glint ships (denoise/weights/oidn/).
inline std::filesystem::path shippedUNetWeights() {
    return std::filesystem::path(GLINT_SOURCE_DIR) / "denoise/weights/oidn";
}

}  // namespace glint::denoise::testing

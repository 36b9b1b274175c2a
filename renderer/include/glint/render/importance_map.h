// An importance map for adaptive sampling (Settings::importance): per-pixel weights from outside
// the renderer (a denoiser's error estimate, an artist's mask) that multiply each pixel's
// estimated error, so that the adaptive passes add samples where the weights are large.
#pragma once

#include <filesystem>
#include <string>

#include "glint/image/image.h"

namespace glint::render {

/// Reads an importance map from an image file (EXR or anything glint::readImage reads, not
/// linearised): its one channel, or the Rec. 709 luminance of its first three. Throws
/// glint::Error naming the file when it cannot be read.
Image readImportanceMap(const std::filesystem::path& path);

/// Throws glint::Error(InvalidArgument) naming `file` (and the first bad pixel) unless
/// `weights` is one channel of width × height finite weights ≥ 0, not all 0.
void checkImportanceMap(const Image& weights, int width, int height, const std::string& file = {});

}  // namespace glint::render

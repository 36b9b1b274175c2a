// Private to glint_image: the SSIM kernel behind glint::ssim and glint::ssimMap (metrics.cpp
// prepares its input: crop, non-finite values, display transform).
#pragma once

#include <cstddef>

#include "glint/image/image.h"

namespace glint::detail {

/// Radius of the SSIM Gaussian window: int(3.5 * 1.5 + 0.5) = 5, as scipy.ndimage truncates.
constexpr int kSsimRadius = 5;
/// Smallest width and height SSIM accepts: the 11-pixel window.
constexpr int kSsimMinSize = 2 * kSsimRadius + 1;

/// Two images as `channels` planes of width × height floats each (plane c starts at
/// c * width * height), values finite; width and height at least kSsimMinSize.
struct SsimPlanes {
    const float* image = nullptr;
    const float* reference = nullptr;
    int width = 0;
    int height = 0;
    int channels = 0;
};

/// Mean SSIM (Wang et al. 2004) over pixels at least kSsimRadius from every border, then over
/// channels. When `map` is non-null it receives a width × height × 1 image of the per-pixel
/// SSIM averaged over channels (border pixels included, computed with the mirrored extension).
double ssimPlanar(const SsimPlanes& planes, Image* map);

}  // namespace glint::detail

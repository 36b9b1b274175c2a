// Private to glint_image: the SSIM kernel behind glint::ssim and glint::ssimMap (metrics.cpp
// validates the request: shapes, crop, minimum size, exposure).
#pragma once

#include <cstddef>

#include "glint/image/image.h"

namespace glint::detail {

/// Radius of the SSIM Gaussian window: int(3.5 * 1.5 + 0.5) = 5, as scipy.ndimage truncates.
constexpr int kSsimRadius = 5;
/// Smallest width and height SSIM accepts: the 11-pixel window.
constexpr int kSsimMinSize = 2 * kSsimRadius + 1;

/// What to compare: `rect` of two images of the same shape (at least kSsimMinSize on each side,
/// inside both). Non-finite values count as 0; when `display`, every value v is replaced by
/// srgbEncode(clamp(v * scale, 0, 1)) first.
struct SsimRequest {
    const Image* image = nullptr;
    const Image* reference = nullptr;
    Rect rect;
    bool display = true;
    float scale = 1.0f;  ///< 2^exposure
};

struct SsimOutcome {
    double mean = 0.0;                ///< SSIM averaged as docs/metrics.md says
    std::size_t nonFinitePixels = 0;  ///< pixels of rect with a NaN/Inf in either image
};

/// Mean SSIM (Wang et al. 2004) over pixels at least kSsimRadius from every border of `rect`,
/// then over channels. When `map` is non-null it receives a rect-sized 1-channel image of the
/// per-pixel SSIM averaged over channels (border pixels included, from the mirrored extension).
SsimOutcome computeSsim(const SsimRequest& request, Image* map);

}  // namespace glint::detail

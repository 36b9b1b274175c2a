// The box mean of an image: each pixel's channels averaged over the (2r + 1)² window around it,
// the window cut at the frame's edge (docs/image.md). For small windows over maps (Keep
// Refining's provisional map); the automatic selection keeps its own tiled running sums
// (denoise/src/auto/box_averages.h), which progress, cancellation and its memory budget need.
#pragma once

#include "glint/image/image.h"

namespace glint {

/// Every channel of `image` averaged over the (2·radius + 1)² window around each pixel, cut at
/// the border (a pixel near the edge averages the pixels the window holds). Each window is summed
/// on its own in double, rows then columns (cost ∝ radius a pixel), so a NaN or Inf reaches only
/// the windows that hold it. radius 0 returns the image; a negative radius throws
/// glint::Error(InvalidArgument).
Image boxMean(const Image& image, int radius);

}  // namespace glint

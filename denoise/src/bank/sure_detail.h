// Internals of the auto composite (sure.cpp) that the tests check directly.
#pragma once

#include "glint/image/image.h"

namespace glint::denoise::detail {

/// Step 2's score of one candidate at one radius (docs/navigation.md, "Automatic start by
/// SURE"): the box average over (2·radius + 1)² pixels, truncated at the border, of
/// d = raw − base, each d rounded to float, plus `confidence` standard errors of that mean,
/// sqrt(max(0, mean of d² − mean²) / (2·radius + 1)²) (the full window's count). `raw` and
/// `base` are 1-channel maps of one size; the result is too. The same, value for value, as
/// boxSmooth of stored d and d² maps.
Image windowScore(const Image& raw, const Image& base, int radius, double confidence);

}  // namespace glint::denoise::detail

// Visual aids of the compositing session: where the bank disagrees, what a candidate would
// change, and a depth layer made readable (docs/painting.md, "Visual aids").
#pragma once

#include <optional>
#include <vector>

#include "glint/image/image.h"

namespace glint::denoise {

/// Filter-variance map: per pixel, the standard deviation across `results` (all the same size,
/// 3 channels) of the mean over channels, divided by its largest value so it lies in [0, 1]
/// (all 0 when the results agree everywhere). Non-finite values are left out. 1 channel.
Image filterVarianceMap(const std::vector<const Image*>& results);

/// Change map: |candidate − composite| averaged over channels, divided by its largest value
/// (in [0, 1]; all 0 when they are equal). 1 channel, of their (equal) size.
Image changeMap(const Image& candidate, const Image& composite);

/// Histogram equalisation of a 1-channel image (e.g. depth) to [0, 1]: each finite value
/// becomes the fraction of finite values at or below it; non-finite values become 0.
Image equalizeHistogram(const Image& values);

}  // namespace glint::denoise

// The bank's median per pixel and channel: the centre of the automatic
// selection's display linearisation (docs/auto.md, "The display transform and the bank's median").
#pragma once

#include <vector>

#include "glint/image/image.h"

namespace glint::denoise {
class FilterBank;
class WorkContext;
}  // namespace glint::denoise

namespace glint::denoise::detail {

/// The median of the bank's results per pixel and channel (3 channels, region-sized): a
/// member-independent estimate of the clean value, the centre of the display linearisation
/// (SureSpace::Display and DisplayTangent). The median rather than the mean, which the members
/// that barely filter pull into the clamp at a firefly or a highlight
/// (docs/lab/auto-notebook.md measures both). The (n/2)-th smallest of the n values (the
/// upper median for even n), found by a sorting network 8 values at a time. Throws
/// glint::Error(InvalidArgument) for a bank without members.
Image bankMedian(const FilterBank& bank);
/// bankMedian with its rows run through `work` (one unit each).
Image bankMedian(const FilterBank& bank, WorkContext& work);
/// The same median of `results` (at least one, all 3 channels and of one size), rows through
/// `work`: the bank's over a strip of rows for the pipeline's tiles (auto_composite.cpp).
Image medianOf(const std::vector<const Image*>& results, WorkContext& work);

}  // namespace glint::denoise::detail

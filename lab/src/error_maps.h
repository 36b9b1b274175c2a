// What the oracles share (oracle.cpp, expected_oracle.cpp): a member's per-pixel error against
// the reference, its box average, and the composite of a per-pixel pick. Private to lab/.
#pragma once

#include <vector>

#include "glint/image/image.h"

namespace glint::denoise {
class FilterBank;
}

namespace glint::lab::detail {

/// Per-pixel squared display error summed over channels, box-averaged over 3×3 (truncated at
/// the border), so the per-pixel choice is not driven by single-pixel noise.
std::vector<float> errorMap(const Image& display, const Image& referenceDisplay);

/// Composite over the bank's region taking each pixel from the member `pick` says.
Image pickComposite(const denoise::FilterBank& bank, const std::vector<int>& pick);

/// The mean over (2·radius + 1)² pixels, truncated at the border, of a 1-channel image: prefix
/// sums along rows, then running sums down columns, in double (the sums of the automatic
/// selection's box averages, term for term). radius 0 returns the image.
Image boxSmooth(const Image& image, int radius);

}  // namespace glint::lab::detail

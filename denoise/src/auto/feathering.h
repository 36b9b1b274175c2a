// The feathering of the automatic selection (docs/auto.md, "Feathering"): the final weight planes
// box-averaged so that the choice changes over a few pixels, gated where a member's display value
// is far from the composite's.
#pragma once

#include <vector>

#include "glint/image/image.h"

namespace glint::denoise {
class FilterBank;
class WorkContext;
}  // namespace glint::denoise

namespace glint::denoise::detail {

/// Each member's plane (the non-empty ones, those of the final candidates) box-averaged over
/// `radius`, zero where the member's display value is more than `gate` from the unfeathered
/// composite's in a channel, then renormalised per pixel; a pixel where every feathered weight
/// is 0 takes the member with the largest unfeathered weight alone. Rows and members through
/// `work`.
void featherWeights(std::vector<Image>& planes, const FilterBank& bank, int radius, double gate,
                    float exposure, WorkContext& work);

/// featherWeights's last step on row y: the planes of `used` become `feathered` (one per used
/// member, in that order) renormalised per pixel, or, where every feathered weight is 0, the
/// member with the largest weight in `planes` alone.
void renormaliseRow(std::vector<Image>& planes, const std::vector<std::size_t>& used,
                    const std::vector<Image>& feathered, int y);

}  // namespace glint::denoise::detail

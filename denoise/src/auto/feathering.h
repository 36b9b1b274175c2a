// The feathering of the automatic selection (docs/auto.md, "Feathering"): the final weight planes
// box-averaged so that the choice changes over a few pixels, gated where a member's display value
// is far from the composite's.
#pragma once

#include <vector>

#include "glint/image/image.h"

namespace glint::denoise {
class WorkContext;
}  // namespace glint::denoise

namespace glint::denoise::detail {

/// Feathering over rows [y0, y1) (one tile): each `used` member's `feathered` plane (its plane
/// in `planes` box-averaged over the feathering's radius, frame-sized) is set to zero where the
/// member's display value (`results`, per member, rows from y0 on; null: no weight in these
/// rows) is more than `gate` from the unfeathered composite's in a channel, then the planes are
/// renormalised per pixel (renormaliseRow). Rows through `work`.
void featherRows(std::vector<Image>& planes, const std::vector<std::size_t>& used,
                 std::vector<Image>& feathered, const std::vector<const Image*>& results, int y0,
                 int y1, double gate, float exposure, WorkContext& work);
/// featherRows's last step on row y: the planes of `used` become `feathered` (one per used
/// member, in that order) renormalised per pixel, or, where every feathered weight is 0, the
/// member with the largest weight in `planes` alone.
void renormaliseRow(std::vector<Image>& planes, const std::vector<std::size_t>& used,
                    const std::vector<Image>& feathered, int y);

}  // namespace glint::denoise::detail

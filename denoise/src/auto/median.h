// The bank's median per pixel and channel (bankMedian, sure.h): the centre of the automatic
// selection's display linearisation (docs/auto.md, "The display transform and the bank's median").
#pragma once

#include "glint/image/image.h"

namespace glint::denoise {
class FilterBank;
class WorkContext;
}  // namespace glint::denoise

namespace glint::denoise::detail {

/// bankMedian with its rows run through `work` (one unit each).
Image bankMedian(const FilterBank& bank, WorkContext& work);

}  // namespace glint::denoise::detail

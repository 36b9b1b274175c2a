// Auto's correction layer in the session's composite (SessionCorrection, docs/painting.md,
// "Auto's correction"): what it adds to the composite beneath it, and the checks of its images.
#pragma once

#include <string>

#include "glint/denoise/session.h"

namespace glint::denoise {

/// dst += w · (result − blend) over `rect` (in double, rounded once, clamped at 0), with w the
/// 1-channel `weight` clamped to [0, 1]: unchanged where w = 0 or result = blend, exactly
/// `result` where w = 1 and dst is `blend` (SessionCorrection).
void correctInPlace(Image& dst, const SessionCorrection& correction, const Image& weight,
                    const Rect& rect);

/// Empty when `correction` fits a width × height session (both images 3 channels of that size,
/// every value finite), else what is wrong, for an error to name.
std::string correctionProblem(const SessionCorrection& correction, int width, int height);

}  // namespace glint::denoise

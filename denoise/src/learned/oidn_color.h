// Open Image Denoise's HDR input and output processing (OIDN 2.x core/color.h and
// devices/cpu/cpu_autoexposure): the perceptually uniform (PU) transfer function and the
// autoexposure that scales the colour before it.
#pragma once

#include "glint/image/image.h"

namespace glint::denoise::learned {

/// PU transfer normalised so that 65504 (the largest half) maps to 1; computed in double.
double puForward(double y);
/// Inverse of puForward.
double puInverse(double x);

/// OIDN's autoexposure of an RGB image: key 0.18 over the geometric mean of the luminance of
/// bins of at most 16 × 16 pixels whose mean luminance exceeds 1e-8 (non-finite and negative
/// values read as 0, +Inf as FLT_MAX); 1 when no bin qualifies.
double autoexposure(const Image& color);

}  // namespace glint::denoise::learned

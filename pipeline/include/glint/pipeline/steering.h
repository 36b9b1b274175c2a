// From the automatic selection's estimated error of the denoised image to the renderer's
// importance map (docs/final-render.md, "Steering"): the error made relative in display values,
// its mean (the estimated relMSE a target is compared with) and the per-pixel weights that
// multiply the renderer's own error estimate in the adaptive passes.
#pragma once

#include "glint/image/image.h"

namespace glint::pipeline {

/// Per pixel, auto's estimated error (AutoResult::error: display MSE per channel, 1 channel)
/// relative to the denoised image's display values (`composite`, 3 channels, linear, of the
/// same size): error / (mean over channels of D(c)² + 0.01), D the display transform at
/// `exposure` stops (relMSE's form, in display values).
Image relativeError(const Image& error, const Image& composite, float exposure);

/// The mean of relativeError over the image: the denoised image's estimated relMSE in display
/// values (the error target's measure).
double estimatedRelMse(const Image& relative);

/// The importance weights for the next adaptive passes: scale · sqrt(relative / its mean),
/// each factor clamped to [1/8, 8] (a pixel the denoiser already gets right still takes a few
/// samples; one it gets wrong cannot take all of them). 1 channel, finite, > 0.
Image importanceFromError(const Image& relative, double scale);

}  // namespace glint::pipeline

// From the automatic selection's estimated error of the denoised image to the renderer's
// importance map (docs/final-render.md, "Steering"): the error made relative in display values,
// its mean (the estimated relMSE a target is compared with) and the per-pixel weights that
// multiply the renderer's own error estimate in the adaptive passes.
#pragma once

#include <memory>

#include "glint/image/frame_buffers.h"
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

/// `map` (the schedule's weights; null: 1 everywhere) with weight 0 at every pixel of `frame`
/// that has at least `ratio` times the mean samples of the pixels rendered (a render region's),
/// which the adaptive passes then leave closed; `map` itself when no pixel is there or ratio is
/// 0 (off). The noise
/// threshold's allocation gives a pixel samples ∝ the square of its relative spread, which puts
/// most of a long render into a few pixels of rare bright paths (a highlight's, a motion
/// streak's end); relMSE falls fastest with samples ∝ the spread itself. `capped`, when given,
/// says whether any pixel was.
std::shared_ptr<const Image> capSamples(std::shared_ptr<const Image> map, const FrameBuffers& frame,
                                        double ratio, bool* capped = nullptr);

}  // namespace glint::pipeline

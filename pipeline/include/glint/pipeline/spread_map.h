// The variance schedule's importance map: the next adaptive pass goes to the pixels where one
// more sample removes the most of the noisy image's relMSE (docs/final-render.md, "Steering").
#pragma once

#include <memory>

#include "glint/image/frame_buffers.h"
#include "glint/image/image.h"

namespace glint::pipeline {

/// A pixel's priority: its relative spread of a sample over its sample count, s_i / n_i, with
/// s_i² = σ_i² / (μ_i² + 0.01) (relMSE's form, mean over the channels) from half B's statistics
/// alone (halfColor, halfVariance, halfSampleCount), so that half A never steers and stays an
/// unbiased estimate. One more sample at pixel i lowers its relMSE by about s_i² / n_i²: giving
/// each pass to the largest priorities leads to n_i ∝ s_i, the allocation that minimises the
/// noisy image's relMSE for a given number of samples. A pixel with fewer than two samples in
/// half B has an infinite priority; one without spread, 0.
Image spreadPriority(const FrameBuffers& frame);

/// The map of the next adaptive pass: weight `open` (> 0) for the `share` of the pixels (in
/// (0, 1]) with the highest priority (spreadPriority) and those tied with the last of them,
/// 0 (the pixel takes no sample) for the others and for priority 0. `open` multiplies the
/// renderer's own error estimate, which it compares with its threshold: large enough, every
/// chosen pixel with an error takes the pass. The frame needs its half buffers.
std::shared_ptr<const Image> spreadMap(const FrameBuffers& frame, double share, float open);

}  // namespace glint::pipeline

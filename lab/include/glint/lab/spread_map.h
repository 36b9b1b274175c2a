// The spread map: an experiment of issue 49 (docs/lab/adaptive-dof.md, "Why adaptive loses
// on dof") — importance weights for the renderer's adaptive passes from the noisy frame alone.
// It did not hold on the reporting seeds, so glint-final does not use it; the lab's
// bench_adaptive_equal_time does.
#pragma once

#include "glint/image/frame_buffers.h"
#include "glint/image/image.h"

namespace glint::lab {
/// The importance weights that make the renderer's threshold spend samples as the noisy image's
/// relMSE is best served (docs/lab/adaptive-dof.md, "Why adaptive loses on dof"): a
/// threshold on the error stops pixel i at n_i ∝ a_i² (a_i its error estimate times √n, Cycles'
/// form, from `frame`'s colour, variance and sampleCount), while the allocation that minimises
/// Σ v_i / (n_i (μ_i² + 0.01)) is n_i ∝ s_i = √(v_i / (μ_i² + 0.01)) (v_i a sample's variance,
/// mean over channels; Cauchy–Schwarz). Weights scale · r_i / mean(r), r_i = √s_i / a_i, each
/// factor clamped to [1/8, 8], turn the first into the second; a pixel below two samples or
/// without noise weighs `scale`. 1 channel, finite, > 0.
Image importanceFromSpread(const FrameBuffers& frame, double scale);

}  // namespace glint::lab

// The image-only noise estimator of the automatic selection (docs/auto.md, "Error estimation
// without variance or halves"): the variance of each pixel's mean estimated from the colour and
// its features alone, for a render that wrote neither a variance layer nor half buffers.
#pragma once

#include <string>

#include "glint/denoise/progress.h"
#include "glint/image/frame_buffers.h"
#include "glint/image/image.h"

namespace glint::denoise::detail {

/// The estimator's settings (docs/auto.md, "Error estimation without variance or halves").
struct ImageNoiseOptions {
    /// Radius of the leave-one-out prediction: each pixel is predicted from the
    /// (2r + 1)² − 1 pixels around it whose features are like its own.
    int predictRadius = 2;
    /// Radius of the window whose normalised squared residuals give the local noise level.
    int window = 3;
    /// Feature distances at which a neighbour's weight falls to e^-1/2: the albedo's (per
    /// channel, in albedo units) and the normal's (unit vectors).
    double albedoSigma = 0.05;
    double normalSigma = 0.15;
    /// A neighbour counts in the local noise level when its feature weight is at least this.
    double gate = 0.5;
    /// Exponent of the brightness modulation: the noise level is estimated for
    /// residual² / m^alpha with m the pixel's predicted (smooth) value, then multiplied back by
    /// the pixel's own m^alpha (0: no modulation; 1: variance proportional to brightness).
    double alpha = 1.0;
    /// Scale the median's level by the frame's tail factor max(1, mean residual / mean level),
    /// so that heavy-tailed (firefly) noise is not under-read (false: the median's level).
    bool tail = true;
};

/// Throws glint::Error(Numeric) naming `file` and the first non-finite colour value unless the
/// estimator can read `frame` (non-finite albedo or normal values are ignored, as the filters
/// do: such a pixel is compared by its colour only).
void checkImageNoiseInput(const FrameBuffers& frame, const std::string& file = {});

/// The variance of the mean of each pixel and channel (3 channels, frame-sized) estimated from
/// the colour and, where the frame has them, the albedo and normal; any variance or half layer
/// is not read. Rows in parallel through `work` (one unit per row, three times).
Image estimateImageNoise(const FrameBuffers& frame, const ImageNoiseOptions& options,
                         WorkContext& work);

}  // namespace glint::denoise::detail

// Feature prefiltering: smooths albedo, normal and depth made noisy by motion blur or depth of
// field before the main filters use them, keeping the sharp edges of static objects.
#pragma once

#include "glint/image/frame_buffers.h"

namespace glint::denoise {

/// Parameters of the feature prefilter (documented in docs/denoise.md).
struct PrefilterParams {
    int radius = 3;             ///< half window in pixels
    double sigmaSpatial = 1.5;  ///< spatial Gaussian sigma in pixels
    /// Weight of a neighbour's difference relative to the two pixels' variances (how many
    /// standard deviations count as "different").
    double varianceScale = 1.0;
};

/// Returns a copy of `frame` whose Albedo, Normal and Depth layers (those present) are filtered
/// with a variance-aware filter; the layers keep their names, and their variance layers are
/// reduced accordingly. Throws glint::Error(InvalidArgument) for absurd parameters.
FrameBuffers prefilterFeatures(const FrameBuffers& frame, const PrefilterParams& params = {});

}  // namespace glint::denoise

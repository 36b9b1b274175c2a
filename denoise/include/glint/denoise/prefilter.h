// Feature prefiltering: smooths albedo, normal and depth made noisy by motion blur or depth of
// field before the main filters use them, keeping the sharp edges of static objects.
#pragma once

#include <vector>

#include "glint/denoise/filter.h"
#include "glint/denoise/progress.h"
#include "glint/image/frame_buffers.h"

namespace glint::denoise {

/// FrameMetadata::extra key set ("1") on a frame whose feature layers prefilterFeatures smoothed:
/// filters that treat noise-free features differently read it (unet's aux = auto).
inline constexpr const char* kFeaturesPrefilteredKey = "featuresPrefiltered";

/// The prefilter's parameters (radius, sigmaSpatial, varianceScale), described like a filter's
/// so that the CLI, the bank and the studio generate their controls from them (docs/denoise.md).
const std::vector<ParamSpec>& prefilterParams();

/// Returns a copy of `frame` whose Albedo, Normal and Depth layers (those present) are filtered
/// with a variance-aware filter; the layers keep their names, and their variance layers are
/// reduced accordingly, and the metadata marks them (kFeaturesPrefilteredKey). `params` are
/// resolved against prefilterParams() (missing names take their defaults; unknown or out-of-range
/// ones throw glint::Error(InvalidArgument)). `progress` may stop it (glint::Error(Cancelled)).
FrameBuffers prefilterFeatures(const FrameBuffers& frame, const ParamValues& params = {},
                               const ProgressFn& progress = {});

}  // namespace glint::denoise

// Private to image/: which EXR channels feed which FrameBuffers layer, for Glint's own names and
// the alias tables of other renderers (docs/image.md, "The layered EXR" and "Reading other
// renderers' EXRs").
#pragma once

#include <string>
#include <vector>

#include "glint/image/frame_buffers.h"

namespace glint::detail {

/// Where one layer of a frame comes from in a file.
struct LayerSource {
    Layer layer;
    std::vector<int> channels;  ///< file channel index of each layer channel
    /// pbrt-v4 Variance.* is the variance of one sample: divide by spp to get that of the mean.
    bool perSampleVariance = false;
};

/// The naming convention a file uses and how its channels map onto layers.
struct ChannelPlan {
    std::string source;  ///< "glint", "cycles", "pbrt" or "mitsuba"
    std::vector<LayerSource> layers;
    std::string normalSpace;    ///< what the convention's normals are in
    std::string depthKind;      ///< what the convention's depth measures
    std::string positionSpace;  ///< non-empty when positions are not in world space
};

/// Chooses the convention of a file from its channel names (and whether it carries glint:*
/// attributes) and maps its channels. Throws glint::Error(Format) naming `file` when R,G,B (or
/// the convention's colour channels) are missing or a layer is incomplete.
ChannelPlan planChannels(const std::vector<std::string>& names, bool hasGlintAttributes,
                         const std::string& file);

}  // namespace glint::detail

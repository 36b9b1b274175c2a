// What tells Navigate's previews apart (docs/studio.md, "Navigate"): each option labelled by
// what differs between the options shown together — the filter's display name where the filters
// differ, the parameters whose values differ where they are one filter's ("strength 0.2",
// "strength 0.8") — and how their images differ: which has the most detail, which is the
// smoothest, and whether they are near-identical. No widgets.
#pragma once

#include <QString>

#include <string>
#include <vector>

#include "glint/denoise/filter.h"
#include "glint/image/image.h"

namespace glint::studio {

/// One option shown: the filter and its (resolved) parameters.
struct OptionMember {
    std::string filter;
    denoise::ParamValues params;
};

/// Per option, the lines that set it apart from the others shown with it: its filter's display
/// name, then (among options of the same filter) the parameters whose values differ between
/// them, at most two, the widest spread first, each rounded to the fewest significant digits (2
/// or 3) that keep the values apart ("strength 0.2"); an option alone of its filter gets its
/// main parameter (choiceName's). Options of one filter with the same values say "same settings".
std::vector<QStringList> distinguishingLabels(const std::vector<OptionMember>& options);

/// One display name per member, no two alike (a choice map's legend): the layer name
/// ("Non-local means, strong"), followed, where members share it, by the parameters that differ
/// among them as distinguishingLabels words them ("Non-local means, strong (strength 0.8)"), and
/// by the member's number ("#12", from 1) where even those are alike.
QStringList distinctNames(const std::vector<OptionMember>& members);

/// Below this largest mean relative difference (of luminance) between two options' images,
/// the options are near-identical: no one can tell them apart at a glance.
inline constexpr double kNearIdentical = 0.01;

/// How the options' images differ (each the same size: the bank's results over the region).
struct OptionContrast {
    /// Per option: "most detail", "smoothest" or "" (the middle ones, or when the options'
    /// detail differs by less than 5 %).
    std::vector<QString> words;
    /// The largest mean relative difference of luminance between two options.
    double maxDifference = 0.0;
    /// maxDifference < kNearIdentical.
    bool nearIdentical = false;
};

/// The square window of side `side` (clamped to the images) where the options' images differ
/// most (the largest sum of the luminance variance across them), for thumbnails that show the
/// difference rather than the whole region scaled down; the whole image when it is no larger.
Rect mostDifferentWindow(const std::vector<const Image*>& images, int side);

/// Compares the options' images (read on a grid of at most 2^16 pixels, so it costs little on
/// the UI thread): detail is the mean luminance gradient relative to the mean luminance.
OptionContrast contrastOf(const std::vector<const Image*>& images);

}  // namespace glint::studio

// A layer's name as the studio shows it ("NL-means, strong", "Cross-bilateral, σs 4") and its
// full parameters for a tooltip, from the filter's registry name and its ParamSpecs. No widgets.
#pragma once

#include <QString>

#include <string>

#include "glint/denoise/filter.h"

namespace glint::studio {

/// A readable name: the filter's title and its main parameter ("Gaussian, σ 2").
QString layerName(const std::string& filter, const denoise::ParamValues& params);

/// Every parameter with its label, one a line ("spatial sigma (px): 4"), under the registry
/// name.
QString layerParameters(const std::string& filter, const denoise::ParamValues& params);

}  // namespace glint::studio

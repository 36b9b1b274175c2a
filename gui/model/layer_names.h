// How the studio names filters, everywhere it shows one (the Tune menu, Navigate's previews and
// choice, the palette, undo texts): the filter's display name ("Non-local means"), a layer's
// name ("Non-local means, strong", "Cross-bilateral, σs 4"), a chosen member in user terms
// ("Non-local means, strength 0.44") and its full parameters for a tooltip, from the filter's
// registry name and its ParamSpecs. No widgets.
#pragma once

#include <QString>

#include <string>

#include "glint/denoise/filter.h"

namespace glint::studio {

/// The filter's display name ("Non-local means" for "nlmeans"): the one name the studio shows
/// for a filter; an unknown one is its registry name capitalised.
QString filterTitle(const std::string& filter);

/// A parameter's label without its unit or symbol ("spatial sigma (px)" -> "spatial sigma",
/// "strength k" -> "strength").
QString shortParamLabel(const denoise::ParamSpec& spec);

/// A value as the studio shows it: a choice by its option's name, an integer whole, a real
/// rounded to `digits` significant digits ("0.44").
QString paramValueText(const denoise::ParamSpec& spec, double value, int digits = 2);

/// A filter choice in user terms: the display name and its main parameter rounded
/// ("Non-local means, strength 0.44", "Learned (unet), balanced").
QString choiceName(const std::string& filter, const denoise::ParamValues& params);

/// A readable name: the filter's title and its main parameter ("Gaussian, σ 2").
QString layerName(const std::string& filter, const denoise::ParamValues& params);

/// Every parameter with its label, one a line ("spatial sigma (px): 4"), under the registry
/// name.
QString layerParameters(const std::string& filter, const denoise::ParamValues& params);

}  // namespace glint::studio

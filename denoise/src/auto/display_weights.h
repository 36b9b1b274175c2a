// The display linearisation of the automatic selection (docs/auto.md, "The display transform and
// the bank's median"): the weights that turn radiance errors into display errors around the
// bank's median m.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "glint/image/display_curve.h"
#include "glint/image/image.h"

namespace glint::denoise {
class WorkContext;
}

namespace glint::denoise::detail {

/// Per-pixel weights of SureSpace::DisplayTangent (and of Display for SURE): the squared display
/// slope at `median` (3 channels), floored at 1e-4 of the largest so saturated pixels still order
/// the members.
Image tangentWeights(const Image& median, float exposure);

/// Squared secant slope of the display transform between linear values f and m (the squared
/// slope at m where they nearly agree); `displayM` is D(m).
inline double secantWeight(double f, double m, double displayM, const DisplayCurve& display,
                           float exposure) {
    const double d = f - m;
    const double s = std::fabs(d) <= 1e-6 * std::max(1.0, std::fabs(m))
                         ? displaySlope(m, exposure)
                         : (display(f) - displayM) / d;
    return s * s;
}

/// D(m) of `centre` (3 channels), per pixel and channel in row order, in double (computed once
/// for all the members' maps). `work`, if given, runs the rows and counts one unit each.
std::vector<double> displayOf(const Image& centre, float exposure, WorkContext* work = nullptr);

}  // namespace glint::denoise::detail

// bilateral — exact brute-force bilateral filter of the colour (Tomasi & Manduchi 1998).
//
//   out(p) = sum_q w(p, q) c(q) / sum_q w(p, q),
//   w(p, q) = exp(-|p - q|^2 / (2 sigmaS^2)) * exp(-|c(p) - c(q)|^2 / (2 sigmaR^2)),
//
// over every pixel q of the square (2r+1)^2 window around p (no subsampling, and not OpenCV's
// disc, so sigmaR -> inf gives gaussian exactly); |c(p) - c(q)| is the Euclidean RGB distance.
// The window is truncated at the image border. Weights are 2^(s + k |c(p) - c(q)|^2) with the
// log2(e) / (2 sigma^2) factors folded into s and k (bilateral_kernel.h has the numerics for
// radiance 1e-30 … 1e30 and sigma 1e-6 … 1e6). Missing (NaN/Inf) neighbours get zero weight; a
// missing centre drops the range term (spatial average of its finite neighbours). Since
// w(p, q) = w(q, p), each pair's weight is computed once and added to both pixels, inside row
// bands fixed in image coordinates (bilateral_symmetric.cpp), so the result is the same for any
// thread count. Vectorised over 8 pixels along a row, TBB-parallel over bands.
//
// Parameters:
//   sigmaS  spatial standard deviation (px), 1e-6 … 1e6 (log)
//   sigmaR  range standard deviation (radiance units), 1e-6 … 1e6 (log); -> inf gives gaussian
//   radius  window radius, 0 … 100; 0 = ceil(3 sigmaS) (at most 100); OpenCV's d = 2 radius + 1
#include "filters/bilateral.h"

#include <algorithm>
#include <cmath>

#include "filters/bilateral_kernel.h"
#include "filters/factories.h"
#include "filters/filter_util.h"

namespace glint::denoise {

namespace {

constexpr std::string_view kDescription =
    "bilateral: exact brute-force bilateral filter (Tomasi & Manduchi 1998) over the square "
    "(2r+1)^2 window; weight = spatial Gaussian(sigmaS) x range Gaussian(sigmaR) of the RGB "
    "distance. radius 0 means ceil(3 sigmaS); d = 31 is radius 15.";

}  // namespace

int bilateralRadius(double sigmaS, int radiusParam) {
    if (radiusParam > 0) return std::min(radiusParam, kBilateralMaxRadius);
    const double r = std::ceil(3.0 * std::max(sigmaS, 0.0));
    return int(std::clamp(r, 1.0, double(kBilateralMaxRadius)));
}

std::vector<ParamSpec> bilateralParamSpecs() {
    return {
        ParamSpec{"sigmaS", "spatial sigma (px)", 1e-6, 1e6, 3.0, ParamScale::Log, false,
                  "Standard deviation of the spatial Gaussian in pixels."}
            .soft(0.5, 6.0),
        ParamSpec{"sigmaR", "range sigma", 1e-6, 1e6, 0.1, ParamScale::Log, false,
                  "Standard deviation of the range Gaussian on the RGB distance (radiance "
                  "units)."}
            .soft(0.01, 2.0),
        ParamSpec{"radius", "window radius (px)", 0, kBilateralMaxRadius, 0, ParamScale::Linear,
                  true, "Half width of the square window; 0 derives it from sigmaS as ceil(3 "
                  "sigmaS)."}
            .soft(0, 0),
    };
}

BilateralFilter::BilateralFilter() : m_params(bilateralParamSpecs()) {}

std::string_view BilateralFilter::description() const {
    return kDescription;
}

int BilateralFilter::margin(const ParamValues& params) const {
    return bilateralRadius(detail::paramValue(params, "sigmaS"),
                           detail::paramInt(params, "radius"));
}

Image BilateralFilter::apply(const FrameBuffers& frame, const ParamValues& params, const Rect& roi,
                             WorkContext& work) const {
    const int radius = margin(params);
    return detail::bilateralExact(frame.color(), roi, radius, detail::paramValue(params, "sigmaS"),
                                  detail::paramValue(params, "sigmaR"), work);
}

std::unique_ptr<Filter> makeBilateralFilter() {
    return std::make_unique<BilateralFilter>();
}

}  // namespace glint::denoise

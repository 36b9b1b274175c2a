// The error estimators of the automatic selection (docs/auto.md, "Error estimation by SURE" and
// "… by cross-validation on the halves") behind one interface, and the estimates the pipeline
// (auto_composite.cpp) keeps of every member.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "glint/denoise/progress.h"
#include "glint/image/image.h"

namespace glint::denoise::detail {

/// "pixel (x, y)", the place an input error names.
std::string pixelText(int x, int y);

/// An error map's value, summed in double, stored as the nearest float: an error too large for a
/// float (a value of 1e32 squares to 1e64) is the largest one, not an infinity the blend and
/// glint-final's steering would have to refuse.
inline float storedError(double s) {
    constexpr double kMax = double(std::numeric_limits<float>::max());
    return float(std::clamp(s, -kMax, kMax));
}

/// The mean of a 1-channel map summed over RGB, per channel: rows summed in order.
double meanPerChannel(const Image& map);

/// One member's estimate: its per-pixel error map over the bank's region (1 channel, summed over
/// RGB) and what the pipeline reports besides.
struct MemberEstimate {
    Image map;
    /// The mean of the unbiased form where the map is not it (the secant's centred map).
    std::optional<double> unbiasedMean;
    bool analytic = false;  ///< SURE: the filter gave its divergence
};

/// A per-pixel error estimate of the bank's members, made without a reference.
class ErrorEstimator {
  public:
    virtual ~ErrorEstimator() = default;
    /// Member `member`'s error map. `going` is the running filters' progress: it returns false
    /// once the operation is cancelled (the filter then throws Error(Cancelled)).
    virtual MemberEstimate estimate(std::size_t member, const ProgressFn& going) = 0;
    /// The variance of the mean of the input at frame pixel (x, y), channel c: the unit of the
    /// soft weights' temperature.
    virtual double noiseVariance(int x, int y, int c) const = 0;
};

/// Every member's estimate (the error estimation stage's result), by member.
struct Estimates {
    std::vector<Image> maps;
    /// When set, the maps are not held (`maps` is empty; the pipeline keeps them in a spill
    /// file): rows [y0, y1) of member m's map, 1 channel, `width` wide.
    std::function<Image(std::size_t m, int y0, int y1)> mapRows;
    int width = 0, height = 0;  ///< the maps' size
    /// The mean of each map per pixel and channel: the choice's baseline is the smallest.
    std::vector<double> mapMean;
    /// The estimate of each member's mean squared error (mapMean but for the secant's centred
    /// maps, whose unbiased mean it is).
    std::vector<double> estimatedMse;
    std::vector<char> analytic;
};

}  // namespace glint::denoise::detail

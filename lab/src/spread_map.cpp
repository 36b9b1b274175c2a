#include "glint/lab/spread_map.h"

#include <algorithm>
#include <cmath>

#include "glint/image/error.h"

namespace glint::lab {

namespace {

// relMSE's floor in its denominator (μ² + 0.01), and the weights' range [1/8, 8] — the same as
// the product's steering map (pipeline/src/steering.cpp), so the two are compared alike.
constexpr double kRelativeFloor = 0.01;
constexpr double kWeightRange = 8.0;

}  // namespace

Image importanceFromSpread(const FrameBuffers& frame, double scale) {
    GLINT_CHECK(std::isfinite(scale) && scale > 0.0, "a positive scale");
    const Image& mean = frame.color();
    const Image& variance = frame.layer(Layer::Variance);
    const Image& count = frame.layer(Layer::SampleCount);
    Image weights(frame.width(), frame.height(), 1);
    // Per pixel r = √s / a (0: no estimate), then its mean over the pixels that have one.
    double sum = 0.0;
    std::size_t counted = 0;
    for (int y = 0; y < frame.height(); ++y)
        for (int x = 0; x < frame.width(); ++x) {
            const double n = double(count(x, y, 0));
            double spread = 0.0, error = 0.0, intensity = 0.0;
            for (int c = 0; c < 3; ++c) {
                // A sample's variance: the variance of the mean times n.
                const double v = std::max(double(variance(x, y, c)), 0.0) * n;
                const double m = double(mean(x, y, c));
                spread += v / (m * m + kRelativeFloor);
                error += std::sqrt(v);
                intensity += m;
            }
            // Film::adaptiveError's form (its constant √(2/π) cancels in the ratio).
            error /= 1e-4 + std::sqrt(std::max(intensity, 0.0));
            const double r =
                n >= 2.0 && error > 0.0 ? std::sqrt(std::sqrt(spread / 3.0)) / error : 0.0;
            weights(x, y, 0) = float(r);
            if (r > 0.0 && std::isfinite(r)) sum += r, ++counted;
        }
    const double average = counted > 0 ? sum / double(counted) : 0.0;
    for (float& w : weights.data()) {
        const double ratio =
            average > 0.0 && w > 0.0 && std::isfinite(w) ? double(w) / average : 1.0;
        w = float(scale * std::clamp(ratio, 1.0 / kWeightRange, kWeightRange));
    }
    return weights;
}

}  // namespace glint::lab

#include "glint/pipeline/steering.h"

#include <algorithm>
#include <cmath>

#include "glint/image/display_curve.h"
#include "glint/image/error.h"

namespace glint::pipeline {

namespace {
/// relMSE's floor of the reference's square (glint::relMse), here of display values.
constexpr double kRelativeFloor = 0.01;
/// The most a pixel's weight moves from the schedule's scale, either way.
constexpr double kWeightRange = 8.0;
}  // namespace

Image relativeError(const Image& error, const Image& composite, float exposure) {
    GLINT_CHECK(error.channels() == 1 && composite.channels() == 3 &&
                    error.width() == composite.width() && error.height() == composite.height(),
                "an error map and the composite it estimates, of one size");
    const DisplayCurve display(std::exp2(double(exposure)));
    Image relative(error.width(), error.height(), 1);
    for (int y = 0; y < error.height(); ++y)
        for (int x = 0; x < error.width(); ++x) {
            double square = 0.0;
            for (int c = 0; c < 3; ++c) {
                const double d = display(double(composite(x, y, c)));
                square += d * d;
            }
            relative(x, y, 0) = float(double(error(x, y, 0)) / (square / 3.0 + kRelativeFloor));
        }
    return relative;
}

double estimatedRelMse(const Image& relative) {
    double sum = 0.0;
    for (float v : relative.data()) sum += double(v);
    return relative.empty() ? 0.0 : sum / double(relative.pixelCount());
}

Image importanceFromError(const Image& relative, double scale) {
    GLINT_CHECK(relative.channels() == 1 && std::isfinite(scale) && scale > 0.0,
                "a relative error map and a positive scale");
    const double mean = estimatedRelMse(relative);
    Image weights(relative.width(), relative.height(), 1);
    for (std::size_t i = 0; i < relative.data().size(); ++i) {
        // An image the denoiser gets right everywhere (mean 0): the schedule alone.
        const double ratio = mean > 0.0 ? std::sqrt(double(relative.data()[i]) / mean) : 1.0;
        weights.data()[i] = float(scale * std::clamp(ratio, 1.0 / kWeightRange, kWeightRange));
    }
    return weights;
}

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

}  // namespace glint::pipeline

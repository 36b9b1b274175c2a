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

std::shared_ptr<const Image> capSamples(std::shared_ptr<const Image> map, const FrameBuffers& frame,
                                        double ratio, bool* capped) {
    if (capped) *capped = false;
    if (!(ratio > 0.0)) return map;
    // The mean over the pixels rendered (outside a render region they have none).
    const Image& count = frame.layer(Layer::SampleCount);
    double sum = 0.0;
    std::size_t rendered = 0;
    for (float n : count.data())
        if (n > 0.0f) {
            sum += double(n);
            ++rendered;
        }
    if (rendered == 0) return map;
    const double cap = ratio * sum / double(rendered);
    std::shared_ptr<Image> out;
    for (int y = 0; y < count.height(); ++y)
        for (int x = 0; x < count.width(); ++x) {
            if (double(count(x, y, 0)) < cap) continue;
            if (!out) {
                out = map ? std::make_shared<Image>(*map)
                          : std::make_shared<Image>(count.width(), count.height(), 1, 1.0f);
                GLINT_CHECK(out->width() == count.width() && out->height() == count.height(),
                            "an importance map of the frame's size");
            }
            for (int c = 0; c < out->channels(); ++c) (*out)(x, y, c) = 0.0f;
        }
    if (!out) return map;
    if (capped) *capped = true;
    return out;
}

}  // namespace glint::pipeline

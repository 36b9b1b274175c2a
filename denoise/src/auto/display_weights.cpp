// The display linearisation of the automatic selection (display_weights.h).
#include "display_weights.h"

#include <limits>

#include "glint/denoise/progress.h"

namespace glint::denoise::detail {

Image tangentWeights(const Image& median, float exposure) {
    Image weights(median.width(), median.height(), 3);
    for (std::size_t i = 0; i < median.data().size(); ++i) {
        const double s = displaySlope(double(median.data()[i]), exposure);
        weights.data()[i] = float(s * s);
    }
    float largest = 0.0f;
    for (float v : weights.data()) largest = std::max(largest, v);
    const float floor = std::max(largest * 1e-4f, std::numeric_limits<float>::min());
    for (float& v : weights.data()) v = std::max(v, floor);
    return weights;
}

std::vector<double> displayOf(const Image& centre, float exposure, WorkContext* work) {
    const DisplayCurve display(std::exp2(double(exposure)));
    const std::size_t rowValues = std::size_t(centre.width()) * 3;
    std::vector<double> out(rowValues * std::size_t(centre.height()));
    WorkContext own;
    (work ? *work : own).parallelFor(0, centre.height(), [&](int y) {
        const float* in = centre.row(y);
        double* o = out.data() + std::size_t(y) * rowValues;
        for (std::size_t i = 0; i < rowValues; ++i) o[i] = display(double(in[i]));
    });
    return out;
}

}  // namespace glint::denoise::detail

// Auto's correction layer in the session's composite (correction.h).
#include "composite/correction.h"

#include <algorithm>
#include <cmath>

namespace glint::denoise {

void correctInPlace(Image& dst, const SessionCorrection& correction, const Image& weight,
                    const Rect& rect) {
    const Rect r = intersect(rect, dst.bounds());
    for (int y = r.y0; y < r.y1; ++y) {
        float* x = dst.row(y);
        const float* t = correction.result.row(y);
        const float* b = correction.blend.row(y);
        const float* pw = weight.row(y);
        for (int px = r.x0; px < r.x1; ++px) {
            const float w = std::clamp(pw[px], 0.0f, 1.0f);  // NaN compares false: stays NaN
            if (!(w > 0.0f)) continue;
            for (int c = 0; c < 3; ++c) {
                const std::size_t i = std::size_t(px) * 3 + std::size_t(c);
                if (t[i] == b[i]) continue;
                // Where the composite beneath is still the blend it corrected, the result itself
                // (x + (t − b) = t exactly); elsewhere the correction added to it.
                if (w == 1.0f && x[i] == b[i]) {
                    x[i] = t[i];
                    continue;
                }
                const double v = double(x[i]) + double(w) * (double(t[i]) - double(b[i]));
                x[i] = float(std::max(0.0, v));
            }
        }
    }
}

std::string correctionProblem(const SessionCorrection& correction, int width, int height) {
    for (const auto& [image, what] : {std::pair{&correction.result, "auto's result"},
                                      std::pair{&correction.blend, "the blend"}}) {
        if (image->width() != width || image->height() != height || image->channels() != 3)
            return std::string(what) + " is " + std::to_string(image->width()) + "x" +
                   std::to_string(image->height()) + "x" + std::to_string(image->channels()) +
                   ", expected " + std::to_string(width) + "x" + std::to_string(height) + "x3";
        const auto& data = image->data();
        const auto bad =
            std::find_if(data.begin(), data.end(), [](float v) { return !std::isfinite(v); });
        if (bad != data.end()) {
            const std::size_t i = std::size_t(bad - data.begin());
            const std::size_t pixel = i / 3;
            return std::string(what) + " has the non-finite value " + std::to_string(*bad) +
                   " at pixel (" + std::to_string(pixel % std::size_t(width)) + ", " +
                   std::to_string(pixel / std::size_t(width)) + "), channel " +
                   std::to_string(i % 3);
        }
    }
    return {};
}

}  // namespace glint::denoise

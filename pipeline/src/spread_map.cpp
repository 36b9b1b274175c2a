#include "glint/pipeline/spread_map.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <span>
#include <vector>

#include "glint/image/error.h"

namespace glint::pipeline {

Image spreadPriority(const FrameBuffers& frame) {
    GLINT_CHECK(frame.has(Layer::HalfColor) && frame.has(Layer::HalfVariance) &&
                    frame.has(Layer::HalfSampleCount) && frame.has(Layer::SampleCount),
                "spreadPriority needs the frame's half buffers and sample counts");
    const Image& mu = frame.layer(Layer::HalfColor);
    const Image& var = frame.layer(Layer::HalfVariance);
    const Image& halfN = frame.layer(Layer::HalfSampleCount);
    const Image& n = frame.layer(Layer::SampleCount);
    Image out(frame.width(), frame.height(), 1);
    for (int y = 0; y < frame.height(); ++y)
        for (int x = 0; x < frame.width(); ++x) {
            const double nB = halfN(x, y, 0);
            if (nB < 2.0) {
                out(x, y, 0) = std::numeric_limits<float>::infinity();
                continue;
            }
            // halfVariance is the variance of half B's mean: σ² = it × n_B.
            double s2 = 0.0;
            for (int c = 0; c < 3; ++c) {
                const double m = mu(x, y, c);
                s2 += std::max(0.0, double(var(x, y, c))) * nB / (m * m + 0.01);
            }
            const double p = std::sqrt(s2 / 3.0) / std::max(1.0, double(n(x, y, 0)));
            out(x, y, 0) = std::isfinite(p) ? float(p) : std::numeric_limits<float>::infinity();
        }
    return out;
}

std::shared_ptr<const Image> spreadMap(const FrameBuffers& frame, double share, float open) {
    GLINT_CHECK(share > 0.0 && share <= 1.0, "spreadMap's share in (0, 1]");
    GLINT_CHECK(open > 0.0f && std::isfinite(open), "spreadMap's open weight finite and > 0");
    const Image priority = spreadPriority(frame);
    const std::span<const float> p = priority.data();
    // The cut: the priority of the last pixel in the share (nth_element: order-free, so the
    // same bits for any thread count).
    std::vector<float> sorted(p.begin(), p.end());
    const std::size_t k =
        std::min(sorted.size() - 1, std::size_t(std::ceil(share * double(sorted.size()))) - 1);
    std::nth_element(sorted.begin(), sorted.begin() + std::ptrdiff_t(k), sorted.end(),
                     std::greater<float>());
    const float cut = sorted[k];
    auto map = std::make_shared<Image>(frame.width(), frame.height(), 1);
    // No pixel with a spread: every one may take the pass (the renderer's error keeps them shut).
    if (!(cut > 0.0f)) {
        std::fill(map->data().begin(), map->data().end(), open);
        return map;
    }
    for (std::size_t i = 0; i < p.size(); ++i)
        map->data()[i] = p[i] > 0.0f && p[i] >= cut ? open : 0.0f;
    return map;
}

}  // namespace glint::pipeline

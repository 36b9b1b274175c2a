// The oracles' per-pixel error maps, their box averages and the composites of a per-pixel pick
// (error_maps.h).
#include "error_maps.h"

#include <algorithm>

#include "glint/denoise/bank.h"
#include "glint/image/error.h"

namespace glint::lab::detail {

// Per-pixel squared display error summed over channels, box-averaged over 3×3 (truncated at
// the border), so the per-pixel choice is not driven by single-pixel noise.
std::vector<float> errorMap(const Image& display, const Image& referenceDisplay) {
    const int w = display.width(), h = display.height();
    std::vector<float> raw(std::size_t(w) * std::size_t(h));
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            float e = 0.0f;
            for (int c = 0; c < 3; ++c) {
                const float d = display(x, y, c) - referenceDisplay(x, y, c);
                e += d * d;
            }
            raw[std::size_t(y) * w + x] = e;
        }
    std::vector<float> out(raw.size());
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            float s = 0.0f;
            int count = 0;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const int xx = x + dx, yy = y + dy;
                    if (xx < 0 || yy < 0 || xx >= w || yy >= h) continue;
                    s += raw[std::size_t(yy) * w + xx];
                    ++count;
                }
            out[std::size_t(y) * w + x] = s / float(count);
        }
    return out;
}

// Composite taking each pixel from the member `pick` says.
Image pickComposite(const denoise::FilterBank& bank, const std::vector<int>& pick) {
    const Rect& r = bank.region();
    Image out(r.width(), r.height(), 3);
    for (int y = 0; y < r.height(); ++y)
        for (int x = 0; x < r.width(); ++x) {
            const int m = pick[std::size_t(y) * r.width() + x];
            for (int c = 0; c < 3; ++c) out(x, y, c) = bank.result(std::size_t(m))(x, y, c);
        }
    return out;
}

Image boxSmooth(const Image& image, int radius) {
    GLINT_CHECK(image.channels() == 1 && radius >= 0);
    if (radius == 0 || image.empty()) return image;
    const int w = image.width(), h = image.height();
    // Horizontal: each row's prefix sums, the window's difference scaled by its width (truncated
    // at the border).
    std::vector<double> horizontal(std::size_t(w) * std::size_t(h)), prefix(std::size_t(w) + 1);
    const double inner = 1.0 / double(2 * radius + 1);
    for (int y = 0; y < h; ++y) {
        prefix[0] = 0.0;
        for (int x = 0; x < w; ++x) prefix[std::size_t(x) + 1] = double(image(x, y, 0));
        for (std::size_t i = 1; i < prefix.size(); ++i) prefix[i] += prefix[i - 1];
        for (int x = 0; x < w; ++x) {
            const auto x0 = std::size_t(std::max(0, x - radius)),
                       x1 = std::size_t(std::min(w, x + radius + 1));
            const double scale =
                x1 - x0 == std::size_t(2 * radius + 1) ? inner : 1.0 / double(x1 - x0);
            horizontal[std::size_t(y) * std::size_t(w) + std::size_t(x)] =
                (prefix[x1] - prefix[x0]) * scale;
        }
    }
    // Vertical: a running sum per column, rows entering and leaving in order.
    Image out(w, h, 1);
    std::vector<double> sum(std::size_t(w), 0.0);
    auto row = [&](int y) { return horizontal.data() + std::size_t(y) * std::size_t(w); };
    for (int y = 0; y < std::min(h, radius); ++y)
        for (int x = 0; x < w; ++x) sum[std::size_t(x)] += row(y)[x];
    for (int y = 0; y < h; ++y) {
        const int entering = y + radius, leaving = y - radius - 1;
        if (entering < h)
            for (int x = 0; x < w; ++x) sum[std::size_t(x)] += row(entering)[x];
        if (leaving >= 0)
            for (int x = 0; x < w; ++x) sum[std::size_t(x)] -= row(leaving)[x];
        const double scale = 1.0 / double(std::min(h, y + radius + 1) - std::max(0, y - radius));
        for (int x = 0; x < w; ++x) out(x, y, 0) = float(sum[std::size_t(x)] * scale);
    }
    return out;
}

}  // namespace glint::lab::detail

// The box mean (box_mean.h).
#include "glint/image/box_mean.h"

#include <algorithm>
#include <string>
#include <vector>

#include "glint/image/error.h"

namespace glint {

Image boxMean(const Image& image, int radius) {
    if (radius < 0)
        throw Error(ErrorKind::InvalidArgument,
                    "radius " + std::to_string(radius) + ", expected >= 0", {}, "box mean");
    if (radius == 0 || image.empty()) return image;
    const int w = image.width(), h = image.height(), channels = image.channels();
    const auto planes = std::size_t(channels);
    auto at = [&](int x, int y) {
        return (std::size_t(y) * std::size_t(w) + std::size_t(x)) * planes;
    };
    // Each window summed on its own (rows, then columns): no running sum, so a non-finite value
    // reaches only the windows that hold it.
    std::vector<double> rows(std::size_t(w) * std::size_t(h) * planes, 0.0);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            double* out = rows.data() + at(x, y);
            for (int sx = std::max(0, x - radius); sx <= std::min(w - 1, x + radius); ++sx)
                for (int c = 0; c < channels; ++c) out[c] += double(image(sx, y, c));
        }
    Image out(w, h, channels);
    std::vector<double> sum(planes);
    for (int y = 0; y < h; ++y) {
        const int y0 = std::max(0, y - radius), y1 = std::min(h - 1, y + radius);
        for (int x = 0; x < w; ++x) {
            const int n =
                (std::min(w - 1, x + radius) - std::max(0, x - radius) + 1) * (y1 - y0 + 1);
            std::fill(sum.begin(), sum.end(), 0.0);
            for (int sy = y0; sy <= y1; ++sy)
                for (int c = 0; c < channels; ++c)
                    sum[std::size_t(c)] += rows[at(x, sy) + std::size_t(c)];
            for (int c = 0; c < channels; ++c)
                out(x, y, c) = float(sum[std::size_t(c)] / double(n));
        }
    }
    return out;
}

}  // namespace glint

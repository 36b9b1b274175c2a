// Visual aids of the session: where the bank disagrees, what a candidate would change, a depth
// layer made readable.
#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

#include "glint/denoise/aids.h"
#include "glint/image/error.h"

namespace glint::denoise {

namespace {

// Divides by the largest value (leaves all-zero maps at 0).
void normalise(Image& map) {
    float top = 0.0f;
    for (float v : map.data()) top = std::max(top, v);
    if (top > 0.0f)
        for (float& v : map.data()) v /= top;
}

}  // namespace

Image filterVarianceMap(const std::vector<const Image*>& results) {
    if (results.empty()) throw Error(ErrorKind::InvalidArgument, "no results to compare");
    const Image& first = *results[0];
    for (const Image* r : results)
        if (!r->sameShape(first) || r->channels() != 3)
            throw Error(ErrorKind::InvalidArgument,
                        "the results must be 3-channel images of the same size");
    Image map(first.width(), first.height(), 1, 0.0f);
    for (std::size_t p = 0; p < first.pixelCount(); ++p) {
        // Welford over the results of the mean over channels, finite values only.
        double mean = 0.0, m2 = 0.0;
        int n = 0;
        for (const Image* r : results) {
            const float* px = r->data().data() + 3 * p;
            const double v = (double(px[0]) + px[1] + px[2]) / 3.0;
            if (!std::isfinite(v)) continue;
            ++n;
            const double d = v - mean;
            mean += d / n;
            m2 += d * (v - mean);
        }
        map.data()[p] = n > 1 ? float(std::sqrt(m2 / n)) : 0.0f;
    }
    normalise(map);
    return map;
}

Image changeMap(const Image& candidate, const Image& composite) {
    if (!candidate.sameShape(composite))
        throw Error(ErrorKind::InvalidArgument, "the candidate and the composite differ in size");
    Image map(candidate.width(), candidate.height(), 1, 0.0f);
    const int c = candidate.channels();
    for (std::size_t p = 0; p < candidate.pixelCount(); ++p) {
        double s = 0.0;
        for (int k = 0; k < c; ++k) {
            const double d = double(candidate.data()[p * c + k]) - composite.data()[p * c + k];
            if (std::isfinite(d)) s += std::fabs(d);
        }
        map.data()[p] = float(s / c);
    }
    normalise(map);
    return map;
}

Image equalizeHistogram(const Image& values) {
    if (values.channels() != 1)
        throw Error(ErrorKind::InvalidArgument, "histogram equalisation takes a 1-channel image");
    std::vector<float> sorted;
    sorted.reserve(values.pixelCount());
    for (float v : values.data())
        if (std::isfinite(v)) sorted.push_back(v);
    std::sort(sorted.begin(), sorted.end());
    Image out(values.width(), values.height(), 1, 0.0f);
    if (sorted.empty()) return out;
    for (std::size_t p = 0; p < values.pixelCount(); ++p) {
        const float v = values.data()[p];
        if (!std::isfinite(v)) continue;
        // The fraction of finite values at or below v.
        const auto at = std::upper_bound(sorted.begin(), sorted.end(), v) - sorted.begin();
        out.data()[p] = float(double(at) / double(sorted.size()));
    }
    return out;
}

}  // namespace glint::denoise

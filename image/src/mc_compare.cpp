// Monte Carlo-aware image comparison (docs/testing.md): windowed, self-normalised sums of
// per-value z-scores with Efron's sub-Gaussian bound and a Bonferroni correction.
#include "glint/image/mc_compare.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "glint/image/error.h"
#include "shape_text.h"

namespace glint {
namespace {

/// Window sides (pixels); each is tested at a stride of a quarter of its side.
constexpr int kWindowSides[] = {8, 16, 32};

/// Summed-area tables of per-pixel sums over channels (double, (w+1) x (h+1)).
struct Integral {
    int w = 0, h = 0;
    std::vector<double> z, z2, diff, ref;
    double sum(const std::vector<double>& t, const Rect& r) const {
        auto at = [&](int x, int y) { return t[std::size_t(y) * (w + 1) + x]; };
        return at(r.x1, r.y1) - at(r.x0, r.y1) - at(r.x1, r.y0) + at(r.x0, r.y0);
    }
};

}  // namespace

McCompareResult mcCompare(const Image& mean, const Image& variance, const Image& reference,
                          const Image& referenceVariance, const McCompareOptions& options) {
    const char* where = "mc";
    for (const Image* im : {&variance, &reference, &referenceVariance})
        if (!im->sameShape(mean))
            throw Error(ErrorKind::InvalidArgument,
                        "the image is " + detail::shapeText(mean) +
                            " but a mean or variance to compare is " + detail::shapeText(*im) +
                            "; they must match",
                        {}, where);
    if (mean.empty()) throw Error(ErrorKind::InvalidArgument, "the images are empty", {}, where);
    if (!(options.falseAlarmRate > 0.0 && options.falseAlarmRate < 1.0))
        throw Error(
            ErrorKind::InvalidArgument,
            "the false-alarm rate must be in (0, 1), got " + numberText(options.falseAlarmRate), {},
            where);

    // Per-pixel z-scores summed over channels, their squares, and their summed-area tables.
    const int w = mean.width(), h = mean.height(), channels = mean.channels();
    Integral t;
    t.w = w;
    t.h = h;
    for (auto* table : {&t.z, &t.z2, &t.diff, &t.ref})
        table->assign(std::size_t(w + 1) * (h + 1), 0.0);
    for (int y = 0; y < h; ++y) {
        double rz = 0, rz2 = 0, rdiff = 0, rref = 0;  // running sums along the row
        for (int x = 0; x < w; ++x) {
            // A pixel's channels come from the same paths, so they are not independent: the
            // self-normalised sum takes each pixel's z-scores summed over its channels as one
            // term (pixels are independent), which keeps Efron's bound for correlated channels.
            double pz = 0;
            for (int c = 0; c < channels; ++c) {
                const double m = mean(x, y, c), r = reference(x, y, c);
                const double vm = variance(x, y, c), vr = referenceVariance(x, y, c);
                if (!std::isfinite(m) || !std::isfinite(r) || !std::isfinite(vm) ||
                    !std::isfinite(vr) || vm < 0 || vr < 0)
                    throw Error(ErrorKind::InvalidArgument,
                                "pixel (" + std::to_string(x) + ", " + std::to_string(y) +
                                    ") channel " + std::to_string(c) +
                                    " has a NaN/Inf value or a negative variance",
                                {}, where);
                const double d = m - r;
                // A value with no variance in either estimate: only an exact match is noise-free;
                // otherwise a tiny floor makes any real difference a large z.
                const double v = vm + vr;
                const double floor = 1e-12 * std::max(std::fabs(m), std::fabs(r)) + 1e-30;
                const double z = d == 0.0 ? 0.0 : d / std::sqrt(std::max(v, floor * floor));
                pz += z;
                rdiff += d;
                rref += r;
            }
            rz += pz;
            rz2 += pz * pz;
            const std::size_t i = std::size_t(y + 1) * (w + 1) + std::size_t(x + 1);
            const std::size_t above = std::size_t(y) * (w + 1) + std::size_t(x + 1);
            t.z[i] = t.z[above] + rz;
            t.z2[i] = t.z2[above] + rz2;
            t.diff[i] = t.diff[above] + rdiff;
            t.ref[i] = t.ref[above] + rref;
        }
    }

    // The windows: every side that fits, at a stride of a quarter of it; else the whole image.
    std::vector<Rect> windows;
    for (const int side : kWindowSides) {
        if (side > w || side > h) continue;
        const int stride = side / 4;
        for (int y0 = 0; y0 + side <= h; y0 += stride)
            for (int x0 = 0; x0 + side <= w; x0 += stride)
                windows.push_back(Rect{x0, x0 + side, y0, y0 + side});
    }
    if (windows.empty()) windows.push_back(mean.bounds());

    McCompareResult result;
    result.windows = windows.size();
    // Efron 1969: P(|sum z / sqrt(sum z^2)| > t) <= 2 exp(-t^2/2); Bonferroni over N windows.
    result.threshold =
        std::sqrt(2.0 * std::log(2.0 * double(windows.size()) / options.falseAlarmRate));
    result.worstWindow = windows.front();
    for (const Rect& r : windows) {
        const double z2 = t.sum(t.z2, r);
        const double s = z2 > 0.0 ? std::fabs(t.sum(t.z, r)) / std::sqrt(z2) : 0.0;
        if (s > result.statistic) {
            result.statistic = s;
            result.worstWindow = r;
        }
    }
    const double refSum = t.sum(t.ref, result.worstWindow);
    result.relativeBias = refSum != 0.0 ? t.sum(t.diff, result.worstWindow) / refSum : 0.0;
    result.passed = result.statistic <= result.threshold;
    return result;
}

McCompareResult mcCompareByChannel(const Image& mean, const Image& variance, const Image& reference,
                                   const Image& referenceVariance,
                                   const McCompareOptions& options) {
    // Channel c of an image, as a one-channel image.
    auto plane = [](const Image& image, int c) {
        Image out(image.width(), image.height(), 1);
        for (int y = 0; y < image.height(); ++y)
            for (int x = 0; x < image.width(); ++x) out(x, y, 0) = image(x, y, c);
        return out;
    };
    // Shapes that differ: mcCompare says so, naming them.
    for (const Image* im : {&variance, &reference, &referenceVariance})
        if (!im->sameShape(mean))
            return mcCompare(mean, variance, reference, referenceVariance, options);
    const int channels = mean.channels();
    const McCompareOptions each{options.falseAlarmRate / std::max(channels, 1)};
    McCompareResult worst;
    for (int c = 0; c < channels; ++c) {
        const McCompareResult r = mcCompare(plane(mean, c), plane(variance, c), plane(reference, c),
                                            plane(referenceVariance, c), each);
        if (c == 0 || r.statistic / r.threshold > worst.statistic / worst.threshold) worst = r;
    }
    worst.passed = worst.statistic <= worst.threshold;
    return worst;
}

}  // namespace glint

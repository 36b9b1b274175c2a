// The image-only noise estimator (image_noise.h; docs/auto.md, "Error estimation without variance
// or halves").
#include "image_noise.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <vector>

#include "estimator.h"
#include "glint/image/error.h"

namespace glint::denoise::detail {

namespace {

// The median of χ²₁: a Gaussian residual's squared value has median 0.4549 σ².
constexpr double kChiSquare1Median = 0.454936;

// The albedo and normal of a frame, each null when absent.
struct Features {
    const Image* albedo = nullptr;
    const Image* normal = nullptr;
};

// Whether the 3 values of `image` at (x, y) are finite.
bool finiteAt(const Image& image, int x, int y) {
    const float* p = image.row(y) + std::size_t(x) * 3;
    return std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]);
}

// ‖a(p) − a(q)‖² over 3 channels, or -1 when either value is not finite.
double distance2(const Image& a, int px, int py, int qx, int qy) {
    if (!finiteAt(a, px, py) || !finiteAt(a, qx, qy)) return -1.0;
    double d = 0.0;
    for (int c = 0; c < 3; ++c) {
        const double v = double(a(px, py, c)) - double(a(qx, qy, c));
        d += v * v;
    }
    return d;
}

// How alike the features of pixels p and q are: exp(−‖ΔA‖²/2σa² − ‖ΔN‖²/2σn²), a feature that is
// absent or not finite at either pixel left out (1 without features).
double featureWeight(const Features& f, const ImageNoiseOptions& o, int px, int py, int qx,
                     int qy) {
    double e = 0.0;
    if (f.albedo) {
        const double d = distance2(*f.albedo, px, py, qx, qy);
        if (d > 0.0) e += d / (2.0 * o.albedoSigma * o.albedoSigma);
    }
    if (f.normal) {
        const double d = distance2(*f.normal, px, py, qx, qy);
        if (d > 0.0) e += d / (2.0 * o.normalSigma * o.normalSigma);
    }
    return std::exp(-e);
}

}  // namespace

void checkImageNoiseInput(const FrameBuffers& frame, const std::string& file) {
    const Image& color = frame.color();
    std::atomic<bool> bad{false};
    WorkContext work;
    work.parallelFor(0, frame.height(), [&](int y) {
        const float* c = color.row(y);
        for (int i = 0; i < frame.width() * 3; ++i)
            if (!std::isfinite(c[i])) bad.store(true);
    });
    if (!bad.load()) return;
    // The first bad value in scan order: a reproducible message.
    for (int y = 0; y < frame.height(); ++y)
        for (int x = 0; x < frame.width(); ++x)
            for (int c = 0; c < 3; ++c)
                if (const float v = color(x, y, c); !std::isfinite(v))
                    throw Error(
                        ErrorKind::Numeric,
                        std::string(std::isnan(v) ? "NaN" : "Inf") + " in " +
                            layerInFile(frame, Layer::Color) +
                            "; the image-only noise estimator needs finite values",
                        file,
                        pixelText(x, y) + ", channel " + channelInFile(frame, Layer::Color, c));
}

Image estimateImageNoise(const FrameBuffers& frame, const ImageNoiseOptions& o, WorkContext& work) {
    const int w = frame.width(), h = frame.height();
    const Image& color = frame.color();
    const Features f{frame.find(Layer::Albedo), frame.find(Layer::Normal)};

    // 1. The leave-one-out residual d = y_p − Σ w_q y_q / Σ w_q over the pixels q ≠ p of the
    //    prediction window, w_q the feature weight: with independent pixel noise of variance σ²
    //    around a mean the features explain, Var d = σ² (1 + Σ w_q² / (Σ w_q)²). Stored
    //    normalised, d² / (1 + Σw²/(Σw)²), with the prediction (the pixel's smooth value) m.
    Image residual(w, h, 3), smooth(w, h, 3);
    const int r = o.predictRadius;
    work.parallelFor(0, h, [&](int y) {
        for (int x = 0; x < w; ++x) {
            double sw = 0.0, sw2 = 0.0;
            std::array<double, 3> acc{};
            for (int pass = 0; pass < 2 && sw <= 1e-6; ++pass) {
                // A pixel whose features match no neighbour is predicted from all of them.
                sw = sw2 = 0.0;
                acc = {};
                for (int qy = std::max(0, y - r); qy <= std::min(h - 1, y + r); ++qy)
                    for (int qx = std::max(0, x - r); qx <= std::min(w - 1, x + r); ++qx) {
                        if (qx == x && qy == y) continue;
                        const double wq = pass == 0 ? featureWeight(f, o, x, y, qx, qy) : 1.0;
                        sw += wq;
                        sw2 += wq * wq;
                        for (int c = 0; c < 3; ++c) acc[std::size_t(c)] += wq * color(qx, qy, c);
                    }
            }
            const double k = sw > 0.0 ? sw2 / (sw * sw) : 0.0;
            for (int c = 0; c < 3; ++c) {
                const double m = sw > 0.0 ? acc[std::size_t(c)] / sw : double(color(x, y, c));
                const double d = double(color(x, y, c)) - m;
                residual(x, y, c) = float(d * d / (1.0 + k));
                smooth(x, y, c) = float(std::max(m, 0.0));
            }
        }
    });

    // 2. The brightness modulation's floor: 1e-3 of the frame's mean m^alpha per channel, so
    //    that black pixels still get their neighbours' noise level.
    std::array<double, 3> floor{};
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < 3; ++c)
                floor[std::size_t(c)] += std::pow(double(smooth(x, y, c)), o.alpha);
    for (double& v : floor)
        v = 1e-3 * v / double(std::max<std::size_t>(color.pixelCount(), 1)) + 1e-20;

    // 3. The local noise level: the median of residual² / (m^alpha + floor) over the pixels of
    //    the window whose features are like the centre's (weight ≥ gate), scaled to a variance
    //    by the median of χ²₁ and multiplied back by the centre's own m^alpha + floor. Each row
    //    also sums, per channel, the levels and the pixels' own residual² / (m^alpha + floor),
    //    for the tail factor of step 4.
    Image variance(w, h, 3);
    std::vector<std::array<double, 6>> rowSums(std::size_t(h), std::array<double, 6>{});
    const int R = o.window;
    work.parallelFor(0, h, [&](int y) {
        std::array<std::vector<double>, 3> values;
        std::array<double, 6>& sums = rowSums[std::size_t(y)];
        for (int x = 0; x < w; ++x) {
            for (auto& v : values) v.clear();
            for (int qy = std::max(0, y - R); qy <= std::min(h - 1, y + R); ++qy)
                for (int qx = std::max(0, x - R); qx <= std::min(w - 1, x + R); ++qx) {
                    const bool self = qx == x && qy == y;
                    if (!self && featureWeight(f, o, x, y, qx, qy) < o.gate) continue;
                    for (int c = 0; c < 3; ++c) {
                        const double s =
                            std::pow(double(smooth(qx, qy, c)), o.alpha) + floor[std::size_t(c)];
                        values[std::size_t(c)].push_back(double(residual(qx, qy, c)) / s);
                    }
                }
            for (int c = 0; c < 3; ++c) {
                std::vector<double>& v = values[std::size_t(c)];
                const auto mid = v.begin() + std::ptrdiff_t(v.size() / 2);
                std::nth_element(v.begin(), mid, v.end());
                const double s = std::pow(double(smooth(x, y, c)), o.alpha) + floor[std::size_t(c)];
                const double level = *mid / kChiSquare1Median;
                variance(x, y, c) = float(level * s);
                sums[std::size_t(c)] += double(residual(x, y, c)) / s;
                sums[std::size_t(c) + 3] += level;
            }
        }
    });

    // 4. The tail factor: over the frame, the mean of the pixels' own residual² / (m^alpha +
    //    floor) estimates the mean normalised variance with every firefly counted; the median
    //    level reads only the body of the distribution, T = mean / mean level times too low for
    //    heavy-tailed noise. T is kept when above 1; a light-tailed or structure-dominated frame
    //    (T < 1: edges the features miss give residuals of even size) keeps the median's level.
    if (!o.tail) return variance;
    std::array<double, 6> total{};
    for (const auto& row : rowSums)  // in row order: the same sum on every run
        for (std::size_t i = 0; i < 6; ++i) total[i] += row[i];
    std::array<double, 3> t{};
    for (std::size_t c = 0; c < 3; ++c)
        t[c] = total[c + 3] > 0.0 ? std::max(1.0, total[c] / total[c + 3]) : 1.0;
    work.parallelFor(0, h, [&](int y) {
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < 3; ++c)
                variance(x, y, c) = float(double(variance(x, y, c)) * t[std::size_t(c)]);
    });
    return variance;
}

}  // namespace glint::denoise::detail

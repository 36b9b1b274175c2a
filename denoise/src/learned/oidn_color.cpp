// PU transfer and autoexposure after Open Image Denoise 2.x (core/color.h,
// devices/cpu/cpu_autoexposure.cpp). The PU curve fits the perceptually uniform encoding of Aydin,
// Mantiuk and Seidel (2008) with a linear, a power and a logarithmic piece.
#include "learned/oidn_color.h"

#include <tbb/parallel_for.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace glint::denoise::learned {

namespace {

// PU fit constants (OIDN core/color.h).
constexpr double kA = 1.41283765e+03, kB = 1.64593172e+00, kC = 4.31384981e-01,
                 kD = -2.94139609e-03, kE = 1.92653254e-01, kF = 6.26026094e-03,
                 kG = 9.98620152e-01, kY0 = 1.57945760e-06, kY1 = 3.22087631e-02,
                 kX0 = 2.23151711e-03, kX1 = 3.70974749e-01;
constexpr double kYMax = 65504.0;  // largest finite half

double puRaw(double y) {
    if (y <= kY0) return kA * y;
    if (y <= kY1) return kB * std::pow(y, kC) + kD;
    return kE * std::log(y + kF) + kG;
}

double puRawInverse(double x) {
    if (x <= kX0) return x / kA;
    if (x <= kX1) return std::pow((x - kD) / kB, 1.0 / kC);
    return std::exp((x - kG) / kE) - kF;
}

const double kXMax = puRaw(kYMax);

// A colour value for the luminance sum: NaN and negatives as 0, +Inf as FLT_MAX.
double sanitize(float v) {
    if (v == std::numeric_limits<float>::infinity()) return std::numeric_limits<float>::max();
    return v > 0.0f ? double(v) : 0.0;
}

}  // namespace

double puForward(double y) {
    return puRaw(y) / kXMax;
}

double puInverse(double x) {
    return puRawInverse(x * kXMax);
}

double autoexposure(const Image& color) {
    constexpr int kMaxBin = 16;
    constexpr double kKey = 0.18, kEps = 1e-8;
    const int h = color.height(), w = color.width();
    const int nbH = (h + kMaxBin - 1) / kMaxBin, nbW = (w + kMaxBin - 1) / kMaxBin;
    // Mean luminance (Rec. 709 weights) of each bin, rows of bins in parallel (each bin summed in
    // one order by one thread, so the same bits on any thread count).
    std::vector<double> bins(std::size_t(nbH) * std::size_t(nbW));
    tbb::parallel_for(0, nbH, [&](int i) {
        const int y0 = int(std::int64_t(i) * h / nbH), y1 = int(std::int64_t(i + 1) * h / nbH);
        for (int j = 0; j < nbW; ++j) {
            const int x0 = int(std::int64_t(j) * w / nbW), x1 = int(std::int64_t(j + 1) * w / nbW);
            double l = 0.0;
            for (int y = y0; y < y1; ++y) {
                const float* p = color.row(y);
                for (int x = x0; x < x1; ++x)
                    l += 0.212671 * sanitize(p[3 * x]) + 0.715160 * sanitize(p[3 * x + 1]) +
                         0.072169 * sanitize(p[3 * x + 2]);
            }
            bins[std::size_t(i) * std::size_t(nbW) + std::size_t(j)] =
                l / (double(y1 - y0) * double(x1 - x0));
        }
    });
    // The log2 mean over the bright-enough bins, in bin order.
    double sum = 0.0;
    int count = 0;
    for (double l : bins)
        if (l > kEps) {
            sum += std::log2(l);
            ++count;
        }
    return count > 0 ? kKey / std::exp2(sum / count) : 1.0;
}

}  // namespace glint::denoise::learned

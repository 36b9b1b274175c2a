// SSIM kernel (Wang, Bovik, Sheikh, Simoncelli 2004, "Image Quality Assessment: From Error
// Visibility to Structural Similarity", eqs. 6-7 and 13-14 with a Gaussian window), written to
// match scikit-image's structural_similarity(gaussian_weights=True, sigma=1.5,
// use_sample_covariance=False, data_range=1).
//
// The five local moments (means, second moments, cross moment) are filtered separably with an
// 11-tap Gaussian: a vertical pass over 11 mirrored rows, then a horizontal pass over a row
// padded by mirroring. Inputs are float; every sum and product is formed in double, because the
// variances come from the cancelling difference E[x^2] - E[x]^2 and are compared with
// C2 = 9e-4 (float sums would leave errors near 1e-4 in flat regions). Rows are processed in
// parallel; each row's sum is stored and the rows are added in order, so the result does not
// depend on the thread count.
#include "ssim.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "glint/image/error.h"

// Hot loops get an AVX2+FMA clone chosen at load time where the compiler supports it; the
// default clone keeps the binary runnable on any x86-64.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
#define GLINT_SIMD_CLONES __attribute__((target_clones("arch=x86-64-v3", "default")))
#else
#define GLINT_SIMD_CLONES
#endif

namespace glint::detail {
namespace {

constexpr int kTaps = 2 * kSsimRadius + 1;
using Weights = std::array<double, kTaps>;

/// Wang et al. 2004 stabilising constants for data range L = 1: C1 = (K1 L)^2, C2 = (K2 L)^2.
constexpr double kC1 = 0.01 * 0.01;
constexpr double kC2 = 0.03 * 0.03;

/// Gaussian taps exp(-k^2 / (2 sigma^2)), sigma = 1.5, k in [-5, 5], normalised to sum 1
/// (the kernel of scipy.ndimage.gaussian_filter1d with truncate = 3.5).
Weights gaussianWeights() {
    constexpr double sigma = 1.5;
    Weights w{};
    double sum = 0.0;
    for (int k = -kSsimRadius; k <= kSsimRadius; ++k) {
        w[k + kSsimRadius] = std::exp(-0.5 * k * k / (sigma * sigma));
        sum += w[k + kSsimRadius];
    }
    for (double& v : w) v /= sum;
    return w;
}

/// Mirrors index i into [0, n) with the edge sample repeated ("c b a | a b c", scipy 'reflect').
/// Valid for -n <= i < 2n, which holds because n >= kSsimMinSize > kSsimRadius.
inline int mirror(int i, int n) {
    return i < 0 ? -1 - i : (i >= n ? 2 * n - 1 - i : i);
}

/// Vertical pass: weighted sums over 11 rows of x, y, x^2, y^2 and xy for every column.
GLINT_SIMD_CLONES
void verticalMoments(const float* const* xRows, const float* const* yRows, const double* w,
                     int width, double* __restrict mx, double* __restrict my,
                     double* __restrict mxx, double* __restrict myy, double* __restrict mxy) {
    for (int x = 0; x < width; ++x) {
        double sx = 0.0, sy = 0.0, sxx = 0.0, syy = 0.0, sxy = 0.0;
        for (int k = 0; k < kTaps; ++k) {
            const double a = xRows[k][x];
            const double b = yRows[k][x];
            const double wa = w[k] * a;
            const double wb = w[k] * b;
            sx += wa;
            sy += wb;
            sxx += wa * a;
            syy += wb * b;
            sxy += wa * b;
        }
        mx[x] = sx;
        my[x] = sy;
        mxx[x] = sxx;
        myy[x] = syy;
        mxy[x] = sxy;
    }
}

/// Horizontal pass over mirrored-padded moment rows, then the SSIM of every pixel of the row.
GLINT_SIMD_CLONES
void horizontalSsim(const double* mx, const double* my, const double* mxx, const double* myy,
                    const double* mxy, const double* w, int width, double* __restrict out) {
    for (int x = 0; x < width; ++x) {
        double ux = 0.0, uy = 0.0, uxx = 0.0, uyy = 0.0, uxy = 0.0;
        for (int k = 0; k < kTaps; ++k) {
            ux += w[k] * mx[x + k];
            uy += w[k] * my[x + k];
            uxx += w[k] * mxx[x + k];
            uyy += w[k] * myy[x + k];
            uxy += w[k] * mxy[x + k];
        }
        // Population (co)variances of the window: E[xy] - E[x]E[y].
        const double vx = uxx - ux * ux;
        const double vy = uyy - uy * uy;
        const double vxy = uxy - ux * uy;
        // Wang et al. 2004, eq. 13: luminance term times contrast-structure term.
        const double a1 = 2.0 * ux * uy + kC1;
        const double a2 = 2.0 * vxy + kC2;
        const double b1 = ux * ux + uy * uy + kC1;
        const double b2 = vx + vy + kC2;
        out[x] = (a1 * a2) / (b1 * b2);
    }
}

/// Fills the kSsimRadius samples on each side of row[r, r + width) by mirroring.
void padMirror(double* row, int width) {
    constexpr int r = kSsimRadius;
    for (int i = 0; i < r; ++i) {
        row[r - 1 - i] = row[r + i];
        row[r + width + i] = row[r + width - 1 - i];
    }
}

}  // namespace

double ssimPlanar(const SsimPlanes& planes, Image* map) {
    const int width = planes.width;
    const int height = planes.height;
    const int channels = planes.channels;
    GLINT_CHECK(width >= kSsimMinSize && height >= kSsimMinSize && channels > 0,
                "SSIM kernel needs at least 11x11 pixels and one channel");
    constexpr int r = kSsimRadius;
    const Weights w = gaussianWeights();
    const std::size_t plane = std::size_t(width) * std::size_t(height);
    const std::size_t padded = std::size_t(width) + 2 * r;
    if (map) *map = Image(width, height, 1);

    std::vector<double> rowSums(std::size_t(height), 0.0);
    tbb::parallel_for(
        tbb::blocked_range<int>(0, height, 8), [&](const tbb::blocked_range<int>& rows) {
            // Scratch for one row: five padded moment rows, the SSIM row, the channel-summed map.
            std::vector<double> scratch(5 * padded + 2 * std::size_t(width));
            double* mx = scratch.data();
            double* my = mx + padded;
            double* mxx = my + padded;
            double* myy = mxx + padded;
            double* mxy = myy + padded;
            double* ssimRow = mxy + padded;
            double* mapSum = ssimRow + width;
            std::array<const float*, kTaps> xRows{};
            std::array<const float*, kTaps> yRows{};

            for (int y = rows.begin(); y != rows.end(); ++y) {
                const bool interiorRow = y >= r && y < height - r;
                double rowSum = 0.0;
                if (map) std::fill(mapSum, mapSum + width, 0.0);
                for (int c = 0; c < channels; ++c) {
                    // Gather the 11 mirrored source rows centred on y.
                    const float* xPlane = planes.image + std::size_t(c) * plane;
                    const float* yPlane = planes.reference + std::size_t(c) * plane;
                    for (int k = 0; k < kTaps; ++k) {
                        const std::size_t src = std::size_t(mirror(y - r + k, height));
                        xRows[std::size_t(k)] = xPlane + src * std::size_t(width);
                        yRows[std::size_t(k)] = yPlane + src * std::size_t(width);
                    }
                    // Filter the moments vertically, pad, filter horizontally and form SSIM.
                    verticalMoments(xRows.data(), yRows.data(), w.data(), width, mx + r, my + r,
                                    mxx + r, myy + r, mxy + r);
                    for (double* m : {mx, my, mxx, myy, mxy}) padMirror(m, width);
                    horizontalSsim(mx, my, mxx, myy, mxy, w.data(), width, ssimRow);
                    // Average only pixels at least r from every border (skimage's crop).
                    if (interiorRow)
                        for (int x = r; x < width - r; ++x) rowSum += ssimRow[x];
                    if (map)
                        for (int x = 0; x < width; ++x) mapSum[x] += ssimRow[x];
                }
                rowSums[std::size_t(y)] = rowSum;
                if (map) {
                    float* out = map->row(y);
                    for (int x = 0; x < width; ++x) out[x] = float(mapSum[x] / channels);
                }
            }
        });

    // Add the rows in order so the mean is independent of the scheduling.
    double total = 0.0;
    for (double s : rowSums) total += s;
    const double count = double(width - 2 * r) * double(height - 2 * r) * double(channels);
    return total / count;
}

}  // namespace glint::detail

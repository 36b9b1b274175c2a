// SSIM kernel (Wang, Bovik, Sheikh, Simoncelli 2004, "Image Quality Assessment: From Error
// Visibility to Structural Similarity", eqs. 6-7 and 13-14 with a Gaussian window), written to
// match scikit-image's structural_similarity(gaussian_weights=True, sigma=1.5,
// use_sample_covariance=False, data_range=1).
//
// Rows are processed in parallel bands. Each band first converts its rows plus a 5-row halo
// (mirrored at the image edge) into per-thread planar float buffers (non-finite values -> 0,
// display transform), so no image-sized copy is made. The five local moments (means, second
// moments, cross moment) are then filtered separably with an 11-tap Gaussian: a vertical pass
// over 11 band rows, then a horizontal pass over a row padded by mirroring. Every sum and
// product is formed in double, because the variances come from the cancelling difference
// E[x^2] - E[x]^2 and are compared with C2 = 9e-4 (float sums would leave errors near 1e-4 in
// flat regions). Each row's sum is stored and the rows are added in order, so the result does
// not depend on the thread count or the band split.
#include "ssim.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "glint/image/error.h"
#include "glint/image/internal/simd.h"
#include "glint/image/io.h"

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

/// True for finite v; written as a compare so that loops over it stay branch-free.
inline bool finite(float v) {
    return std::fabs(v) <= std::numeric_limits<float>::max();
}

/// Writes one row of interleaved pixels as `channels` plane rows `planeStride` apart, with
/// non-finite values replaced by 0 and, when `display`, srgbEncode(clamp(v * scale, 0, 1)).
void toPlanarRow(const float* src, int width, int channels, bool display, float scale, float* dst,
                 std::size_t planeStride) {
    for (int c = 0; c < channels; ++c) {
        const float* in = src + c;
        float* out = dst + std::size_t(c) * planeStride;
        const std::size_t step = std::size_t(channels);
        if (display) {
            for (int x = 0; x < width; ++x) {
                const float v = in[std::size_t(x) * step];
                out[x] = srgbEncode(finite(v) ? std::clamp(v * scale, 0.0f, 1.0f) : 0.0f);
            }
        } else {
            for (int x = 0; x < width; ++x) {
                const float v = in[std::size_t(x) * step];
                out[x] = finite(v) ? v : 0.0f;
            }
        }
    }
}

/// Pixels of a row with a NaN/Inf in some channel of a or b.
std::size_t nonFiniteInRow(const float* a, const float* b, int width, int channels) {
    // A branch-free scan of the whole row first: rows are almost always all finite.
    const std::size_t n = std::size_t(width) * std::size_t(channels);
    int anyBad = 0;
    for (std::size_t i = 0; i < n; ++i) anyBad |= int(!finite(a[i])) | int(!finite(b[i]));
    if (!anyBad) return 0;
    std::size_t count = 0;
    for (int x = 0; x < width; ++x) {
        bool ok = true;
        for (int c = 0; c < channels; ++c) {
            const std::size_t i = std::size_t(x) * std::size_t(channels) + std::size_t(c);
            ok = ok && finite(a[i]) && finite(b[i]);
        }
        count += ok ? 0 : 1;
    }
    return count;
}

/// Sum of v[begin, end) with four interleaved partial sums (a fixed order, so deterministic).
double sumRange(const double* v, int begin, int end) {
    double s0 = 0.0, s1 = 0.0, s2 = 0.0, s3 = 0.0;
    int x = begin;
    for (; x + 4 <= end; x += 4) {
        s0 += v[x];
        s1 += v[x + 1];
        s2 += v[x + 2];
        s3 += v[x + 3];
    }
    for (; x < end; ++x) s0 += v[x];
    return (s0 + s1) + (s2 + s3);
}

/// Per-thread buffers, reused by every band the thread processes.
struct Scratch {
    std::vector<float> band;   ///< image planes then reference planes, band rows each
    std::vector<double> rows;  ///< five padded moment rows, the SSIM row, the map sum
};

}  // namespace

SsimOutcome computeSsim(const SsimRequest& request, Image* map) {
    const Image& image = *request.image;
    const Image& reference = *request.reference;
    const Rect rect = request.rect;
    const int width = rect.width();
    const int height = rect.height();
    const int channels = image.channels();
    GLINT_CHECK(image.sameShape(reference) && intersect(rect, image.bounds()) == rect,
                "SSIM request outside the images");
    GLINT_CHECK(width >= kSsimMinSize && height >= kSsimMinSize && channels > 0,
                "SSIM kernel needs at least 11x11 pixels and one channel");
    constexpr int r = kSsimRadius;
    const Weights w = gaussianWeights();
    const std::size_t padded = std::size_t(width) + 2 * r;
    if (map) *map = Image(width, height, 1);

    // Bands of up to 128 rows, about four per thread: the 10 halo rows converted twice cost
    // at most ~8% extra (display transform), the buffers stay a few MB.
    const int threads = std::max(1, tbb::this_task_arena::max_concurrency());
    const int bandRows = std::clamp(height / (4 * threads), 16, 128);
    tbb::enumerable_thread_specific<Scratch> scratch;
    std::vector<double> rowSums(std::size_t(height), 0.0);
    std::vector<std::size_t> rowNonFinite(std::size_t(height), 0);

    auto band = [&](const tbb::blocked_range<int>& rows) {
        const int y0 = rows.begin();
        const int y1 = rows.end();
        Scratch& s = scratch.local();
        // Convert rows y0 - r .. y1 + r - 1 (mirrored into the rect) to planar input.
        const int n = y1 - y0 + 2 * r;
        const std::size_t plane = std::size_t(n) * std::size_t(width);
        s.band.resize(2 * plane * std::size_t(channels));
        float* xBand = s.band.data();
        float* yBand = xBand + plane * std::size_t(channels);
        for (int j = 0; j < n; ++j) {
            const int src = rect.y0 + mirror(y0 - r + j, height);
            const std::size_t offset = std::size_t(rect.x0) * std::size_t(channels);
            const std::size_t dst = std::size_t(j) * std::size_t(width);
            toPlanarRow(image.row(src) + offset, width, channels, request.display, request.scale,
                        xBand + dst, plane);
            toPlanarRow(reference.row(src) + offset, width, channels, request.display,
                        request.scale, yBand + dst, plane);
        }
        for (int y = y0; y < y1; ++y) {
            const std::size_t offset = std::size_t(rect.x0) * std::size_t(channels);
            rowNonFinite[std::size_t(y)] =
                nonFiniteInRow(image.row(rect.y0 + y) + offset, reference.row(rect.y0 + y) + offset,
                               width, channels);
        }

        s.rows.resize(5 * padded + 2 * std::size_t(width));
        double* mx = s.rows.data();
        double* my = mx + padded;
        double* mxx = my + padded;
        double* myy = mxx + padded;
        double* mxy = myy + padded;
        double* ssimRow = mxy + padded;
        double* mapSum = ssimRow + width;
        std::array<const float*, kTaps> xRows{};
        std::array<const float*, kTaps> yRows{};
        for (int y = y0; y < y1; ++y) {
            const bool interiorRow = y >= r && y < height - r;
            double rowSum = 0.0;
            if (map) std::fill(mapSum, mapSum + width, 0.0);
            for (int c = 0; c < channels; ++c) {
                // The 11 band rows centred on y (band row y - y0 + r is row y).
                for (int k = 0; k < kTaps; ++k) {
                    const std::size_t at =
                        std::size_t(c) * plane + std::size_t(y - y0 + k) * std::size_t(width);
                    xRows[std::size_t(k)] = xBand + at;
                    yRows[std::size_t(k)] = yBand + at;
                }
                // Filter the moments vertically, pad, filter horizontally and form SSIM.
                verticalMoments(xRows.data(), yRows.data(), w.data(), width, mx + r, my + r,
                                mxx + r, myy + r, mxy + r);
                for (double* m : {mx, my, mxx, myy, mxy}) padMirror(m, width);
                horizontalSsim(mx, my, mxx, myy, mxy, w.data(), width, ssimRow);
                // Average only pixels at least r from every border (skimage's crop).
                if (interiorRow) rowSum += sumRange(ssimRow, r, width - r);
                if (map)
                    for (int x = 0; x < width; ++x) mapSum[x] += ssimRow[x];
            }
            rowSums[std::size_t(y)] = rowSum;
            if (map) {
                float* out = map->row(y);
                for (int x = 0; x < width; ++x) out[x] = float(mapSum[x] / channels);
            }
        }
    };
    tbb::parallel_for(tbb::blocked_range<int>(0, height, std::size_t(bandRows)), band,
                      tbb::simple_partitioner());

    // Add the rows in order so the mean is independent of the scheduling.
    SsimOutcome outcome;
    double total = 0.0;
    for (std::size_t y = 0; y < rowSums.size(); ++y) {
        total += rowSums[y];
        outcome.nonFinitePixels += rowNonFinite[y];
    }
    const double count = double(width - 2 * r) * double(height - 2 * r) * double(channels);
    outcome.mean = total / count;
    return outcome;
}

}  // namespace glint::detail

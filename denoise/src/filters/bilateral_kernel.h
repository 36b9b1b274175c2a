// The inner loops shared by "bilateral" (every window pixel) and "bilateral-mc" (a sampled
// subset of the window per pixel, Banterle et al. 2012).
//
// Every kernel evaluates the weight of Tomasi & Manduchi 1998 in base 2 with the constants folded:
//   w(p, q) = 2^(s(q - p) + k |c(q) - c(p)|^2),  s(dx, dy) = -log2(e) (dx^2 + dy^2) / (2 sigmaS^2),
//   k = -log2(e) / (2 sigmaR^2),
// with detail::exp2InPlace (relative error < 3e-6, exactly 0 for exponents <= -127). The squared
// RGB distance is formed from unscaled differences: it overflows to +inf only where the true
// weight is 0 anyway (|c(q) - c(p)| > 1.8e19 with sigmaR <= 1e6) and only underflows where the
// weight is 1 to float precision, so radiance 1e-30 ... 1e30 and sigma 1e-6 ... 1e6 are safe.
#pragma once

#include <cstdint>
#include <vector>

#include "glint/denoise/progress.h"
#include "glint/image/image.h"
#include "glint/image/random.h"

namespace glint::denoise::detail {

struct PlanarPlanes;  // filter_util.h

/// A window offset in pixels.
struct Offset {
    int dx = 0;
    int dy = 0;
};

/// A set of distinct window offsets that one output pixel visits.
struct BilateralPattern {
    std::vector<Offset> offsets;
};

/// Base-2 exponent s of the spatial weight of offset (dx, dy) (formed on scaled offsets, so a tiny
/// sigmaS gives a large negative exponent, never an overflow).
float spatialExponent(int dx, int dy, double sigmaS);

/// The factor k turning a squared RGB distance into a base-2 exponent, -log2(e) / (2 sigmaR^2).
float rangeExponentScale(double sigmaR);

/// Exact bilateral filter over the full (2 radius + 1)^2 window inside `roi`. It computes each
/// pair's weight once and adds it to both pixels (w(p, q) = w(q, p)) within bands of rows fixed in
/// image coordinates, so the result does not depend on the thread count. Bands holding a missing
/// pixel use the one-sided kernel (the non-finite policy needs the centre's validity).
Image bilateralExact(const Image& color, const Rect& roi, int radius, double sigmaS, double sigmaR,
                     WorkContext& work);

/// One-sided bilateral of rows [y0, y1) of `roi` into `out` (the rows of the roi-sized output):
/// every pixel visits the whole window. The fallback of bilateralExact for bands with missing
/// pixels; `planes` must cover roi grown by radius.
void bilateralWindowRows(const PlanarPlanes& planes, const Rect& roi, int y0, int y1, int radius,
                         double sigmaS, double sigmaR, Image& out);

/// Bilateral filter where pixel (x, y) visits patterns[patternIndex(x, y, seed, size)] only.
/// `patterns` must not be empty; its size need not be a power of two.
Image bilateralSampled(const Image& color, const Rect& roi, int radius, double sigmaS,
                       double sigmaR, const std::vector<BilateralPattern>& patterns,
                       std::uint64_t seed, WorkContext& work);

/// Deterministic pseudo-random choice in [0, count) from the image position and the seed
/// (SplitMix64 finaliser), so a region of interest gets the same choices as the full frame.
inline std::uint32_t patternIndex(int x, int y, std::uint64_t seed, std::uint32_t count) {
    const std::uint64_t z = mix64(seed * 0x9E3779B97F4A7C15ull +
                                  (std::uint64_t(std::uint32_t(y)) << 32) + std::uint32_t(x));
    // z mod count; a mask when count is a power of two (the same value, no 64-bit division).
    return std::uint32_t((count & (count - 1)) == 0 ? z & (count - 1) : z % count);
}

}  // namespace glint::denoise::detail

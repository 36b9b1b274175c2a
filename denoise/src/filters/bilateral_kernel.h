// The inner loops shared by "bilateral" (every window pixel) and "bilateral-mc" (a sampled
// subset of the window per pixel, Banterle et al. 2012).
#pragma once

#include <cstdint>
#include <vector>

#include "glint/image/image.h"

namespace glint::denoise::detail {

/// A window offset in pixels.
struct Offset {
    int dx = 0;
    int dy = 0;
};

/// A set of distinct window offsets that one output pixel visits.
struct BilateralPattern {
    std::vector<Offset> offsets;
};

/// Bilateral filter of the 3-channel `color` inside `roi` where every pixel visits the same
/// `pattern` (offsets within [-radius, radius]^2): the exact filter when the pattern is the full
/// window. Weights: spatial Gaussian(sigmaS) x range Gaussian(sigmaR) of the RGB distance.
Image bilateralWindowed(const Image& color, const Rect& roi, int radius, double sigmaS,
                        double sigmaR, const BilateralPattern& pattern);

/// Bilateral filter where pixel (x, y) visits patterns[patternIndex(x, y, seed, size)] only.
/// `patterns` must not be empty; its size need not be a power of two.
Image bilateralSampled(const Image& color, const Rect& roi, int radius, double sigmaS,
                       double sigmaR, const std::vector<BilateralPattern>& patterns,
                       std::uint64_t seed);

/// Deterministic pseudo-random choice in [0, count) from the image position and the seed
/// (SplitMix64 finaliser), so a region of interest gets the same choices as the full frame.
std::uint32_t patternIndex(int x, int y, std::uint64_t seed, std::uint32_t count);

}  // namespace glint::denoise::detail

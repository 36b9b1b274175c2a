// The tile kernel of the "nfor" filter (nfor.cpp): NL-means weights, per-window first-order
// weighted least squares and the collaborative average, on planar float data.
#pragma once

#include <array>
#include <cstddef>
#include <vector>

#include "glint/image/image.h"

namespace glint::denoise::detail {

/// Planes of one cross-filtering pass over a rectangle (image coordinates) that covers the tiles
/// plus the filter's margin and 16 spare columns on the right for the 8-wide loops. Pixels
/// outside the image read as missing.
struct NforPlanes {
    /// Guide colour and its variance of the mean (the NL-means weights), regression target
    /// colour, the 7 features (albedo RGB, normal XYZ, depth / mean |depth|), and two masks:
    /// V = 1 where guide, target and features are all finite, FM = 1 where the features are;
    /// GS: the guide's variance, averaged over the channels and the 3×3 pixels around.
    enum Plane : int { G0, G1, G2, GV0, GV1, GV2, Y0, Y1, Y2, F0, V = F0 + 7, FM, GS, kCount };
    static constexpr int kFeatures = 7;

    Rect rect;
    int stride = 0;
    /// The planes, owned elsewhere (the two cross-filtering passes share all but the colours).
    std::array<const float*, kCount> planes{};
    /// The guide's typical GS (the frame's median of the positive GS; 0 when there is none).
    float typicalVariance = 0.0f;

    std::size_t index(int x, int y) const {
        return std::size_t(y - rect.y0) * std::size_t(stride) + std::size_t(x - rect.x0);
    }
    const float* at(int plane, std::size_t i) const { return planes[std::size_t(plane)] + i; }
};

/// Settings of the kernel, from the filter's parameters.
struct NforSettings {
    int r = 5;            ///< window radius
    int f = 3;            ///< patch radius
    float k2 = 0.25f;     ///< squared NL-means strength
    double ridge = 1e-3;  ///< ridge, relative to the window's weight sum
    /// Weights are scaled by min(1, rho (GS_min + t) / (GS_max + t)) over the pair's two GS, t
    /// the typical one: a neighbour far noisier than the centre (or far quieter) is let in less.
    float varianceRatio = 4.0f;
};

/// Per-thread scratch buffers of the kernel.
struct NforScratch {
    std::vector<float> weights;  // (2r+1)^2 weight images over the tile grown by r
    std::vector<float> dist, vert;
    std::vector<float> moments;  // 60 accumulator rows of one row of the grown tile
    std::vector<float> zeros;    // a row of zero weights
    std::vector<float> beta;     // 24 coefficient planes + validity over the grown tile
};

/// Filters the tile with top-left (tx0, ty0) and size tw × th (at most `tile` on a side): the
/// collaborative first-order estimate of the target colour, 3 planes of tile × tile floats into
/// `out` (row stride `tile`).
void nforTile(const NforPlanes& pk, int tx0, int ty0, int tw, int th, int tile,
              const NforSettings& st, NforScratch& sc, float* out);

}  // namespace glint::denoise::detail

// Film: per-pixel running statistics in double (Welford 1962) of colour and features, box filter
// (each sample belongs to the pixel it was taken in), NaN/Inf samples discarded and counted.
#pragma once

#include <cstdint>
#include <vector>

#include "glint/image/frame_buffers.h"
#include "glint/image/large_pages.h"
#include "glint/render/settings.h"
#include "vecmath.h"

namespace glint::render {

/// What one camera sample contributes to its pixel.
struct FilmSample {
    Vec3 color;
    Vec3 albedo;         ///< at the first non-specular hit (0 if none)
    Vec3 normal;         ///< world shading normal there (0 if none)
    float depth = 0.0f;  ///< camera-space z there (0 if none)
    Vec3 position;       ///< world position there (0 if none)
};

/// Accumulates FilmSamples per pixel. A pixel must only be written by one thread at a time.
class Film {
  public:
    /// With `halfBuffers`, also the statistics of each pixel's second half of samples alone
    /// (the half-buffer layers; add() says which samples belong to it). `keepHalf` keeps those
    /// statistics without writing them (adaptive sampling's error from half B).
    Film(int width, int height, bool halfBuffers = false, bool keepHalf = false);

    int width() const { return m_width; }
    int height() const { return m_height; }
    /// Adds a sample to pixel (x, y); a sample with any non-finite value is counted and dropped.
    /// `secondHalf`: the sample also goes into half B's statistics (with half buffers).
    void add(int x, int y, const FilmSample& sample, bool secondHalf = false);
    /// Samples accepted in pixel (x, y).
    std::uint32_t count(int x, int y) const { return m_pixels[index(x, y)].n; }
    /// Samples taken in pixel (x, y), the discarded non-finite ones included: the index of the
    /// pixel's next sample.
    std::uint32_t taken(int x, int y) const {
        const Pixel& p = m_pixels[index(x, y)];
        return p.n + p.nonFinite;
    }
    /// Adaptive sampling's estimate of pixel (x, y)'s error, on the scale of Cycles' noise
    /// threshold (docs/renderer.md, "Adaptive sampling"): the expected |I − A| of Cycles'
    /// estimator, √(2/π) Σc SEc, over 1e-4 + √(Σc μc), from the colour's standard errors of the
    /// mean SEc and means μc of every sample (`from` Whole) or of half B alone, its standard
    /// errors scaled to the whole's count (Half; needs half statistics). Infinite below two
    /// samples.
    double adaptiveError(int x, int y, AdaptiveError from) const;
    /// Takes a resolved frame's statistics as the film's (Settings::continueFrom, checked by
    /// checkContinuedFrame): per pixel its means, variances of the mean and sample counts, and
    /// half B's when the film keeps them; the position's mean when the frame has one (its
    /// spread is not in a frame: the position layer has no variance). The next sample of a pixel
    /// is then its count (the frame discarded none).
    void continueFrom(const FrameBuffers& frame);
    /// Total discarded (non-finite) samples.
    std::int64_t nonFiniteSamples() const;
    /// Means, variances of the mean (sample variance / n; 0 below two samples), sample counts,
    /// and the same for half B in the half-buffer layers when the film has them. When some
    /// pixel's variance is below float's normal range, the metadata's
    /// extra[kVarianceUnderflowKey] counts those pixels.
    FrameBuffers resolve(bool withPosition) const;

    /// Bytes of running statistics per pixel.
    static constexpr std::uint64_t bytesPerPixel(bool halfBuffers = false) {
        return sizeof(Pixel) * (halfBuffers ? 2 : 1);
    }

  private:
    static constexpr int kChannels = 13;  // colour 3, albedo 3, normal 3, depth 1, position 3
    struct Pixel {
        std::uint32_t n = 0;
        std::uint32_t nonFinite = 0;
        double mean[kChannels] = {};
        double m2[kChannels] = {};
    };
    std::size_t index(int x, int y) const { return std::size_t(y) * std::size_t(m_width) + x; }

    int m_width, m_height;
    using Pixels = std::vector<Pixel, LargePageAllocator<Pixel>>;
    Pixels m_pixels;
    Pixels m_half;       ///< half B's statistics; empty without half buffers
    bool m_writeHalves;  ///< resolve() writes the half-buffer layers
};

}  // namespace glint::render

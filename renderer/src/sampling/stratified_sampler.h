// The stratified and independent samplers of the path tracer: the camera's numbers placed by a
// pass-wide pattern (jittered strata drawn without repetition), every other number the next of
// the sample's (seed, pixel, sample) stream in reading order.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "glint/render/settings.h"
#include "sampling/rng.h"
#include "sampling/sampler.h"
#include "vecmath.h"

namespace glint::render {

/// Pixel-sample placement of one pass: `count` samples starting at `first`, stratified over a
/// jittered grid (one random cell of a ceil(√n) × ⌈n/⌈√n⌉⌉ grid per sample, cells drawn without
/// repetition by a per-pixel permutation) or independent.
struct StratifiedPattern {
    SamplerKind kind;
    std::uint64_t seed;
    int first, count, nx, ny;

    StratifiedPattern(SamplerKind k, std::uint64_t s, int firstSample, int n)
        : kind(k), seed(s), first(firstSample), count(n) {
        nx = int(std::ceil(std::sqrt(double(n))));
        ny = (n + nx - 1) / nx;
    }

    /// Stratified 2D point for sample `sample` of pixel `pixel` in dimension pair `dim`.
    Vec2 point(std::uint64_t pixel, int sample, int dim, Rng& rng) const {
        const Vec2 jitter{rng.uniform(), rng.uniform()};
        if (kind == SamplerKind::Independent || count == 1) return jitter;
        const auto key = std::uint32_t(mix64(streamKey(seed, pixel, std::uint64_t(first)) +
                                             std::uint64_t(dim) * 0x2545f491ULL));
        const std::uint32_t cell =
            permuteIndex(std::uint32_t(sample - first), std::uint32_t(nx * ny), key);
        const int cx = int(cell % std::uint32_t(nx)), cy = int(cell / std::uint32_t(nx));
        return {std::min((float(cx) + jitter.x) / float(nx), 0x1.fffffep-1f),
                std::min((float(cy) + jitter.y) / float(ny), 0x1.fffffep-1f)};
    }

    /// Stratified 1D value for sample `sample` of pixel `pixel` in dimension `dim`: one random
    /// stratum of `count` per sample, drawn without repetition by its own permutation.
    float value(std::uint64_t pixel, int sample, int dim, Rng& rng) const {
        const float jitter = rng.uniform();
        if (kind == SamplerKind::Independent || count == 1) return jitter;
        const auto key = std::uint32_t(mix64(streamKey(seed, pixel, std::uint64_t(first)) +
                                             std::uint64_t(dim) * 0x2545f491ULL));
        const std::uint32_t stratum =
            permuteIndex(std::uint32_t(sample - first), std::uint32_t(count), key);
        return std::min((float(stratum) + jitter) / float(count), 0x1.fffffep-1f);
    }
};

/// The sampler of sample `sample` of pixel `pixel` under a pass's pattern (which must outlive
/// it): a stream sampler, every number drawn from the stream (seed, pixel, sample) in the order
/// the camera and the path read them.
class StratifiedSampler {
  public:
    static constexpr bool kSlotted = false;

    StratifiedSampler(const StratifiedPattern& pattern, std::uint64_t seed, std::uint64_t pixel,
                      int sample)
        : m_pattern(&pattern),
          m_rng(seed, pixel, std::uint64_t(sample)),
          m_pixel(pixel),
          m_sample(sample) {}

    /// Camera pair `dim` (0 film, 1 lens) and number `dim` (2 time), placed by the pattern.
    Vec2 camera2D(int dim) { return m_pattern->point(m_pixel, m_sample, dim, m_rng); }
    float camera1D(int dim) { return m_pattern->value(m_pixel, m_sample, dim, m_rng); }

    /// The next number(s) of the stream, whatever the bounce and slot.
    float bounce1D(int /*depth*/, BounceDim /*slot*/) { return m_rng.uniform(); }
    Vec2 bounce2D(int /*depth*/, BounceDim /*slot*/) {
        const float u = m_rng.uniform();
        return {u, m_rng.uniform()};
    }

  private:
    const StratifiedPattern* m_pattern;
    Rng m_rng;
    std::uint64_t m_pixel;
    int m_sample;
};

static_assert(PixelSampler<StratifiedSampler>);

}  // namespace glint::render

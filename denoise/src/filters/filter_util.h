// Shared private helpers for the filters in src/filters/ (owner: denoise A; any filter may use
// them, e.g. cross_bilateral.cpp, guided.cpp, nlmeans.cpp, src/prefilter/).
//
//   paramValue / paramInt      read a resolved parameter (throws Internal if absent).
//   expandRect                 roi grown by a margin, clipped to the image.
//   isFinitePixel              the non-finite policy test (see below).
//   parallelRows(y0, y1, fn)   TBB parallel-for over rows; fn(int y) runs once per row.
//   PlanarPlanes               planar float copy of an interleaved image over a rectangle that may
//                              reach outside the image, with a 0/1 validity plane and padding
//                              columns so 8-wide SIMD loads never leave the buffer.
//   VecF / VecI / loadVec / storeVec / expNegInPlace
//                              8-wide GCC vector-extension helpers; expNegInPlace computes
//                              exp(x) for x <= 0 to ~6e-6 relative error (exactly 0 below -87).
//   GLINT_SIMD_CLONES          put on a hot kernel function: GCC builds an x86-64-v3 (AVX2+FMA)
//                              clone and a baseline clone and picks one at load time.
//
// Non-finite policy shared by all filters (tested by tests/denoise/filter_properties_test.cpp):
// an input pixel with a NaN or Inf in any colour channel is *missing*: it gets zero weight as a
// neighbour, so it cannot influence any output pixel, and its own output is the normalised
// average of the finite neighbours its kernel reaches (range terms that need the centre's value
// are dropped for it). When a kernel reaches no finite pixel at all, the output is 0. Hence the
// output is finite everywhere and equals the clean-input output beyond the filter's margin.
#pragma once

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "glint/denoise/filter.h"
#include "glint/image/error.h"
#include "glint/image/image.h"

namespace glint::denoise::detail {

/// The resolved value of parameter `name` (resolveParams guarantees presence).
inline double paramValue(const ParamValues& params, const std::string& name) {
    auto it = params.find(name);
    GLINT_CHECK(it != params.end(), "parameter not resolved");
    return it->second;
}

/// The resolved value of integer parameter `name`.
inline int paramInt(const ParamValues& params, const std::string& name) {
    return int(std::lround(paramValue(params, name)));
}

/// `roi` grown by `margin` on every side and clipped to `bounds`.
inline Rect expandRect(const Rect& roi, int margin, const Rect& bounds) {
    return intersect(Rect{roi.x0 - margin, roi.x1 + margin, roi.y0 - margin, roi.y1 + margin},
                     bounds);
}

/// True when the `channels` values at `p` are all finite (the non-finite policy above).
inline bool isFinitePixel(const float* p, int channels) {
    for (int c = 0; c < channels; ++c)
        if (!std::isfinite(p[c])) return false;
    return true;
}

/// Runs fn(y) for every y in [y0, y1) in parallel (TBB), a few rows per task.
template <class Fn>
void parallelRows(int y0, int y1, const Fn& fn) {
    if (y1 <= y0) return;
    tbb::parallel_for(tbb::blocked_range<int>(y0, y1), [&](const tbb::blocked_range<int>& r) {
        for (int y = r.begin(); y != r.end(); ++y) fn(y);
    });
}

/// Planar copy of the first `channels` channels of an image over `rect` (which may extend past
/// the image). Pixels outside the image or non-finite read as value 0 with valid 0.
struct PlanarPlanes {
    static constexpr int kPad = 8;  ///< extra missing columns on the right for SIMD tails
    Rect rect;                      ///< covered region, image coordinates
    int stride = 0;                 ///< floats per plane row (rect.width() + kPad)
    int channels = 0;
    std::vector<std::vector<float>> planes;  ///< channel planes
    std::vector<float> valid;                ///< 1 for a finite pixel inside the image, else 0

    /// Index of image pixel (x, y) in the planes; (x, y) must lie in rect.
    std::size_t index(int x, int y) const {
        return std::size_t(y - rect.y0) * std::size_t(stride) + std::size_t(x - rect.x0);
    }
};

/// Builds the planar copy of `image` (first `channels` channels) over `rect`; parallel over rows.
inline PlanarPlanes makePlanar(const Image& image, const Rect& rect, int channels) {
    PlanarPlanes p;
    p.rect = rect;
    p.stride = rect.width() + PlanarPlanes::kPad;
    p.channels = channels;
    const std::size_t size = std::size_t(p.stride) * std::size_t(std::max(0, rect.height()));
    p.planes.assign(std::size_t(channels), std::vector<float>(size, 0.0f));
    p.valid.assign(size, 0.0f);
    const int x0 = std::max(rect.x0, 0), x1 = std::min(rect.x1, image.width());
    const int y0 = std::max(rect.y0, 0), y1 = std::min(rect.y1, image.height());
    const int ic = image.channels();
    parallelRows(y0, y1, [&](int y) {
        const float* src = image.row(y);
        for (int x = x0; x < x1; ++x) {
            const float* px = src + std::size_t(x) * ic;
            if (!isFinitePixel(px, channels)) continue;
            const std::size_t i = p.index(x, y);
            for (int c = 0; c < channels; ++c) p.planes[std::size_t(c)][i] = px[c];
            p.valid[i] = 1.0f;
        }
    });
    return p;
}

// 8-wide float / int vectors (GCC vector extensions). Pass them by reference only, so that no
// function's ABI depends on whether AVX is enabled.
typedef float VecF __attribute__((vector_size(32)));
typedef int VecI __attribute__((vector_size(32)));

/// Unaligned load of 8 floats.
[[gnu::always_inline]] inline void loadVec(VecF& v, const float* p) {
    std::memcpy(&v, p, sizeof v);
}

/// Unaligned store of 8 floats.
[[gnu::always_inline]] inline void storeVec(float* p, const VecF& v) {
    std::memcpy(p, &v, sizeof v);
}

/// x <- exp(x) for x <= 0, lane-wise: 2^(x log2 e) = 2^n 2^f with n = round(x log2 e) found by
/// the 1.5 * 2^23 magic-number trick and 2^f, f in [-1/2, 1/2], by a degree-5 Taylor polynomial
/// (relative error < 6e-6, from rounding x log2 e to float); lanes below -87 give 0.
[[gnu::always_inline]] inline void expNegInPlace(VecF& x) {
    constexpr float kMagic = 12582912.0f;  // 1.5 * 2^23: adding it rounds to an integer
    const VecI underflow = x < -87.0f;
    const VecF t = (underflow ? VecF{} - 87.0f : x) * 1.44269504f;
    const VecF shifted = t + kMagic;
    const VecF f = t - (shifted - kMagic);
    VecF p = VecF{} + 1.3333558e-3f;
    p = p * f + 9.6181291e-3f;
    p = p * f + 5.5504109e-2f;
    p = p * f + 2.4022651e-1f;
    p = p * f + 6.9314718e-1f;
    p = p * f + 1.0f;
    VecI bits;
    std::memcpy(&bits, &shifted, sizeof bits);
    bits = (bits - 0x4B400000 + 127) << 23;  // 0x4B400000 is the bit pattern of kMagic
    VecF scale;
    std::memcpy(&scale, &bits, sizeof scale);
    x = underflow ? VecF{} : p * scale;
}

}  // namespace glint::denoise::detail

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define GLINT_SIMD_CLONES __attribute__((target_clones("arch=x86-64-v3", "default")))
#else
#define GLINT_SIMD_CLONES
#endif

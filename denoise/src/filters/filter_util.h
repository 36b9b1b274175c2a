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
//   VecF / VecI / loadVec / storeVec / expNegInPlace / exp2InPlace
//                              8-wide GCC vector-extension helpers; expNegInPlace computes
//                              exp(x) for x <= 0 to ~6e-6 relative error (exactly 0 below -87);
//                              exp2InPlace computes 2^x for x <= 0 to 3.6e-6 relative error
//                              (exactly 1 at 0, exactly 0 at or below -127) in fewer operations.
//   GLINT_SIMD_CLONES          put on a hot kernel function: GCC builds an x86-64-v3 (AVX2+FMA)
//                              clone and a baseline clone and picks one at load time.
//   GLINT_SIMD_CLONES_V4       the same plus an x86-64-v4 (AVX-512) clone: still 8-wide vectors,
//                              but 32 vector registers (no spills in kernels with many live sums).
//                              Defining GLINT_SIMD_BASELINE_ONLY or GLINT_SIMD_V3_ONLY (test
//                              builds) compiles only the baseline or only the AVX2 version.
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

/// x <- 2^x for x <= 0, lane-wise (V: a float vector type such as VecF): 2^n 2^f with n = round(x)
/// by the 1.5 * 2^23 magic-number trick and 2^f, f in [-1/2, 1/2], by 1 + f q(f) with q of degree
/// 3, fitted for minimax relative error (3.6e-6; exactly 1 at x = 0, so a lone centre weight is
/// exactly 1). Lanes at or below -127 (and -inf) give exactly 0: the clamp makes n = -127, whose
/// biased exponent field is 0. Callers fold log2(e) into their constants, so a Gaussian weight
/// exp(-a) costs two multiply-adds less than with expNegInPlace.
template <class V>
[[gnu::always_inline]] inline void exp2InPlace(V& x) {
    typedef unsigned U __attribute__((vector_size(sizeof(V))));
    typedef int I __attribute__((vector_size(sizeof(V))));
    constexpr float kMagic = 12582912.0f;  // 1.5 * 2^23: adding it rounds to an integer
    // Clamp at -127 on the bit patterns: for x <= 0 (and -0, -inf) the unsigned pattern grows
    // with |x|, so the clamp is one unsigned minimum (a single vpminud) instead of a compare
    // and a blend.
    constexpr unsigned kMinus127 = 0xC2FE0000u;  // bit pattern of -127.0f
    U u;
    std::memcpy(&u, &x, sizeof u);
    u = u > kMinus127 ? U{} + kMinus127 : u;
    V t;
    std::memcpy(&t, &u, sizeof t);
    const V shifted = t + kMagic;
    const V f = t - (shifted - kMagic);
    V q = V{} + 9.782912210e-3f;
    q = q * f + 5.597688258e-2f;
    q = q * f + 2.402071059e-1f;
    q = q * f + 6.931136250e-1f;
    const V p = q * f + 1.0f;
    I bits;
    std::memcpy(&bits, &shifted, sizeof bits);
    bits = (bits - (0x4B400000 - 127)) << 23;  // 0x4B400000 is the bit pattern of kMagic
    V scale;
    std::memcpy(&scale, &bits, sizeof scale);
    x = p * scale;
}

/// The shared tail of the bilateral kernels: turns base-2 log-weights `w` of 8 samples into
/// weights 2^w times their validity `qv` and adds the weighted colours and weights to the sums.
[[gnu::always_inline]] inline void addWeightedSamples(VecF w, const VecF& qr, const VecF& qg,
                                                      const VecF& qb, const VecF& qv, VecF& nr,
                                                      VecF& ng, VecF& nb, VecF& den) {
    exp2InPlace(w);
    w *= qv;
    nr += w * qr;
    ng += w * qg;
    nb += w * qb;
    den += w;
}

}  // namespace glint::denoise::detail

#if defined(GLINT_SIMD_BASELINE_ONLY)  // test builds: only the baseline code paths
#define GLINT_SIMD_CLONES
#define GLINT_SIMD_CLONES_V4
#elif defined(GLINT_SIMD_V3_ONLY)  // test builds: only the x86-64-v3 (AVX2) code paths
#define GLINT_SIMD_CLONES __attribute__((target("arch=x86-64-v3")))
#define GLINT_SIMD_CLONES_V4 __attribute__((target("arch=x86-64-v3")))
#elif defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define GLINT_SIMD_CLONES __attribute__((target_clones("arch=x86-64-v3", "default")))
#define GLINT_SIMD_CLONES_V4 \
    __attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default")))
#else
#define GLINT_SIMD_CLONES
#define GLINT_SIMD_CLONES_V4
#endif

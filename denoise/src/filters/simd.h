// 8-wide SIMD helpers for the filter kernels (GCC vector extensions), private to denoise/. The
// vectors, their loads and stores and the GLINT_SIMD_CLONES / GLINT_SIMD_CLONES_V4 markers are
// image/'s (glint/image/internal/simd.h); here the kernels' own:
//
//   expNegInPlace / exp2InPlace
//                              expNegInPlace computes exp(x) for x <= 0 to ~6e-6 relative error
//                              (exactly 0 below -87); exp2InPlace computes 2^x for x <= 0 to
//                              3.6e-6 relative error (exactly 1 at 0, exactly 0 at or below -127)
//                              in fewer operations.
//   addWeightedSamples         the weight-and-accumulate tail of the bilateral kernels.
#pragma once

#include <cstring>

#include "glint/image/internal/simd.h"

namespace glint::denoise::detail {

using glint::detail::loadVec;
using glint::detail::storeVec;
using glint::detail::VecF;
using glint::detail::VecI;

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

// 8-wide SIMD helpers for the filter kernels (GCC vector extensions), private to denoise/.
//
//   VecF / VecI / loadVec / storeVec / expNegInPlace / exp2InPlace
//                              8-wide GCC vector-extension helpers; expNegInPlace computes
//                              exp(x) for x <= 0 to ~6e-6 relative error (exactly 0 below -87);
//                              exp2InPlace computes 2^x for x <= 0 to 3.6e-6 relative error
//                              (exactly 1 at 0, exactly 0 at or below -127) in fewer operations.
//   addWeightedSamples         the weight-and-accumulate tail of the bilateral kernels.
//   GLINT_SIMD_CLONES          put on a hot kernel function: GCC builds an x86-64-v3 (AVX2+FMA)
//                              clone and a baseline clone and picks one at load time.
//   GLINT_SIMD_CLONES_V4       the same plus an x86-64-v4 (AVX-512) clone: still 8-wide vectors,
//                              but 32 vector registers (no spills in kernels with many live sums).
//                              Defining GLINT_SIMD_BASELINE_ONLY or GLINT_SIMD_V3_ONLY (test
//                              builds) compiles only the baseline or only the AVX2 version.
#pragma once

#include <cstring>

namespace glint::denoise::detail {

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

// 8-wide SIMD helpers (GCC vector extensions) that image/ (SSIM, FLIP) and denoise/ (the filter
// kernels, denoise/src/filters/simd.h) share; never installed.
//
//   VecF / VecI / loadVec / storeVec
//                         8 floats / ints, loaded and stored unaligned. Pass vectors by
//                         reference only, so that no function's ABI depends on whether AVX is
//                         enabled.
//   GLINT_SIMD_CLONES     put on a hot kernel function: GCC builds an x86-64-v3 (AVX2+FMA) clone
//                         and a baseline clone and picks one at load time; elsewhere a no-op.
//   GLINT_SIMD_CLONES_V4  the same plus an x86-64-v4 (AVX-512) clone: still 8-wide vectors, but
//                         32 vector registers (no spills in kernels with many live sums).
//                         Defining GLINT_SIMD_BASELINE_ONLY or GLINT_SIMD_V3_ONLY (test builds)
//                         compiles only the baseline or only the AVX2 version.
#pragma once

#include <cstring>

namespace glint::detail {

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

}  // namespace glint::detail

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

// 8-wide SIMD helpers private to image/ (GCC vector extensions).
//
//   GLINT_SIMD_CLONES  put on a hot kernel function: GCC builds an x86-64-v3 (AVX2+FMA) clone
//                      and a baseline clone and picks one at load time; elsewhere a no-op.
//   Vec8f, load8, store8
//                      8 floats, loaded and stored unaligned. Pass vectors by reference only,
//                      so that no function's ABI depends on whether AVX is enabled.
#pragma once

#include <cstring>

#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
#define GLINT_SIMD_CLONES __attribute__((target_clones("arch=x86-64-v3", "default")))
#else
#define GLINT_SIMD_CLONES
#endif

namespace glint::detail {

typedef float Vec8f __attribute__((vector_size(32)));

/// Unaligned load of 8 floats.
[[gnu::always_inline]] inline void load8(Vec8f& v, const float* p) {
    std::memcpy(&v, p, sizeof v);
}

/// Unaligned store of 8 floats.
[[gnu::always_inline]] inline void store8(float* p, const Vec8f& v) {
    std::memcpy(p, &v, sizeof v);
}

}  // namespace glint::detail

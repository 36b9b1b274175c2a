// IEEE 754 binary16 ("half") to float, by bit manipulation: no table (Imath's half → float goes
// through a 256 KB table unless built for F16C, which costs cache misses in texture filtering).
#pragma once

#include <bit>
#include <cstdint>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace glint::render::detail {

/// The float a half's bits stand for: normals, subnormals, ±0, ±infinity and NaN alike.
inline float halfToFloat(std::uint16_t bits) {
    // Exponent and mantissa moved to a float's places; the exponent then rebiased (15 → 127).
    const std::uint32_t magnitude = std::uint32_t(bits & 0x7fffu) << 13;
    const std::uint32_t exponent = magnitude & 0x0f800000u;
    std::uint32_t out = magnitude + (std::uint32_t(127 - 15) << 23);
    if (exponent == 0x0f800000u) {
        out += std::uint32_t(128 - 16) << 23;  // infinity or NaN: the largest exponent
    } else if (exponent == 0) {
        // A subnormal (or zero): as a normal of exponent 1, less that normal's implicit one.
        out += 1u << 23;
        out = std::bit_cast<std::uint32_t>(std::bit_cast<float>(out) -
                                           std::bit_cast<float>(113u << 23));
    }
    return std::bit_cast<float>(out | (std::uint32_t(bits & 0x8000u) << 16));
}

#if defined(__SSE2__)
/// halfToFloat on the four halves at `p` (one RGBA texel) at once, in SSE2 (every x86-64).
inline __m128 halfToFloat4(const std::uint16_t* p) {
    const __m128i h = _mm_unpacklo_epi16(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(p)),
                                         _mm_setzero_si128());
    const __m128i magnitude = _mm_slli_epi32(_mm_and_si128(h, _mm_set1_epi32(0x7fff)), 13);
    const __m128i exponent = _mm_and_si128(magnitude, _mm_set1_epi32(0x0f800000));
    __m128i out = _mm_add_epi32(magnitude, _mm_set1_epi32((127 - 15) << 23));
    const __m128i infNan = _mm_cmpeq_epi32(exponent, _mm_set1_epi32(0x0f800000));
    out = _mm_add_epi32(out, _mm_and_si128(infNan, _mm_set1_epi32((128 - 16) << 23)));
    const __m128i subnormal = _mm_cmpeq_epi32(exponent, _mm_setzero_si128());
    const __m128 renormalised =
        _mm_sub_ps(_mm_castsi128_ps(_mm_add_epi32(out, _mm_set1_epi32(1 << 23))),
                   _mm_castsi128_ps(_mm_set1_epi32(113 << 23)));
    out = _mm_or_si128(_mm_andnot_si128(subnormal, out),
                       _mm_and_si128(subnormal, _mm_castps_si128(renormalised)));
    out = _mm_or_si128(out, _mm_slli_epi32(_mm_and_si128(h, _mm_set1_epi32(0x8000)), 16));
    return _mm_castsi128_ps(out);
}
#endif

}  // namespace glint::render::detail

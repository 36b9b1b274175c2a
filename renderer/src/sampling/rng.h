// Counter-based random streams: every (seed, pixel, sample) triple names an independent stream,
// so a pixel's samples do not depend on which thread renders them or in which order.
#pragma once

#include <cstdint>

#include "glint/image/random.h"

namespace glint::render {

using glint::mix64;

/// Stream key of (seed, pixel, sample): nested mixing so nearby triples decorrelate.
inline std::uint64_t streamKey(std::uint64_t seed, std::uint64_t pixel, std::uint64_t sample) {
    std::uint64_t k = mix64(seed + 0x9e3779b97f4a7c15ULL);
    k = mix64(k ^ (pixel * 0xd1b54a32d192ed03ULL + 0x8bb84b93962eacc9ULL));
    return mix64(k ^ (sample * 0xaef17502108ef2d9ULL + 0x4f1bbcdcbfa53e0bULL));
}

/// A counter-based generator: the SplitMix64 sequence (glint/image/random.h) started at the
/// stream key, so value i of the stream is mix64(key + (i + 1) × golden ratio).
class Rng {
  public:
    explicit Rng(std::uint64_t key) : m_gen(key) {}
    Rng(std::uint64_t seed, std::uint64_t pixel, std::uint64_t sample)
        : m_gen(streamKey(seed, pixel, sample)) {}

    /// Next 64 random bits.
    std::uint64_t nextU64() { return m_gen.next(); }
    /// Next 32 random bits.
    std::uint32_t nextU32() { return std::uint32_t(nextU64() >> 32); }
    /// Uniform float in [0, 1) with 24 random bits.
    float uniform() { return m_gen.uniformFloat(); }
    /// Uniform double in [0, 1) with 53 random bits.
    double uniformDouble() { return m_gen.uniformDouble(); }

  private:
    SplitMix64 m_gen;
};

/// A pseudo-random permutation of [0, n) evaluated at i (bijective hash on the enclosing power
/// of two with cycle walking, in the spirit of Kensler 2013, "Correlated Multi-Jittered
/// Sampling"). Requires i < n.
inline std::uint32_t permuteIndex(std::uint32_t i, std::uint32_t n, std::uint32_t key) {
    if (n <= 1) return 0;
    std::uint32_t mask = n - 1;
    mask |= mask >> 1, mask |= mask >> 2, mask |= mask >> 4, mask |= mask >> 8, mask |= mask >> 16;
    do {
        // Each step is a bijection of [0, mask]: xor, odd multiply, xorshift (all mod 2^bits).
        i ^= key & mask;
        i = (i * 0x9e3779b1u) & mask;
        i ^= (i & mask) >> 3;
        i = (i * 0x85ebca6bu + (key >> 8)) & mask;
        i ^= (i & mask) >> 5;
        i = (i * 0xc2b2ae35u) & mask;
        i ^= (i & mask) >> 7;
    } while (i >= n);
    return i;
}

}  // namespace glint::render

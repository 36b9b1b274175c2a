// Deterministic hashing and a small generator shared by every module: the SplitMix64 finaliser
// and sequence (Steele, Lea & Flood 2014). The same numbers on every platform and thread count.
#pragma once

#include <cstdint>

namespace glint {

/// SplitMix64 finaliser: a bijective 64-bit avalanche mix.
inline std::uint64_t mix64(std::uint64_t z) {
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}

/// Hash of two integers (e.g. a seed and an index) to 64 bits.
inline std::uint64_t hash64(std::uint64_t a, std::uint64_t b) {
    return mix64(mix64(a + 0x9e3779b97f4a7c15ULL) ^ (b * 0xd1b54a32d192ed03ULL));
}

/// The SplitMix64 sequence: value i is mix64(state + (i + 1) × golden ratio).
class SplitMix64 {
  public:
    explicit SplitMix64(std::uint64_t state) : m_state(state) {}

    /// Next 64 random bits.
    std::uint64_t next() {
        m_state += 0x9e3779b97f4a7c15ULL;
        return mix64(m_state);
    }
    /// Uniform double in [0, 1) with 53 random bits.
    double uniformDouble() { return double(next() >> 11) * 0x1p-53; }
    /// Uniform float in [0, 1) with 24 random bits.
    float uniformFloat() { return float(next() >> 40) * 0x1p-24f; }
    /// Integer in [0, n) (n > 0; modulo bias below 2^-40 for n < 2^24).
    std::uint64_t below(std::uint64_t n) { return next() % n; }

  private:
    std::uint64_t m_state;
};

}  // namespace glint

// Owen-scrambled Sobol sampling over every path dimension (Burley 2020, "Practical Hash-based
// Owen Scrambling"): each dimension pair of a pixel takes the first two Sobol dimensions — a
// (0,2)-sequence — at a shuffled sample index, nested-uniform scrambled by hashes of (seed,
// pixel, dimension). Shuffling the index per pair decorrelates the pairs ("padding"); scrambling
// per pixel decorrelates the pixels. A sample's numbers depend only on (seed, pixel, sample
// index, dimension), so passes of any size add up to the same estimate, and the first 2^m
// samples of every pair are a (0,m,2)-net (docs/renderer.md, "Sampling").
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "glint/image/random.h"
#include "sampling/sampler.h"
#include "vecmath.h"

namespace glint::render {

/// The bits of x in reverse order.
constexpr std::uint32_t reverseBits(std::uint32_t x) {
    // Bytes swapped in one instruction, then the bits inside each byte.
    x = __builtin_bswap32(x);
    x = ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
    x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
    return ((x >> 4) & 0x0f0f0f0fu) | ((x & 0x0f0f0f0fu) << 4);
}

/// The first Sobol dimension: the van der Corput radical inverse in base 2, as 32 bits.
inline std::uint32_t sobol0(std::uint32_t index) {
    return reverseBits(index);
}

namespace detail {
/// The generator matrix of the second Sobol dimension (primitive polynomial x + 1, all direction
/// numbers m_k = 1): columns v_1 = 2^31, v_k = v_{k-1} xor (v_{k-1} >> 1) (Bratley and Fox 1988),
/// applied a byte of the index at a time: table[b][x] is the xor of the columns of the set bits
/// of byte value x in byte b. With `reversed`, the table of reverseBits(sobol1(i)) (every
/// column bit-reversed), the form the scramble of sobol2D takes.
constexpr std::array<std::array<std::uint32_t, 256>, 4> sobol1Tables(bool reversed) {
    std::array<std::uint32_t, 32> column{};
    column[0] = 1u << 31;
    for (int k = 1; k < 32; ++k) column[k] = column[k - 1] ^ (column[k - 1] >> 1);
    std::array<std::array<std::uint32_t, 256>, 4> table{};
    for (int b = 0; b < 4; ++b)
        for (int x = 0; x < 256; ++x)
            for (int bit = 0; bit < 8; ++bit)
                if (x & (1 << bit)) {
                    const int j = 8 * b + bit;
                    table[b][x] ^= reversed ? reverseBits(column[j]) : column[j];
                }
    return table;
}
inline constexpr auto kSobol1 = sobol1Tables(false);
inline constexpr auto kSobol1Reversed = sobol1Tables(true);

/// xor of table[b][byte b of x] over the four bytes.
inline std::uint32_t byTable(const std::array<std::array<std::uint32_t, 256>, 4>& t,
                             std::uint32_t x) {
    return t[0][x & 0xffu] ^ t[1][(x >> 8) & 0xffu] ^ t[2][(x >> 16) & 0xffu] ^ t[3][x >> 24];
}
}  // namespace detail

/// The second Sobol dimension; with sobol0 a (0,2)-sequence in base 2. A shuffled index uses all
/// 32 bits, so the matrix is applied by table, four lookups.
inline std::uint32_t sobol1(std::uint32_t index) {
    return detail::byTable(detail::kSobol1, index);
}

/// Laine and Karras' hash-based Owen permutation of bit-reversed values, with Burley's (2020,
/// sec. 3) constants: each output bit flips by a hash of the bits below it, which in reversed
/// order are the bits above it, i.e. a nested uniform scramble.
inline std::uint32_t laineKarrasPermutation(std::uint32_t x, std::uint32_t seed) {
    x ^= x * 0x3d20adeau;
    x += seed;
    x *= (seed >> 16) | 1u;
    x ^= x * 0x05526c56u;
    x ^= x * 0x53a22864u;
    return x;
}

/// A 32-bit fixed-point value as a float in [0, 1) (top 24 bits, exact).
inline float fixedToFloat(std::uint32_t x) {
    return float(x >> 8) * 0x1p-24f;
}

/// A 32-bit integer hash (Wellons' lowbias32): full avalanche at the cost of two multiplies.
inline std::uint32_t hash32(std::uint32_t x) {
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    x ^= x >> 16;
    return x;
}

/// Point `index` of Owen-scrambled Sobol dimensions (0, 1) for the scramble seed `seed`: the
/// index is shuffled by a nested uniform scramble (which maps each aligned block of 2^m indices
/// onto an aligned block, so prefixes of 2^m points stay (0,m,2)-nets), then each coordinate is
/// scrambled with its own seed.
///
/// Written with the reversals cancelled: the scramble of sobol0(i) = rev(i) is
/// rev(LK(i, t)), and rev(sobol1(i)) comes from a table of i's bytes, so a pair costs four bit
/// reversals instead of nine.
/// `reversedIndex` is reverseBits(index), the same for every dimension of a sample.
inline Vec2 sobol2DReversed(std::uint32_t reversedIndex, std::uint64_t seed) {
    const auto s = std::uint32_t(seed), t = std::uint32_t(seed >> 32);
    const std::uint32_t u = t * 0x2c1b3c6du + 0x297a2d39u;  // the y scramble: another odd map of t
    const std::uint32_t shuffled = reverseBits(laineKarrasPermutation(reversedIndex, s));
    const std::uint32_t reversedY = detail::byTable(detail::kSobol1Reversed, shuffled);
    return {fixedToFloat(reverseBits(laineKarrasPermutation(shuffled, t))),
            fixedToFloat(reverseBits(laineKarrasPermutation(reversedY, u)))};
}

/// The 1D form: the first Sobol dimension, shuffled and scrambled.
inline float sobol1DReversed(std::uint32_t reversedIndex, std::uint64_t seed) {
    const std::uint32_t shuffled =
        reverseBits(laineKarrasPermutation(reversedIndex, std::uint32_t(seed)));
    return fixedToFloat(reverseBits(laineKarrasPermutation(shuffled, std::uint32_t(seed >> 32))));
}

/// Point `index` of the scrambled pair for `seed` (sobol2DReversed of its reversed index).
inline Vec2 sobol2D(std::uint32_t index, std::uint64_t seed) {
    return sobol2DReversed(reverseBits(index), seed);
}
/// Value `index` of the scrambled 1D sequence for `seed`.
inline float sobol1D(std::uint32_t index, std::uint64_t seed) {
    return sobol1DReversed(reverseBits(index), seed);
}

/// Dimensions of the camera sample: film position (pair 0), lens (pair 1), time (2).
inline constexpr int kSobolCameraDims = 3;
/// Dimensions reserved per bounce (one per BounceDim, a pair's two in one), whether used or
/// not, so that what one bounce draws never shifts the next.
inline constexpr int kSobolDimsPerBounce = 5;

/// The sampler of one camera sample: sample `index` of pixel `pixel`, every dimension its own
/// scrambled Sobol sequence. A PrefetchingSampler (sampling/sampler.h); it has no free-running
/// stream, so every number a path draws must have its slot.
class SobolSampler {
  public:
    static constexpr bool kSlotted = true;

    SobolSampler(std::uint64_t seed, std::uint64_t pixel, std::uint32_t index)
        : m_key(hash64(hash64(seed, 0x50b01ULL), pixel)), m_reversedIndex(reverseBits(index)) {}

    /// Camera dimension `dim` (0 film, 1 lens as pairs; 2 time).
    Vec2 camera2D(int dim) const { return sobol2DReversed(m_reversedIndex, dimensionSeed(dim)); }
    float camera1D(int dim) const { return sobol1DReversed(m_reversedIndex, dimensionSeed(dim)); }

    /// Slot `slot` of bounce `depth` (BounceDim): computed now, or taken from prefetchMany().
    float bounce1D(int depth, BounceDim slot) const {
        if (depth == m_prefetchedDepth && (m_prefetched & slotBit(slot)))
            return m_numbers[kOffset[int(slot)]];
        return sobol1DReversed(m_reversedIndex, dimensionSeed(bounceDim(depth, slot)));
    }
    Vec2 bounce2D(int depth, BounceDim slot) const {
        if (depth == m_prefetchedDepth && (m_prefetched & slotBit(slot)))
            return {m_numbers[kOffset[int(slot)]], m_numbers[kOffset[int(slot)] + 1]};
        return sobol2DReversed(m_reversedIndex, dimensionSeed(bounceDim(depth, slot)));
    }

    /// The bit of `slot` in prefetchMany()'s masks.
    static constexpr unsigned slotBit(BounceDim slot) { return render::slotBit(slot); }
    /// Two 32-bit scramble seeds of dimension `dim` from a pixel's key (sobol2D/1D split them).
    static std::uint64_t dimensionSeedOf(std::uint64_t key, int dim) {
        const std::uint32_t s = hash32(std::uint32_t(key) + std::uint32_t(dim) * 0x9e3779b9u);
        const std::uint32_t t = (std::uint32_t(key >> 32) ^ s) * 0x9e3779b1u;
        return (std::uint64_t(t) << 32) | s;
    }

    /// Computes the numbers of bounce depths[i] for the slots in slots[i] (slotBit()s) of
    /// samplers[i] ahead of their use: the same numbers bounce1D/2D would compute, slot by slot
    /// across the samplers in loops the compiler vectorises, with an AVX2 clone chosen at load
    /// time where the CPU has it (sobol_batch.cpp). The scrambles are long chains of dependent
    /// multiplies: one path at a time they stall the core, across a batch they fill vector
    /// lanes (PathIntegrator::traceMany).
    static void prefetchMany(std::size_t n, SobolSampler* const* samplers, const int* depths,
                             const unsigned* slots);

  private:
    static int bounceDim(int depth, BounceDim slot) {
        return kSobolCameraDims + depth * kSobolDimsPerBounce + int(slot);
    }
    std::uint64_t dimensionSeed(int dim) const { return dimensionSeedOf(m_key, dim); }

    /// Where each slot's numbers start in m_numbers (pairs take two).
    static constexpr int kOffset[kSobolDimsPerBounce + 1] = {0, 1, 3, 5, 6, 7};

    std::uint64_t m_key;
    std::uint32_t m_reversedIndex;
    int m_prefetchedDepth = -1;
    unsigned m_prefetched = 0;
    float m_numbers[7] = {};
};

/// ⌈log2 n⌉ for n ≥ 1.
inline int ceilLog2(std::uint32_t n) {
    int k = 0;
    while ((std::uint64_t(1) << k) < n) ++k;
    return k;
}

/// x's bits spread to the even bit positions (bit i → bit 2i), for a Morton code.
inline std::uint32_t spreadBits(std::uint32_t x) {
    x &= 0xffffu;
    x = (x | (x << 8)) & 0x00ff00ffu;
    x = (x | (x << 4)) & 0x0f0f0f0fu;
    x = (x | (x << 2)) & 0x33333333u;
    return (x | (x << 1)) & 0x55555555u;
}

/// The ZSobol sampler (Ahmed and Wonka 2020, "Screen-Space Blue-Noise Diffusion of Monte Carlo
/// Sampling Error via Hierarchical Ordering of Pixels"; pbrt-v4's default): one Owen-scrambled
/// Sobol sequence across the whole film, pixel (x, y) owning the aligned block of indices
/// (Morton(x, y) · 2^log2Spp + s). Per dimension the index's base-4 digits are permuted, each
/// by a hash of the digits above it, the dimension and its position: a nested permutation, so a
/// pixel's block maps onto an aligned block (its 2^m samples stay a (0, m, 2)-net), dimensions
/// are decorrelated, and neighbouring pixels take neighbouring blocks in a shuffled Morton order
/// (their errors come out as blue noise). Costs a hash per digit and dimension: about 11 on a
/// 256² film at 64 spp. A PixelSampler as SobolSampler is, without prefetching.
class ZSobolSampler {
  public:
    static constexpr bool kSlotted = true;

    /// Sample `index` of pixel (x, y) for a film whose larger side is at most 2^log2Res and at
    /// most 2^log2Spp samples a pixel; 2 log2Res + log2Spp ≤ 32 (Renderer checks).
    ZSobolSampler(std::uint64_t seed, int x, int y, std::uint32_t index, int log2Res, int log2Spp)
        : m_key(std::uint32_t(hash64(seed, 0x25ab017ULL))),
          m_bits(2 * log2Res + log2Spp),
          m_morton(((spreadBits(std::uint32_t(y)) << 1 | spreadBits(std::uint32_t(x))) << log2Spp) |
                   index) {}

    Vec2 camera2D(int dim) const { return point2D(dim); }
    float camera1D(int dim) const { return point1D(dim); }
    float bounce1D(int depth, BounceDim slot) const {
        return point1D(kSobolCameraDims + depth * kSobolDimsPerBounce + int(slot));
    }
    Vec2 bounce2D(int depth, BounceDim slot) const {
        return point2D(kSobolCameraDims + depth * kSobolDimsPerBounce + int(slot));
    }

    /// The Sobol index of dimension `dim` (the permuted Morton index; for tests).
    std::uint32_t indexOf(int dim) const {
        const std::uint32_t dimKey = hash32(m_key ^ (std::uint32_t(dim) * 0x9e3779b9u));
        // With an odd number of bits the lowest is a base-2 digit, flipped by a hash of the rest.
        const int low = m_bits & 1;
        std::uint32_t out = 0;
        for (int shift = m_bits - 2; shift >= low; shift -= 2) {
            const std::uint32_t digit = (m_morton >> shift) & 3u;
            const std::uint32_t higher = shift + 2 >= 32 ? 0u : m_morton >> (shift + 2);
            const std::uint32_t h = hash32(higher ^ dimKey ^ (std::uint32_t(shift) * 0x85ebca6bu));
            out |= std::uint32_t(kPermutations[(h >> 8) % 24][digit]) << shift;
        }
        if (low) out |= (m_morton & 1u) ^ (hash32((m_morton >> 1) ^ dimKey ^ 0xc2b2ae35u) & 1u);
        return out;
    }

  private:
    /// The 24 permutations of {0, 1, 2, 3}.
    static constexpr std::uint8_t kPermutations[24][4] = {
        {0, 1, 2, 3}, {0, 1, 3, 2}, {0, 2, 1, 3}, {0, 2, 3, 1}, {0, 3, 1, 2}, {0, 3, 2, 1},
        {1, 0, 2, 3}, {1, 0, 3, 2}, {1, 2, 0, 3}, {1, 2, 3, 0}, {1, 3, 0, 2}, {1, 3, 2, 0},
        {2, 0, 1, 3}, {2, 0, 3, 1}, {2, 1, 0, 3}, {2, 1, 3, 0}, {2, 3, 0, 1}, {2, 3, 1, 0},
        {3, 0, 1, 2}, {3, 0, 2, 1}, {3, 1, 0, 2}, {3, 1, 2, 0}, {3, 2, 0, 1}, {3, 2, 1, 0}};

    /// Owen scrambles of the first two Sobol dimensions at indexOf(dim): the nested scramble of
    /// sobol0(i) = rev(i) is rev(LK(i, s)); of sobol1(i), rev(LK(rev(sobol1(i)), t)).
    Vec2 point2D(int dim) const {
        const std::uint32_t i = indexOf(dim);
        const std::uint32_t s = hash32(m_key + std::uint32_t(dim) * 0x2c1b3c6du);
        const std::uint32_t t = hash32(s ^ 0x297a2d39u);
        return {fixedToFloat(reverseBits(laineKarrasPermutation(i, s))),
                fixedToFloat(reverseBits(
                    laineKarrasPermutation(detail::byTable(detail::kSobol1Reversed, i), t)))};
    }
    float point1D(int dim) const {
        const std::uint32_t s = hash32(m_key + std::uint32_t(dim) * 0x2c1b3c6du);
        return fixedToFloat(reverseBits(laineKarrasPermutation(indexOf(dim), s)));
    }

    std::uint32_t m_key;
    int m_bits;              // 2 log2Res + log2Spp: the bits of the index
    std::uint32_t m_morton;  // Morton(x, y) · 2^log2Spp + index
};

static_assert(PrefetchingSampler<SobolSampler> && PixelSampler<SobolSampler>);
static_assert(PixelSampler<ZSobolSampler> && !PrefetchingSampler<ZSobolSampler>);

}  // namespace glint::render

// SobolSampler::prefetchMany: the scrambled Sobol numbers of a batch of paths, slot by slot, in
// structure-of-arrays loops. Built with -O3 (renderer/CMakeLists.txt) so that GCC vectorises
// them, and cloned for AVX2 (whose 32-bit vector multiply the hash scrambles need; SSE2 has
// none), chosen at load time. Every lane computes exactly what sobol1DReversed /
// sobol2DReversed compute (tests/render/wavefront_test.cpp).
#include <vector>

#include "sampling/sobol.h"

namespace glint::render {

namespace {

/// Lane i: sobol2DReversed(reversedIndex[i], dimensionSeedOf(key[i], dim[i])).
[[gnu::target_clones("avx2", "default")]] void sobol2DLanes(std::size_t n,
                                                            const std::uint32_t* reversedIndex,
                                                            const std::uint64_t* key,
                                                            const int* dim, float* x, float* y) {
    for (std::size_t i = 0; i < n; ++i) {
        const std::uint64_t seed = SobolSampler::dimensionSeedOf(key[i], dim[i]);
        const auto s = std::uint32_t(seed), t = std::uint32_t(seed >> 32);
        const std::uint32_t u = t * 0x2c1b3c6du + 0x297a2d39u;
        const std::uint32_t shuffled = reverseBits(laineKarrasPermutation(reversedIndex[i], s));
        const std::uint32_t reversedY = detail::byTable(detail::kSobol1Reversed, shuffled);
        x[i] = fixedToFloat(reverseBits(laineKarrasPermutation(shuffled, t)));
        y[i] = fixedToFloat(reverseBits(laineKarrasPermutation(reversedY, u)));
    }
}

/// Lane i: sobol1DReversed(reversedIndex[i], dimensionSeedOf(key[i], dim[i])).
[[gnu::target_clones("avx2", "default")]] void sobol1DLanes(std::size_t n,
                                                            const std::uint32_t* reversedIndex,
                                                            const std::uint64_t* key,
                                                            const int* dim, float* x) {
    for (std::size_t i = 0; i < n; ++i) {
        const std::uint64_t seed = SobolSampler::dimensionSeedOf(key[i], dim[i]);
        const std::uint32_t shuffled =
            reverseBits(laineKarrasPermutation(reversedIndex[i], std::uint32_t(seed)));
        x[i] =
            fixedToFloat(reverseBits(laineKarrasPermutation(shuffled, std::uint32_t(seed >> 32))));
    }
}

/// The lanes of one slot, kept per thread so that batches do not allocate.
struct Lanes {
    std::vector<std::uint32_t> reversedIndex;
    std::vector<std::uint64_t> key;
    std::vector<int> dim;
    std::vector<std::size_t> sampler;
    std::vector<float> x, y;

    void clear() {
        reversedIndex.clear();
        key.clear();
        dim.clear();
        sampler.clear();
    }
};

}  // namespace

void SobolSampler::prefetchMany(std::size_t n, SobolSampler* const* samplers, const int* depths,
                                const unsigned* slots) {
    thread_local Lanes lanes;
    for (std::size_t i = 0; i < n; ++i) {
        samplers[i]->m_prefetchedDepth = depths[i];
        samplers[i]->m_prefetched = slots[i];
    }
    for (int slot = 0; slot < kSobolDimsPerBounce; ++slot) {
        const unsigned bit = slotBit(BounceDim(slot));
        lanes.clear();
        for (std::size_t i = 0; i < n; ++i) {
            if (!(slots[i] & bit)) continue;
            lanes.reversedIndex.push_back(samplers[i]->m_reversedIndex);
            lanes.key.push_back(samplers[i]->m_key);
            lanes.dim.push_back(bounceDim(depths[i], BounceDim(slot)));
            lanes.sampler.push_back(i);
        }
        const std::size_t count = lanes.sampler.size();
        if (count == 0) continue;
        lanes.x.resize(count);
        lanes.y.resize(count);
        const bool pair = kOffset[slot + 1] - kOffset[slot] == 2;
        if (pair)
            sobol2DLanes(count, lanes.reversedIndex.data(), lanes.key.data(), lanes.dim.data(),
                         lanes.x.data(), lanes.y.data());
        else
            sobol1DLanes(count, lanes.reversedIndex.data(), lanes.key.data(), lanes.dim.data(),
                         lanes.x.data());
        for (std::size_t k = 0; k < count; ++k) {
            float* to = &samplers[lanes.sampler[k]]->m_numbers[kOffset[slot]];
            to[0] = lanes.x[k];
            if (pair) to[1] = lanes.y[k];
        }
    }
}

}  // namespace glint::render

// Reproducible O(1) box sums by block prefix and suffix sums (see box_filter.h).
#include "filters/box_filter.h"

#include <algorithm>
#include <cstring>
#include <vector>

#include "filters/filter_util.h"
#include "glint/image/error.h"

namespace glint::denoise::detail {

namespace {

typedef double VecD __attribute__((vector_size(32)));

// dst[0..width) = a[0..width) + b[0..width), four doubles at a time (width a multiple of 4;
// dst may alias a or b).
[[gnu::always_inline]] inline void addRows(double* dst, const double* a, const double* b,
                                           int width) {
    for (int k = 0; k < width; k += 4) {
        VecD va, vb;
        std::memcpy(&va, a + k, sizeof va);
        std::memcpy(&vb, b + k, sizeof vb);
        const VecD s = va + vb;
        std::memcpy(dst + k, &s, sizeof s);
    }
}

// Start of the block (of size n, grid starting at lim0) holding i >= lim0.
inline int blockStart(int i, int lim0, int n) {
    return lim0 + (i - lim0) / n * n;
}

}  // namespace

GLINT_SIMD_CLONES
void boxSums1D(const double* in, int in0, std::ptrdiff_t inStride, double* out, int out0, int out1,
               std::ptrdiff_t outStride, int width, int r, int lim0, int lim1) {
    GLINT_CHECK(width % 4 == 0, "box sums need a multiple of 4 doubles per element");
    if (out0 >= out1) return;
    const int n = 2 * r + 1;
    const int lo = std::max(out0 - r, lim0), hi = std::min(out1 + r, lim1);
    if (lo >= hi) {
        for (int j = out0; j < out1; ++j)
            std::fill_n(out + std::ptrdiff_t(j - out0) * outStride, width, 0.0);
        return;
    }
    auto element = [&](int i) { return in + std::ptrdiff_t(i - in0) * inStride; };
    // Suffix sums within each block, truncated at hi: suffix(i) = in(i) + suffix(i + 1). Where a
    // suffix is used, its block ends below hi or at lim1, so it never depends on out1.
    std::vector<double> suffix(std::size_t(hi - lo) * std::size_t(width));
    auto suf = [&](int i) { return suffix.data() + std::size_t(i - lo) * std::size_t(width); };
    for (int i = hi - 1; i >= lo; --i) {
        const bool blockEnd = i + 1 == hi || (i + 1 - lim0) % n == 0;
        if (blockEnd)
            std::memcpy(suf(i), element(i), sizeof(double) * std::size_t(width));
        else
            addRows(suf(i), element(i), suf(i + 1), width);
    }
    // Prefix sums within each block, streamed forward; each used prefix starts at its block's
    // start (>= lo), so it never depends on out0.
    std::vector<double> prefix(static_cast<std::size_t>(width));
    int pEnd = -1;  // prefix holds the sum from blockStart(pEnd) to pEnd
    for (int j = out0; j < out1; ++j) {
        const int s = std::max(j - r, lim0), e = std::min(j + r, lim1 - 1);
        double* dst = out + std::ptrdiff_t(j - out0) * outStride;
        const int bs = blockStart(e, lim0, n);
        const bool sameBlock = bs <= s;
        if (sameBlock && s != bs) {
            std::memcpy(dst, suf(s), sizeof(double) * std::size_t(width));  // [s, lim1)
            continue;
        }
        // Advance the prefix of e's block to e (bs >= s >= lo: all held in the input).
        if (pEnd < bs || pEnd > e) {
            std::memcpy(prefix.data(), element(bs), sizeof(double) * std::size_t(width));
            pEnd = bs;
        }
        for (; pEnd < e; ++pEnd) addRows(prefix.data(), prefix.data(), element(pEnd + 1), width);
        if (sameBlock)
            std::memcpy(dst, prefix.data(), sizeof(double) * std::size_t(width));
        else
            addRows(dst, suf(s), prefix.data(), width);
    }
}

GLINT_SIMD_CLONES
void verticalBoxStep(double* ring, int rows, int width, double* prefix, double* sum, int j, int r,
                     int limit, bool first) {
    const int n = 2 * r + 1;
    auto row = [&](int i) { return ring + std::size_t(i % rows) * std::size_t(width); };
    const std::size_t bytes = sizeof(double) * std::size_t(width);
    const int s = std::max(j - r, 0), e = std::min(j + r, limit - 1);
    const int bs = blockStart(e, 0, n);
    // Prefix of e's block: extended by the row that just entered, or summed directly on the first
    // call (only where it is needed before its block restarts: bs >= s).
    if (first) {
        if (bs >= s) {
            std::memcpy(prefix, row(bs), bytes);
            for (int i = bs + 1; i <= e; ++i) addRows(prefix, prefix, row(i), width);
        }
    } else if (j + r < limit) {
        if (e == bs)
            std::memcpy(prefix, row(e), bytes);
        else
            addRows(prefix, prefix, row(e), width);
    }
    // Suffix sums of s's block, in place, when s reaches a block start (or on the first call).
    if ((j - r >= 0 && j - r == blockStart(j - r, 0, n)) || (first && j - r > 0)) {
        const int end = std::min(blockStart(s, 0, n) + n - 1, limit - 1);
        for (int i = end - 1; i >= s; --i) addRows(row(i), row(i), row(i + 1), width);
    }
    if (bs > s)
        addRows(sum, row(s), prefix, width);
    else if (bs == s)
        std::memcpy(sum, prefix, bytes);
    else
        std::memcpy(sum, row(s), bytes);
}

}  // namespace glint::denoise::detail

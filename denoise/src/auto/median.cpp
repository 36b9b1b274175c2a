// The bank's median per pixel and channel by a sorting network (median.h).
#include "median.h"

#include <algorithm>
#include <vector>

#include "../filters/simd.h"
#include "glint/denoise/bank.h"
#include "glint/denoise/progress.h"
#include "glint/image/error.h"

namespace glint::denoise {

namespace detail {

namespace {

// Sorts `n` columns of 8 floats (column i at v + 8 i) lane-wise, ascending: Batcher's
// merge-exchange network for any n (Knuth, TAOCP vol. 3, 5.2.2, Algorithm M; about n log²n / 4
// comparators), 8 values per comparator. Branch-free in the values, where a selection per value
// mispredicts about half its comparisons.
GLINT_SIMD_CLONES
void sortLanes(float* v, std::size_t n) {
    if (n < 2) return;
    std::size_t top = 1;  // 2^(t−1), t = ⌈log2 n⌉
    while (top * 2 < n) top *= 2;
    for (std::size_t p = top; p > 0; p >>= 1) {
        std::size_t q = top, r = 0, d = p;
        for (;;) {
            for (std::size_t i = 0; i + d < n; ++i) {
                if ((i & p) != r) continue;
                VecF a, b;
                loadVec(a, v + 8 * i);
                loadVec(b, v + 8 * (i + d));
                storeVec(v + 8 * i, a < b ? a : b);
                storeVec(v + 8 * (i + d), a < b ? b : a);
            }
            if (q == p) break;
            d = q - p;
            q >>= 1;
            r = p;
        }
    }
}

}  // namespace

Image medianOf(const std::vector<const Image*>& results, WorkContext& work) {
    if (results.empty()) throw Error(ErrorKind::InvalidArgument, "the bank has no members");
    const int width = results.front()->width(), height = results.front()->height();
    Image median(width, height, 3);
    const std::size_t n = results.size();
    // Per row, 8 values (pixels × channels) at a time: each member's 8 side by side, sorted
    // lane-wise; the median is the (n/2)-th smallest (as std::nth_element would give it).
    const std::size_t rowValues = std::size_t(width) * 3;
    work.parallelFor(0, height, [&](int y) {
        std::vector<float> v(n * 8);
        for (std::size_t x0 = 0; x0 < rowValues; x0 += 8) {
            const std::size_t count = std::min<std::size_t>(8, rowValues - x0);
            for (std::size_t m = 0; m < n; ++m) {
                const float* row = results[m]->row(y) + x0;
                std::copy(row, row + count, v.begin() + std::ptrdiff_t(8 * m));
            }
            sortLanes(v.data(), n);
            std::copy(v.begin() + std::ptrdiff_t(8 * (n / 2)),
                      v.begin() + std::ptrdiff_t(8 * (n / 2) + count), median.row(y) + x0);
        }
    });
    return median;
}

Image bankMedian(const FilterBank& bank, WorkContext& work) {
    if (bank.size() == 0) throw Error(ErrorKind::InvalidArgument, "the bank has no members");
    std::vector<const Image*> results(bank.size());
    for (std::size_t m = 0; m < bank.size(); ++m) results[m] = &bank.result(m);
    return medianOf(results, work);
}

Image bankMedian(const FilterBank& bank) {
    WorkContext work;
    return bankMedian(bank, work);
}

}  // namespace detail

}  // namespace glint::denoise

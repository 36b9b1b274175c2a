// Reproducible O(1) box sums (see box_filter.h).
#include "filters/box_filter.h"

#include <algorithm>
#include <cstring>
#include <vector>

#include "filters/filter_util.h"
#include "glint/image/error.h"

namespace glint::denoise::detail {

namespace {

typedef double VecD __attribute__((vector_size(32)));

// acc[0..width) += sign * v[0..width), four doubles at a time (width is a multiple of 4), with
// the rounding error of every addition added to comp (Knuth's branch-free TwoSum): acc + comp
// stays accurate when a large element enters the window and leaves it again, which a plain
// running sum would turn into an error of about 1e-16 times that element for every later sum.
template <int Sign>
[[gnu::always_inline]] inline void accumulate(double* acc, double* comp, const double* v,
                                              int width) {
    for (int k = 0; k < width; k += 4) {
        VecD a, b, e;
        std::memcpy(&a, acc + k, sizeof a);
        std::memcpy(&b, v + k, sizeof b);
        std::memcpy(&e, comp + k, sizeof e);
        if (Sign < 0) b = -b;
        const VecD s = a + b;
        const VecD bv = s - a;
        const VecD av = s - bv;
        e += (a - av) + (b - bv);
        std::memcpy(acc + k, &s, sizeof s);
        std::memcpy(comp + k, &e, sizeof e);
    }
}

}  // namespace

GLINT_SIMD_CLONES
void boxSums1D(const double* in, int in0, std::ptrdiff_t inStride, double* out, int out0, int out1,
               std::ptrdiff_t outStride, int width, int r, int lim0, int lim1) {
    GLINT_CHECK(width % 4 == 0, "box sums need a multiple of 4 doubles per element");
    std::vector<double> acc(static_cast<std::size_t>(width)), comp(acc.size());
    auto element = [&](int i) { return in + std::ptrdiff_t(i - in0) * inStride; };
    for (int a = boxAnchorBelow(out0); a < out1; a += kBoxAnchor) {
        // Direct sum of the window at the anchor.
        std::fill(acc.begin(), acc.end(), 0.0);
        std::fill(comp.begin(), comp.end(), 0.0);
        const int lo = std::max(a - r, lim0), hi = std::min(a + r + 1, lim1);
        for (int i = lo; i < hi; ++i) {
            accumulate<1>(acc.data(), comp.data(), element(i), width);
        }
        // Slide the window up to the next anchor: add the entering, drop the leaving element.
        const int end = std::min(a + kBoxAnchor, out1);
        for (int j = a; j < end; ++j) {
            if (j > a) {
                const int enter = j + r, leave = j - r - 1;
                if (enter < lim1) accumulate<1>(acc.data(), comp.data(), element(enter), width);
                if (leave >= lim0) accumulate<-1>(acc.data(), comp.data(), element(leave), width);
            }
            if (j >= out0)
                compensatedSum(acc.data(), comp.data(), width,
                               out + std::ptrdiff_t(j - out0) * outStride);
        }
    }
}

GLINT_SIMD_CLONES
void accumulateRow(double* acc, double* comp, const double* v, int width, bool subtract) {
    if (subtract)
        accumulate<-1>(acc, comp, v, width);
    else
        accumulate<1>(acc, comp, v, width);
}

void compensatedSum(const double* acc, const double* comp, int width, double* out) {
    for (int k = 0; k < width; ++k) out[k] = acc[k] + comp[k];
}

}  // namespace glint::denoise::detail

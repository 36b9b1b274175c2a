// Box sums in double precision: O(1) per element whatever the radius, and reproducible — the
// value at an index does not depend on where the caller starts, so a filter evaluated on a region
// of interest gives bit-identical pixels to the same filter evaluated on the whole frame.
#pragma once

#include <cstddef>

namespace glint::denoise::detail {

/// Running sums restart with a direct sum at every multiple of kBoxAnchor (global coordinates).
inline constexpr int kBoxAnchor = 64;

/// The anchor at or below index i (i >= 0).
inline int boxAnchorBelow(int i) {
    return (i / kBoxAnchor) * kBoxAnchor;
}

/// Truncated box sums along one axis. Elements are vectors of `width` doubles (a multiple of 4);
/// element i of the input starts at in + (i - in0) * inStride. For every j in [out0, out1) writes
/// sum_{i in [j - r, j + r] ∩ [lim0, lim1)} in(i) to out + (j - out0) * outStride. The input must
/// hold every i in [boxAnchorBelow(out0) - r, out1 + r) ∩ [lim0, lim1).
void boxSums1D(const double* in, int in0, std::ptrdiff_t inStride, double* out, int out0, int out1,
               std::ptrdiff_t outStride, int width, int r, int lim0, int lim1);

/// acc[0, width) += v[0, width), or -= when `subtract`, with the rounding error of each addition
/// added to comp (compensated running sums: the sum is acc + comp); width a multiple of 4.
void accumulateRow(double* acc, double* comp, const double* v, int width, bool subtract);

/// out[k] = acc[k] + comp[k] for k in [0, width): the value of a compensated running sum.
void compensatedSum(const double* acc, const double* comp, int width, double* out);

}  // namespace glint::denoise::detail

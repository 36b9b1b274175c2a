// Box sums in double precision: O(1) per element whatever the radius, and reproducible — the
// value at an index does not depend on where the caller starts, so a filter evaluated on a region
// of interest gives bit-identical pixels to the same filter evaluated on the whole frame.
//
// No running sum ever subtracts: the axis is cut into blocks of 2r+1 elements on a fixed grid
// (starting at the lower limit), and a window [j - r, j + r] is the suffix sum of the block holding
// j - r plus the prefix sum of the block holding j + r (the block-decomposition of van Herk 1992
// and Gil & Werman 1993, applied to sums). Every sum only adds elements of its own window, so a
// huge element (1e20) cannot leave rounding error in the sums of windows that do not contain it,
// and each window sum has the accuracy of a direct sum of at most 2r+1 terms. Three additions per
// element and pass.
#pragma once

#include <cstddef>

namespace glint::denoise::detail {

/// Truncated box sums along one axis. Elements are vectors of `width` doubles (a multiple of 4);
/// element i of the input starts at in + (i - in0) * inStride. For every j in [out0, out1) writes
/// sum_{i in [j - r, j + r] ∩ [lim0, lim1)} in(i) to out + (j - out0) * outStride. The input must
/// hold every i in [out0 - r, out1 + r) ∩ [lim0, lim1).
void boxSums1D(const double* in, int in0, std::ptrdiff_t inStride, double* out, int out0, int out1,
               std::ptrdiff_t outStride, int width, int r, int lim0, int lim1);

/// Vertical box sums streaming down a ring of rows, in the same block decomposition as boxSums1D
/// (limits [0, limit)). Row i of `width` doubles (a multiple of 4) lives at ring + (i % rows) *
/// width, rows >= 2r + 2. Call for consecutive j, `first` on the first call, after rows
/// [max(0, j - r), min(limit, j + r + 1)) are in the ring; writes the window sum at row j to sum.
/// Rewrites ring rows in place (to their block suffix sums); `prefix` is width doubles of state.
void verticalBoxStep(double* ring, int rows, int width, double* prefix, double* sum, int j, int r,
                     int limit, bool first);

}  // namespace glint::denoise::detail

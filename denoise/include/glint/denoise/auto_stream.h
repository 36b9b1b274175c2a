// The automatic selection without a materialised bank (docs/auto.md, "Memory"): the members are
// filtered strip by strip and reduced at once to what the stages need, so that the peak memory
// grows with the frame, not with the bank's size.
#pragma once

#include <vector>

#include "glint/denoise/auto.h"
#include "glint/denoise/bank.h"

namespace glint::denoise {

/// What autoCompositeStreamed returns: the result and the bank it chose from, without its
/// results (FilterBank::results() is empty: no member's pixels are kept).
struct StreamedAuto {
    AutoResult result;
    FilterBank bank;
};

/// autoComposite(buildBank(frame, bank), frame, options) without building the bank: each member
/// is applied to strips of rows (with the margin its filter declares, and the stacking's
/// windows) in a few passes over the frame, and only per-pixel error maps (one channel per
/// member) and the stages' frame-sized images are kept. The result equals autoComposite's up
/// to float rounding (a filter over a strip equals the strip of its whole-frame output within
/// 1e-5 relative; the box averages add their sums per strip). bank.cacheDir is not used, and
/// options.prefilter must be bank.prefilter (with its parameters). Throws like buildBank and
/// autoComposite; Error(Cancelled) when options.progress says stop.
StreamedAuto autoCompositeStreamed(const FrameBuffers& frame, const BankOptions& bank,
                                   const AutoOptions& options = {});

}  // namespace glint::denoise

// The automatic selection without a materialised bank (docs/auto-memory.md): autoComposite's
// pipeline applying the members tile by tile, so that the peak memory grows with the frame, not
// with the bank's size. What `glint-denoise auto` runs without --bank.
#pragma once

#include <string>
#include <vector>

#include "glint/denoise/auto.h"
#include "glint/denoise/bank.h"

namespace glint::denoise {

/// What autoCompositeStreamed returns: the result and the bank it chose from, without its
/// results (FilterBank::results() is empty: no member's pixels are kept).
struct StreamedAuto {
    AutoResult result;
    FilterBank bank;
    /// Whether the members' results that later passes read again were kept in a temporary file
    /// (the spill) instead of filtered again; the result is the same either way.
    bool spilled = false;
    /// Why the spill was not used, when it was asked for ("on") or a write to it failed; else
    /// empty. One line for the user.
    std::string warning;
};

/// autoComposite(buildBank(frame, bank), frame, options) without building the bank: each member
/// is applied to the pipeline's tiles (strips of rows, with the margin its filter declares) in
/// a few passes over the frame, and only per-pixel error maps (one channel per member) and the
/// stages' frame-sized images are kept. The same floats as autoComposite's (a filter over a
/// strip gives the strip of its whole-frame output). The results that later passes read again
/// go to an unlinked temporary file in TMPDIR (else /tmp) when it has room (the spill), which
/// does not change them. bank.cacheDir is not used, and options.prefilter must be
/// bank.prefilter (with its parameters). Throws like buildBank and autoComposite;
/// Error(Cancelled) when options.progress says stop.
StreamedAuto autoCompositeStreamed(const FrameBuffers& frame, const BankOptions& bank,
                                   const AutoOptions& options = {});

}  // namespace glint::denoise

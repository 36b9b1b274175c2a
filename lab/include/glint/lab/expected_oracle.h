// The expected-error oracle: a measure of what an exact estimate of each member's error could
// reach (glint-lab oracle --expected; docs/lab/oidn-gap.md, "What limits the share").
#pragma once

#include <map>
#include <string>
#include <vector>

#include "glint/denoise/bank.h"
#include "glint/image/frame_buffers.h"
#include "glint/image/image.h"
#include "glint/lab/oracle.h"

namespace glint::lab {

/// The per-pixel choice by each member's *expected* error instead of the error it made on this
/// render. Each member's per-pixel error (the oracle's: 3×3 display MSE) is averaged over the
/// bank's own results and over `others`, independent renders of the same scene with the same
/// settings (another seed), each filtered by every member over the bank's region (prefiltered
/// like the bank's input when `prefilter`); for each radius r in `radii` the averages are
/// box-averaged over (2r + 1)² pixels (0: the oracle's 3×3 alone) and each
/// pixel takes the result of the member with the smallest. The per-pixel oracle picks by the
/// error this render happened to have, luck no estimate can know of; this choice by the error
/// a member makes on average is what an exact estimate of each member's error could reach, and
/// its SSIM at the auto composite's window is what that choice can reach there
/// (docs/lab/oidn-gap.md, "What limits the share"). `others` must be frame-sized; memory: one
/// float per member and pixel.
struct ExpectedOracleOptions {
    std::vector<int> radii{0, 2, 4, 8};  ///< each 0 … 64
    float exposure = 0.0f;
    bool prefilter = false;  ///< the bank was built on prefiltered features
    std::map<std::string, double> prefilterParams;
};
struct ExpectedOracleResult {
    std::vector<int> radii;
    std::vector<double> ssim;  ///< per radius, of the choice on the bank's own results
    int renders = 0;           ///< the bank's input and the others
    Image choice;              ///< the member chosen per pixel at the first radius (as float)
};
/// Throws glint::Error(InvalidArgument) naming `others[i]` by its index when its size differs,
/// for no others, or for a radius outside 0 … 64.
ExpectedOracleResult expectedErrorOracle(const denoise::FilterBank& bank,
                                         const std::vector<FrameBuffers>& others,
                                         const Image& reference,
                                         const ExpectedOracleOptions& options = {});

}  // namespace glint::lab

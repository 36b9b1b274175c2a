// What a bank can reach against a reference (the thesis's oracle measures): the noisy input,
// the best single member, the best three members with a per-pixel choice among them (the
// image-complexity measure) and the per-pixel optimal choice over the whole bank.
#pragma once

#include <array>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "glint/image/frame_buffers.h"
#include "glint/image/image.h"

namespace glint::denoise {

class FilterBank;

/// SSIM (display values) of each composite against the reference over the bank's region.
struct OracleResult {
    double noisy = 0.0;       ///< the input itself
    double bestSingle = 0.0;  ///< the best member applied everywhere
    int bestMember = -1;
    double best3 = 0.0;  ///< per-pixel choice among the best three members
    std::array<int, 3> best3Members{-1, -1, -1};
    double perPixel = 0.0;  ///< per-pixel choice among all members
    /// Per pixel, the member the per-pixel oracle chose (1 channel, region-sized, as float).
    Image choice;
};

/// Computes the oracle table. `noisy` and `reference` are frame-sized colour images; the bank's
/// region is used. Per pixel, a member's error is the squared difference of display values
/// summed over channels, box-averaged over a 3×3 neighbourhood; the best three are searched
/// exhaustively among the 12 best single members. Throws glint::Error(InvalidArgument) for
/// mismatched sizes or a bank smaller than 3.
OracleResult oracle(const FilterBank& bank, const Image& noisy, const Image& reference,
                    float exposure = 0.0f);

/// The per-pixel choice by each member's *expected* error instead of the error it made on this
/// render. Each member's per-pixel error (the oracle's: 3×3 display MSE) is averaged over the
/// bank's own results and over `others`, independent renders of the same scene with the same
/// settings (another seed), each filtered by every member over the bank's region (prefiltered
/// like the bank's input when `prefilter`); for each radius r in `radii` the averages are
/// box-averaged over (2r + 1)² pixels (0: the oracle's 3×3 alone, boxSmooth in sure.h) and each
/// pixel takes the result of the member with the smallest. The per-pixel oracle picks by the
/// error this render happened to have, luck no estimate can know of; this choice by the error
/// a member makes on average is what an exact estimate of each member's error could reach, and
/// its SSIM at the auto composite's window is what that choice can reach there
/// (docs/auto.md, "What limits the share"). `others` must be frame-sized; memory: one float per
/// member and pixel.
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
ExpectedOracleResult expectedErrorOracle(const FilterBank& bank,
                                         const std::vector<FrameBuffers>& others,
                                         const Image& reference,
                                         const ExpectedOracleOptions& options = {});

}  // namespace glint::denoise

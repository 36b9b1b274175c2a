// What a bank can reach against a reference (the thesis's oracle measures): the noisy input,
// the best single member, the best three members with a per-pixel choice among them (the
// image-complexity measure) and the per-pixel optimal choice over the whole bank (glint-lab
// oracle; docs/lab/README.md).
#pragma once

#include <array>

#include "glint/image/frame_buffers.h"
#include "glint/image/image.h"

namespace glint::denoise {
class FilterBank;
}

namespace glint::lab {

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
OracleResult oracle(const denoise::FilterBank& bank, const Image& noisy, const Image& reference,
                    float exposure = 0.0f);

}  // namespace glint::lab

// Monte Carlo-aware image comparison (docs/testing.md, "The Monte Carlo comparison"): is the
// difference between two Monte Carlo estimates of one image explained by their noise?
#pragma once

#include <cstddef>

#include "glint/image/image.h"

namespace glint {

struct McCompareOptions {
    /// Probability that two unbiased estimates of the same image fail the comparison (whole
    /// image, all windows together).
    double falseAlarmRate = 1e-4;
};

struct McCompareResult {
    bool passed = true;
    /// Largest |window statistic| and the threshold it was held against.
    double statistic = 0.0;
    double threshold = 0.0;
    Rect worstWindow;           ///< where that statistic was found
    double relativeBias = 0.0;  ///< sum(image - reference) / sum(reference) in that window
    std::size_t windows = 0;    ///< windows tested
};

/// Compares `mean` with `reference` given both images' variance of the mean per value (the
/// `variance` layers of Glint's EXRs; same shape, any channel count). Per value the z-score
/// z = (x - r) / sqrt(v_x + v_r); over every window of 8, 16 and 32 pixels (stride a quarter of
/// the side; the whole image if it is smaller) the self-normalised sum S = sum z / sqrt(sum z^2).
/// The comparison fails when some |S| exceeds t = sqrt(2 ln(2 N / alpha)) for N windows:
/// Efron's bound P(|S| > t) <= 2 exp(-t^2 / 2) for independent, symmetric z, with Bonferroni's
/// correction over the windows, keeps the false-alarm rate below alpha. Throws
/// glint::Error(InvalidArgument) for shapes that differ, NaN/Inf, a negative variance or an
/// alpha outside (0, 1).
McCompareResult mcCompare(const Image& mean, const Image& variance, const Image& reference,
                          const Image& referenceVariance, const McCompareOptions& options = {});

/// mcCompare channel by channel, each at falseAlarmRate / channels, the worst channel's result
/// (by statistic over threshold): sharper for a change confined to one channel (a tint), which
/// mcCompare, summing a pixel's channels into one term, shares with the other channels' noise.
/// The same errors as mcCompare.
McCompareResult mcCompareByChannel(const Image& mean, const Image& variance, const Image& reference,
                                   const Image& referenceVariance,
                                   const McCompareOptions& options = {});

}  // namespace glint

// The per-pixel choice of the automatic selection (docs/auto.md, "Per-pixel choice"): each
// candidate's map scored against a baseline's over a window, with a confidence margin, and the
// scores turned into per-pixel weights.
#pragma once

#include <cstddef>
#include <vector>

#include "glint/image/image.h"

namespace glint::denoise {
class WorkContext;
}

namespace glint::denoise::detail {

class ErrorEstimator;
struct Estimates;
struct AutoSettings;

/// The score of one candidate at one radius: the box average over (2·radius + 1)² pixels,
/// truncated at the border, of d = raw − base, each d rounded to float, plus `confidence`
/// standard errors of that mean, sqrt(max(0, mean of d² − mean²) / (2·radius + 1)²) (the full
/// window's count). `raw` and `base` are 1-channel maps of one size; the result is too. The
/// same, value for value, as boxSmooth of stored d and d² maps.
Image windowScore(const Image& raw, const Image& base, int radius, double confidence);

/// The margin, in standard errors, that keeps at Φ(−confidence) the chance that any of
/// `comparisons` candidates (each at each radius) leaves the baseline by the noise of its score
/// alone: Φ⁻¹(1 − Φ(−confidence)/comparisons) (Bonferroni), `confidence` itself for one
/// comparison or a confidence of 0. Among many candidates whose noisy window means are compared
/// with one margin, the lowest falls below it somewhere far more often than any one does (the
/// winner's curse; docs/auto.md, "Per-pixel choice").
double familywiseMargin(double confidence, std::size_t comparisons);

/// Box average of a 1-channel image over (2·radius + 1)² pixels, truncated at the border. `work`,
/// if given, runs its passes (one unit per row each).
Image boxSmooth(const Image& image, int radius, WorkContext* work = nullptr);

/// The temperature's unit per pixel of `region` (1 channel, region-sized): Σ_c of the
/// estimator's noise variance, times `weight` (3 channels, region-sized; empty: 1), box-averaged
/// over `window`. Rows through `work`.
Image noiseLevel(const ErrorEstimator& estimator, const Rect& region, const Image& weight,
                 int window, WorkContext& work);

/// A choice among candidates: per member, the pixels where it has the largest weight, its total
/// weight and, for a final choice, its weight plane (0 and empty for the others).
struct Choice {
    std::vector<Image> planes;
    std::vector<long> wins;
    std::vector<double> totals;
};

/// The choice among `candidates` (member indices, ascending) by their maps: the window scores
/// (with settings.finer smaller windows too in a `final` choice), then per-pixel weights — a
/// hard choice, or soft ones in units of `noise` (noiseLevel) with settings.temperature > 0.
/// Only a final choice keeps the planes. Candidates, then rows, through `work`. With
/// `stripRows` > 0, the scores are computed strip by strip of that many rows (ScoreRows), so
/// that they take c strips, not c maps; the result is the same, value for value.
Choice choose(const Estimates& estimates, const std::vector<std::size_t>& candidates, bool final,
              const AutoSettings& settings, const Image& noise, WorkContext& work,
              int stripRows = 0);

}  // namespace glint::denoise::detail

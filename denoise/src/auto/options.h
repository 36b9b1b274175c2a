// The automatic selection's options resolved for one bank and frame: validated, the estimator
// chosen and the estimator's defaults filled in (docs/auto.md, "Command line").
#pragma once

#include <cstddef>
#include <cstdint>

#include "glint/denoise/auto.h"
#include "image_noise.h"

namespace glint::denoise::detail {

/// Which error the estimators estimate (the tuning's "space", in its choices' order).
enum class SureSpace {
    /// To first order, of display values (exposure, clamp, sRGB), around a member-independent
    /// estimate m of the clean value (the median of the bank's results). SURE weighs each
    /// channel's term by the squared slope of the display transform at m (Stein's lemma needs a
    /// weight that does not depend on the filter). The halves weigh each output f's term by the
    /// squared secant slope between f and m, (D(f) − D(m)) / (f − m): it sees a highlight blurred
    /// from above the clamp to below it, which the tangent at a clamped m (slope 0) does not
    /// (docs/auto.md, "The display transform and the bank's median").
    Display,
    DisplayTangent,  ///< the slope at m for both estimators
    DisplayExact,    ///< halves only: the display transform applied to the values themselves
    Linear,          ///< squared error of the radiance
};

/// How SURE's divergence is estimated and the data perturbed.
struct SureOptions {
    /// Perturbation size relative to the pixel's own noise: ε = epsilon · σ per pixel and channel
    /// (Ramani et al. suggest ε of about σ/100; docs/auto.md, "Error estimation by SURE"),
    /// never below 1e-4 of |y| (or 1e-7) so that float rounding cannot swallow it.
    double epsilon = 0.01;
    std::uint64_t seed = 1;          ///< of the ±1 field b (hashed per pixel and channel)
    bool analyticDivergence = true;  ///< use Filter::divergence when the filter provides it
};

/// What autoComposite runs, from AutoOptions (its tuning resolved) and the input.
struct AutoSettings {
    AutoEstimator estimator = AutoEstimator::Sure;  ///< never Auto
    bool halves = false;                            ///< estimator == Halves
    int window = 0;
    double confidence = 0.0;
    /// The confidence is the family's (choice.h, familywiseMargin), not each comparison's.
    bool familywise = false;
    double temperature = 0.0;
    int finer = 0;
    int feather = 0;
    /// The display linearisation around the bank's median: the halves' Display by the secant to
    /// each output, SURE's Display and DisplayTangent by the slope there.
    bool secant = false;
    bool tangent = false;
    /// Halves, both sides, 0 < shortlist < the bank's size: every member on A first, both halves
    /// only for the shortlist.
    bool shortlisted = false;
    /// Halves, one side, 0 < shortlist < the bank's size: the final choice is made again among
    /// the shortlist's members, on the same maps.
    bool rechosen = false;
    /// Every member is filtered on both halves (symmetric without a shortlist).
    bool bothHalves = false;
    int stack = 0;  ///< members in the stacking (0: off)
    bool stackAlbedo = false;
    bool stackNormal = false;

    // The rest of the tuning, and the options as given.
    SureSpace space = SureSpace::Display;
    float exposure = 0.0f;
    int shortlist = 0;
    double featherGate = 0.0;
    SureOptions sure;
    ImageNoiseOptions imageNoise;  ///< estimator == Image
    int stackWindow = 0;
    double stackRidge = 0.0;
    double stackFloor = 0.0;
    int stackSmooth = 0;
    int stackFeatureWindow = 0;
    double stackNoiseGate = 0.0;
    bool prefilter = false;
    ParamValues prefilterParams;
    bool estimateError = false;  ///< AutoOptions::estimateError
};

/// The image-only estimator's settings from a resolved tuning map (noiseWindow, noiseAlpha,
/// noiseTail).
ImageNoiseOptions imageNoiseOptions(const ParamValues& tuning);

/// Checks `options` (validate), that `bank` was built from `frame` and that the options and the
/// input fit each other (checkAutoInput, the stacking's features), and resolves them. Throws
/// glint::Error as autoComposite documents.
AutoSettings resolveSettings(const FilterBank& bank, const FrameBuffers& frame,
                             const AutoOptions& options);

}  // namespace glint::denoise::detail

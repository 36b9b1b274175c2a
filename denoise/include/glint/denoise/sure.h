// The automatic local baseline: Stein's unbiased risk estimate (SURE) of every bank member's
// error at every pixel, from the render's variance of the mean and without a reference, then a
// per-pixel choice (or soft weights) among the members — the "auto" composite a painting session
// can start from (docs/auto.md, "Error estimation by SURE").
//
// Per pixel and channel, with y the noisy colour, σ² its variance of the mean and f the filter,
//   SURE = (f(y) − y)² − σ² + 2σ²·∂f/∂y                      (Stein 1981; summed over RGB)
// and the divergence of a black-box filter is estimated by Monte-Carlo SURE (Ramani, Blu & Unser
// 2008, eq. 8): one more application to y + ε·b, b a random ±1 field,
//   ∂f_p/∂y_p ≈ b_p (f(y + εb)_p − f(y)_p) / ε_p.
// A filter may give its divergence itself (Filter::divergence); the Gaussian does.
//
// A render with half buffers allows a second estimator without SURE's assumptions (Gaussian
// noise of known variance, guides independent of the colour): cross-validation on the two
// independent halves A and B of the samples, E(f(A) − B)² = MSE f(A) + Var B
// (docs/auto.md, "Error estimation by cross-validation on the halves").
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "glint/denoise/filter.h"
#include "glint/denoise/progress.h"
#include "glint/image/frame_buffers.h"
#include "glint/image/image.h"

namespace glint::denoise {

class FilterBank;
class Session;

/// Which error SURE estimates.
enum class SureSpace {
    Linear,  ///< squared error of the radiance
    /// To first order, of display values (exposure, clamp, sRGB), around a member-independent
    /// estimate m of the clean value (the median of the bank's results). SURE weighs each
    /// channel's term by the squared slope of the display transform at m (DisplayTangent; Stein's
    /// lemma needs a weight that does not depend on the filter). The halves weigh each output f's
    /// term by the squared secant slope between f and m, (D(f) − D(m)) / (f − m)
    /// (docs/auto.md, "Error estimation by cross-validation on the halves"): it sees a highlight
    /// blurred from above the clamp to below it, which the tangent at a clamped m (slope 0) does
    /// not.
    Display,
    DisplayTangent,  ///< the slope at m for both estimators (the halves' default before the
                     ///< secant; docs/auto.md, "The display transform and the bank's
                     ///< median")
    DisplayExact,    ///< halves only: the display transform applied to the values themselves
                     ///< (not the default:
                     ///< docs/research/auto-notebook.md measures it)
};

/// Parses "display" / "display-tangent" / "display-exact" / "linear"; throws
/// glint::Error(InvalidArgument) naming the expected names.
SureSpace parseSureSpace(const std::string& name);
/// The name parseSureSpace reads.
const char* sureSpaceName(SureSpace space);

/// How the divergence is estimated and the data perturbed.
struct SureOptions {
    /// Perturbation size relative to the pixel's own noise: ε = epsilon · σ per pixel and channel
    /// (Ramani et al. suggest ε of about σ/100; docs/auto.md, "Error estimation by SURE",
    /// measures it), never below 1e-4 of |y| (or 1e-7) so that float rounding cannot swallow it.
    double epsilon = 0.01;
    std::uint64_t seed = 1;          ///< of the ±1 field b (hashed per pixel and channel)
    bool analyticDivergence = true;  ///< use Filter::divergence when the filter provides it
};

/// How the auto composite estimates each member's error per pixel.
enum class AutoEstimator {
    Auto,    ///< Halves when the frame has half buffers, else Sure
    Sure,    ///< Stein's unbiased risk estimate from the variance layer (above)
    Halves,  ///< cross-validation on the render's two independent halves
};

/// Parses "auto" / "sure" / "halves"; throws glint::Error(InvalidArgument).
AutoEstimator parseAutoEstimator(const std::string& name);
/// "auto", "sure" or "halves".
const char* autoEstimatorName(AutoEstimator estimator);
/// The estimator Auto stands for with `frame` (the others as given).
AutoEstimator resolveEstimator(AutoEstimator estimator, const FrameBuffers& frame);

/// Throws glint::Error naming `file` and the place unless the auto composite can use `frame`
/// with `estimator`: for SURE, the variance layer (variance.R/G/B, the variance of the mean) and
/// finite colour and finite, non-negative variance at every pixel (Format for a missing layer,
/// Numeric for bad values); for the halves, every half-buffer layer
/// (glint::splitHalves) and finite colour and half colour.
void checkAutoInput(const FrameBuffers& frame, AutoEstimator estimator,
                    const std::string& file = {});

/// The smoothing window, confidence, temperature, finer window, feathering and stacking an
/// estimator uses unless told otherwise, measured on the quality table of docs/auto.md (and
/// chosen in docs/research/auto-notebook.md):
/// SURE 4, 3, 0 (a hard choice), no finer window, feather 4 and no stacking; the halves 8, 1,
/// 0.06, 1, 5 and 6 members (their maps are noisier per pixel: a wider window with a lower bar
/// wins on every scene, slightly soft weights blend members whose estimates are within the
/// noise of each other instead of picking one by that noise, and the window halved once
/// decides where its evidence is clear).
struct AutoDefaults {
    int window;
    double confidence;
    double temperature;
    int finer;
    int feather;
    int stack;  ///< with both halves (AutoOptions::symmetric); one-sided: 0
};
AutoDefaults autoDefaults(AutoEstimator estimator);

/// How the auto composite is chosen.
struct AutoOptions {
    /// The error estimate per member and pixel.
    AutoEstimator estimator = AutoEstimator::Auto;
    /// Halves: filter both halves (two applications per member) rather than only A (one).
    bool symmetric = true;
    /// Halves, symmetric: how many members are filtered on both halves. Every member is
    /// filtered on A and chosen among by its one-sided estimate first; then the `shortlist`
    /// members that carry the largest weight at the most pixels in that first choice are
    /// filtered on B too, and the final choice is among them, by their symmetric estimate
    /// (docs/auto.md, "Shortlist"). 0, or at least the bank's size: every member on both
    /// halves, the choice among all.
    int shortlist = 16;
    SureOptions sure;
    SureSpace space = SureSpace::Display;
    float exposure = 0.0f;  ///< of the display transform (the display spaces)
    /// The error maps are box-averaged over (2·window + 1)² pixels before the choice: a
    /// per-pixel estimate from a few samples is itself noisy. Unset: the estimator's default
    /// (autoDefaults).
    std::optional<int> window;
    /// A pixel leaves the baseline (the member with the smallest estimate over the whole
    /// region) only for a member whose smoothed estimate is lower by at least `confidence`
    /// standard errors of the local mean (estimated from the spread of the difference in the
    /// window): the per-pixel choice among many members must not follow the noise of their
    /// estimates. Unset: the estimator's default (autoDefaults).
    std::optional<double> confidence;
    /// The final choice also looks through the window halved this many times (radius window/2,
    /// window/4 …, at least 1), with the same confidence, and scores each member by the lowest
    /// of them: a small window decides where its estimate is clear enough, the full window
    /// elsewhere. 0: the full window only. Unset: the estimator's default (autoDefaults).
    std::optional<int> finer;
    /// 0: a hard per-pixel choice (the smallest score). > 0: soft weights
    /// exp(−(score − min score) / (temperature · σ²)), σ² the pixel's smoothed variance summed
    /// over RGB (so the temperature is in units of the noise), weights below 1e-3 of the
    /// largest dropped. Unset: the estimator's default (autoDefaults).
    std::optional<double> temperature;
    /// Feathering: each member's weight plane is box-averaged over (2·feather + 1)² pixels
    /// before the composite, so that the choice changes from member to member over a few
    /// pixels instead of from one pixel to the next — except where the member's display value
    /// (exposure, clamp, sRGB) differs from the unfeathered composite's by more than
    /// `featherGate` in some channel: there it gets no weight from its neighbours (a blur
    /// chosen around a small light must not spread into the light). Then the weights are
    /// renormalised (a pixel where all are gated takes its largest-weight member alone). 0: off.
    /// Unset: the estimator's default (autoDefaults). docs/auto.md, "Feathering".
    std::optional<int> feather;
    double featherGate = 0.2;
    /// Stacking (halves, both sides; docs/auto.md, "Stacking"): the `stack` members
    /// with the largest total weight (at most 16) correct the composite c per pixel to
    /// c + Σ a_i (f_i − c). The a_i are fitted over (2·stackWindow + 1)² pixels by a ridge
    /// regression of each half on the members' results on the other half (weighted by the
    /// squared display slope at c); the ridge is `stackRidge` times the halves' noise there
    /// plus `stackFloor` times the regressors' mean squared difference from c (the members' and
    /// the features', below). With `stackSmooth`
    /// > 0 each pixel applies the a_i averaged over the (2·stackSmooth + 1)² pixels around it:
    /// every window's fit applied to every pixel it covers, averaged, as the guided filter does
    /// (0: each pixel's own fit). The a_i may be negative or sum past 1, so the result is no
    /// longer a blend of the members: a session cannot start from it (startFromAuto; ask for
    /// 0). 0: off. Unset: the estimator's default (autoDefaults: 6 for the halves, 0 one-sided
    /// and for SURE, which cannot stack). Keeps every member's result on half A until the
    /// shortlist is chosen: as much memory again as the bank's results.
    std::optional<int> stack;
    int stackWindow = 6;
    double stackRidge = 0.5;
    double stackFloor = 0.1;
    int stackSmooth = 8;
    /// The stacking's feature regressors (docs/auto.md, "Stacking"): besides the members,
    /// the fit takes each feature's local deviation from its box average over
    /// (2·stackFeatureWindow + 1)² pixels, times c — the albedo's relative deviation in each
    /// colour channel (one regressor) and each axis of the normal (three) — from the whole
    /// frame's features for c and from each half's for the blend on that half. Where the blend
    /// smooths over an albedo or shading edge the features mark, the fit puts the edge back.
    /// Unset: each feature the input has (with its half layer); true: the feature must be
    /// there (autoComposite throws Error(Format) naming the layer otherwise); false: off.
    std::optional<bool> stackAlbedo;
    std::optional<bool> stackNormal;
    int stackFeatureWindow = 3;
    /// The bank was built on prefiltered features: the perturbed input is prefiltered alike.
    bool prefilter = false;
    ParamValues prefilterParams;
    /// The fraction of the work done, through every stage (docs/auto.md, "Stages"); returning
    /// false stops: autoComposite throws Error(Cancelled).
    ProgressFn progress;
};

/// Throws glint::Error(InvalidArgument) naming the first bad option.
void validate(const AutoOptions& options);

/// One member used by the auto composite and its weight there.
struct AutoLayer {
    int member = -1;
    Image weights;  ///< 1 channel, region-sized, in [0, 1]; the layers' weights sum to 1
};

/// The auto composite of a bank.
struct AutoResult {
    Image composite;  ///< 3 channels, region-sized: Σ weights · member result (unless stacked)
    Image choice;     ///< 1 channel: per pixel, the member with the largest weight (as float)
    std::vector<AutoLayer> layers;  ///< members with any weight, by total weight, largest first
    /// Per member: the mean estimate per channel over the region (with a shortlist: the
    /// symmetric estimate for its members, the one-sided one for the others).
    std::vector<double> estimatedMse;
    int bestMember = -1;         ///< the smallest estimatedMse among the members chosen from (the
                                 ///< shortlist, when there is one): auto's single choice
    std::vector<bool> analytic;  ///< per member: the filter gave its divergence
    AutoEstimator estimator = AutoEstimator::Sure;  ///< the estimator used (never Auto)
    /// The members the stacking fitted (AutoOptions::stack): > 0, the composite is the stacked
    /// one and `layers` and `choice` are the blend it corrected; 0, the composite is the blend.
    int stacked = 0;
    /// The feature regressors the stacking fitted besides them (AutoOptions::stackAlbedo and
    /// stackNormal: 1 for the albedo, 3 for the normal).
    int stackFeatures = 0;
};

/// Computes every member's error map — SURE (one extra application of each member to the
/// perturbed input) or cross-validation on the halves (one application to A, and one to B for
/// the shortlist or every member) — with members in parallel in the caller's TBB pool, smooths
/// them and builds the composite.
/// With the halves, estimatedMse is a member's error on a half of the samples.
/// `frame` is the input the bank was built from (checked by hash). Deterministic for a seed,
/// whatever the thread count. Throws glint::Error like checkAutoInput, InvalidArgument for a
/// bank of another frame or bad options, Cancelled when progress says stop.
AutoResult autoComposite(const FilterBank& bank, const FrameBuffers& frame,
                         const AutoOptions& options = {});

/// Starts a painting session from the auto composite: one layer per AutoLayer (largest first,
/// output taken from the bank) with the weights that make the session's left-to-right blend
/// equal Σ weights · result (up to float rounding). The bank must cover the whole frame and be
/// of the session's filter input, and the result not stacked (AutoOptions::stack). Returns how many
/// session edits were made (two per layer: added, weights set). Throws
/// glint::Error(InvalidArgument) otherwise (nothing changes then).
std::size_t startFromAuto(Session& session, const FilterBank& bank, const AutoResult& result);

}  // namespace glint::denoise

// The automatic selection ("auto", docs/auto.md): every bank member's error estimated at every
// pixel without a reference, then a per-pixel choice (or soft weights) among the members, the
// composite a painting session can start from. Two estimators (and SURE with a variance estimated
// from the image when the render has neither its variance nor half buffers):
// - SURE, Stein's unbiased risk estimate from the render's variance of the mean, with a
//   Monte-Carlo divergence for black-box filters (Stein 1981; Ramani, Blu & Unser 2008);
// - cross-validation on the render's two independent halves A and B of the samples,
//   E(f(A) − B)² = MSE f(A) + Var B, without SURE's assumptions.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "glint/denoise/denoised_frame.h"
#include "glint/denoise/filter.h"
#include "glint/denoise/progress.h"
#include "glint/image/frame_buffers.h"
#include "glint/image/image.h"

namespace glint::denoise {

class FilterBank;
class Session;

/// How the auto composite estimates each member's error per pixel.
enum class AutoEstimator {
    Auto,  ///< Halves when the frame has half buffers, else Sure with a variance layer, else Image
    Sure,  ///< Stein's unbiased risk estimate from the variance layer (above)
    Halves,  ///< cross-validation on the render's two independent halves
    /// SURE with the variance of the mean estimated from the colour and its features (any
    /// variance layer is not read; docs/auto.md, "Error estimation without variance or halves")
    Image,
};

/// Parses "auto" / "sure" / "halves" / "image"; throws glint::Error(InvalidArgument).
AutoEstimator parseAutoEstimator(const std::string& name);
/// "auto", "sure", "halves" or "image".
const char* autoEstimatorName(AutoEstimator estimator);
/// The estimator Auto stands for with `frame` (the others as given).
AutoEstimator resolveEstimator(AutoEstimator estimator, const FrameBuffers& frame);

/// Throws glint::Error naming `file` and the place unless the auto composite can use `frame`
/// with `estimator`: for SURE, the variance layer (variance.R/G/B, the variance of the mean) and
/// finite colour and finite, non-negative variance at every pixel (Format for a missing layer,
/// Numeric for bad values); for the halves, every half-buffer layer
/// (glint::splitHalves) and finite colour and half colour; for the image-only estimator, finite
/// colour.
void checkAutoInput(const FrameBuffers& frame, AutoEstimator estimator,
                    const std::string& file = {});

/// The tuning map's parameters (window, confidence, feathering, stacking …), described as
/// filters describe theirs: name, range, default with the halves, one-line help. glint-lab
/// auto's flags and the tuning table of docs/lab/auto-tuning.md are generated from them. Where
/// SURE's default differs, autoTuningDefaults gives it.
const std::vector<ParamSpec>& autoTuningSpecs();
/// Every tuning parameter's default with `estimator` (Auto: as the halves).
ParamValues autoTuningDefaults(AutoEstimator estimator);
/// The command-line flag of a tuning parameter, which errors name: featherGate → --feather-gate
/// (an integer parameter over 0 … 1 that defaults to 0 is a flag without a value).
std::string autoTuningFlag(const std::string& name);

/// The trade of time for quality an artist picks (glint-denoise auto --quality; docs/auto.md,
/// "Command line"): each is a bank size and tuning overrides the lab measured (docs/lab/).
enum class AutoQuality {
    Fast,      ///< 32 members, the halves filtered one-sided (no shortlist, no stacking)
    Balanced,  ///< the defaults: 64 members, the tuning's defaults
    Best,      ///< 128 members, the tuning's defaults
};
/// Parses "fast" / "balanced" / "best"; throws glint::Error(InvalidArgument).
AutoQuality parseAutoQuality(const std::string& name);
/// "fast", "balanced" or "best".
const char* autoQualityName(AutoQuality quality);
/// The tuning a quality sets (AutoOptions::tuning; Balanced: none, the defaults).
ParamValues autoQualityTuning(AutoQuality quality);
/// The Latin-hypercube members of the bank auto builds at a quality (BankOptions::size).
int autoQualityBankSize(AutoQuality quality);

/// How the auto composite is chosen: what a user sets, and a tuning map for the rest.
struct AutoOptions {
    /// The error estimate per member and pixel.
    AutoEstimator estimator = AutoEstimator::Auto;
    float exposure = 0.0f;  ///< stops, of the display transform the error is measured in
    /// Whether the result may be stacked (a regression on the members, docs/auto.md,
    /// "Stacking"), which the halves do by default. A session starts from a stacked result too
    /// (startFromAuto adds the stacking's correction as a layer of its own).
    bool allowStacking = true;
    std::uint64_t seed = 1;  ///< of SURE's random ±1 perturbation
    /// Tuning parameters by name (autoTuningSpecs); missing names take the estimator's default.
    ParamValues tuning;
    /// The bank was built on prefiltered features (BankOptions::prefilter): the halves and the
    /// perturbed input are prefiltered alike.
    bool prefilter = false;
    ParamValues prefilterParams;
    /// The fraction of the work done, through every stage (docs/auto.md, "Stages"); returning
    /// false stops: autoComposite throws Error(Cancelled).
    ProgressFn progress;
    /// Bytes the selection may allocate besides its input frame and a given bank's results: the
    /// height of its tiles follows (docs/auto-memory.md). 0: the default, 1.25 GiB (or the
    /// memory available, availableMemory(), when less); a limit only lowers it. The result
    /// does not depend on it.
    std::uint64_t memoryLimit = 0;
    /// Also estimate the result's error per pixel (AutoResult::error); needs the halves
    /// estimator. Costs the final members' applications on the halves unless the stacking
    /// makes them anyway.
    bool estimateError = false;
};

/// The bytes the selection's tiles may take for AutoOptions::memoryLimit `limit`: 1.25 GiB,
/// lowered to `limit` (0: to the memory available, availableMemory(), which
/// GLINT_MEMORY_LIMIT lowers).
std::uint64_t autoMemoryBudget(std::uint64_t limit);

/// Throws glint::Error(InvalidArgument) naming the first bad option (a tuning parameter by its
/// flag, e.g. "--window").
void validate(const AutoOptions& options);

/// The tuning autoComposite uses with `estimator` (resolved, not Auto): `options.tuning` over
/// the estimator's defaults, validated (throws as validate).
ParamValues resolveAutoTuning(const AutoOptions& options, AutoEstimator estimator);

/// `frame` with its variance layer set to the image-only estimate (AutoEstimator::Image, its
/// tuning from `options`): for building the bank on a render without variance, so that filters
/// that read the variance see the one auto uses. Throws like checkAutoInput.
FrameBuffers withImageNoiseVariance(const FrameBuffers& frame, const AutoOptions& options);

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
    /// The height of the tiles (strips of rows) the selection ran in: the region's height when
    /// it was one tile (AutoOptions::memoryLimit).
    int tileRows = 0;
    /// With AutoOptions::estimateError (else empty): 1 channel, region-sized, the estimated mean
    /// squared error per channel of the blend (before any stacking) on half the samples, in
    /// display values (exposure, clamp, sRGB; each linear error weighted by the display's squared
    /// secant slope to the result), by cross-validation on the halves (the blend on each half
    /// against the other half), box-averaged over the choice's window, at least 0.
    Image error;
};

/// Computes every member's error map — SURE (one extra application of each member to the
/// perturbed input) or cross-validation on the halves (one application to A, and one to B for
/// the shortlist or every member) — with members in parallel in the caller's TBB pool, smooths
/// them and builds the composite. Tiled in strips of rows whose height follows
/// options.memoryLimit (one tile when the region fits): the same floats for any tiling.
/// With the halves, estimatedMse is a member's error on a half of the samples.
/// `frame` is the input the bank was built from (checked by hash). Deterministic for a seed,
/// whatever the thread count. Throws glint::Error like checkAutoInput, InvalidArgument for a
/// bank of another frame or bad options, Cancelled when progress says stop.
AutoResult autoComposite(const FilterBank& bank, const FrameBuffers& frame,
                         const AutoOptions& options = {});

/// Starts a painting session from the auto composite: one layer per AutoLayer (largest first,
/// output taken from the bank, or run by the session for a bank without results) with the
/// weights that make the session's left-to-right blend equal Σ weights · result (up to float
/// rounding), then, unless that blend is already the composite bit for bit, auto's correction
/// (Session::addCorrection, weight 1 everywhere): the stacking's correction and the blend's
/// rounding, so that the session's composite is result.composite bit for bit. The bank must
/// cover the whole frame and be of the session's filter input. Returns how many session edits
/// were made (two per layer: added, weights set). Throws glint::Error(InvalidArgument)
/// otherwise (nothing changes then).
std::size_t startFromAuto(Session& session, const FilterBank& bank, const AutoResult& result);

}  // namespace glint::denoise

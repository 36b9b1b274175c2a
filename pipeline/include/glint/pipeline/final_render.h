// glint::pipeline — a final frame: render and denoise a scene to a time or error target
// (docs/final-render.md). Adaptive passes steered by the automatic selection's per-pixel error of
// the denoised image (the renderer's Callbacks::importance), auto on the frame as it grows, and
// the denoised frame with the render's layers. The renderer and the denoiser never include each
// other; this module holds both.
#pragma once

#include <functional>
#include <string>

#include "glint/denoise/auto.h"
#include "glint/image/frame_buffers.h"
#include "glint/render/renderer.h"
#include "glint/render/settings.h"

namespace glint::pipeline {

/// What steers the adaptive passes after the uniform start.
enum class Steering {
    /// The renderer's error times auto's relative error of the denoised image (steering.h),
    /// refreshed as the frame grows, under the threshold schedule below.
    Denoiser,
    /// The renderer's error alone, under the same threshold schedule (weights all alike).
    Variance,
    /// The renderer's adaptive sampling at its fixed noise threshold (Cycles'): no refresh.
    Fixed,
};

/// The steering glint-final uses: the renderer's variance under a time limit without an error
/// target (there a refresh's seconds are worth more as samples: at 15–60 s on 2 threads the
/// denoiser-steered map lost to it on dof and cornell and never beat the fixed threshold,
/// docs/lab/adaptive-sampling.md), auto's map otherwise (an error target runs auto at each
/// refresh anyway; a spp bound alone loses no samples to it).
Steering defaultSteering(double timeLimit, double targetError);
/// Parses "denoiser" / "variance" / "fixed"; throws glint::Error(InvalidArgument).
Steering parseSteering(const std::string& name);
/// "denoiser", "variance" or "fixed".
const char* steeringName(Steering steering);

/// The largest error target (estimated relMSE) and the longest time limit accepted.
inline constexpr double kMaxTargetError = 1e6;
/// The side of the centred crop of the first pass on which auto's cost is probed (time limit).
inline constexpr int kProbeSide = 64;
/// The probe's runs: the fastest calibrates auto's cost (a run slowed by the machine's load
/// would make every plan look slower; three of about 0.03 s take under 0.1 s).
inline constexpr int kProbeRuns = 3;

/// Where the whole frame was probed, it is probed once more at the first pass's end whose time
/// left is within this share of the limit past the final auto's reserve (the render about to
/// stop), and that run calibrates auto's cost: the load changes within a run.
inline constexpr double kLateProbeShare = 0.1;

/// The final auto's clock reads for its deadline (renderFinal): at the first progress report past
/// each 1/kDeadlineChecks of its work.
inline constexpr int kDeadlineChecks = 32;

/// The probe runs once more on the whole frame when its predicted time is at most this share of
/// the time limit (256² at 2 threads: from about 8 s), and that run calibrates auto's cost.
inline constexpr double kFrameProbeShare = 0.04;

/// How the final frame is made.
struct FinalOptions {
    /// The render's settings. Adaptive sampling is what the steering steers (off: uniform passes,
    /// then auto once); half buffers are always on (auto's error estimate needs them); spp is the
    /// most a pixel takes (0: only the targets end the render).
    render::Settings settings;
    /// Seconds for the whole: the render, auto's refreshes and the final auto; 0: none. The first
    /// pass always completes (FinalResult::overTime says when it alone took longer).
    double timeLimit = 0.0;
    /// Stop once auto's estimated relMSE of the denoised image (estimatedRelMse) is at most this;
    /// 0: none. Checked at each refresh.
    double targetError = 0.0;
    Steering steering = Steering::Denoiser;
    /// Refresh (run auto) before the first adaptive pass and then whenever the mean samples per
    /// pixel have grown by this factor since the last refresh (> 1).
    double refreshGrowth = 2.0;
    /// Steered adaptive passes (Steering::Variance, Steering::Denoiser) leave a pixel closed
    /// while it has at least this many times the frame's mean samples per pixel (capSamples);
    /// 0: no cap. The fixed threshold is Cycles' and is not capped.
    double sppCapRatio = 16.0;
    /// The automatic selection (the halves estimator; AutoOptions::estimateError is set here).
    denoise::AutoOptions autoOptions;
    /// The final auto's quality; under a time limit the most it runs at: a cheaper plan
    /// (choosePlan: fast, then fewer members) when this one does not fit its share.
    denoise::AutoQuality quality = denoise::AutoQuality::Balanced;
    /// The quality of the refreshes (and of the probe that calibrates auto's cost).
    denoise::AutoQuality refreshQuality = denoise::AutoQuality::Fast;
    /// With a time limit, the most of it the refreshes take together, in (0, 1] (TimeBudget).
    double refreshShare = 0.2;
    /// With a time limit, the most of it the final auto's plan is chosen to take, in (0, 1]:
    /// the render gets the rest.
    double finalShare = 0.5;
    /// Seconds the final auto at `quality` is expected to take on this film: it calibrates auto's
    /// cost model (AutoCost) instead of a probe; 0: a probe on a crop of the first pass
    /// (kProbeSide, the fastest of kProbeRuns runs; kFrameProbeShare) calibrates it.
    double expectedAutoSeconds = 0.0;
    /// Seconds since any fixed time, for the time limit; empty: std::chrono::steady_clock.
    /// (The renderer's own pass sizing reads the steady clock; with a clock here the limit is
    /// kept by this clock alone.) Tests pass a fake one.
    std::function<double()> clock;
    /// One line per refresh and stage, for a log; may be empty.
    std::function<void(const std::string& line)> log;
};

/// Throws glint::Error(InvalidArgument) naming the first bad option ("timeLimit",
/// "targetError", "refreshGrowth", "sppCapRatio", "refreshShare", "finalShare", "spp") and what
/// was expected: a time limit or error target not NaN, ≥ 0 and at most kMaxTimeLimit /
/// kMaxTargetError; a samples cap of 0 or in [1, 1e6]; shares in (0, 1]; some end (a time limit,
/// an error target or a spp); render::validate's for the settings.
void validate(const FinalOptions& options);

/// What a final render made.
struct FinalResult {
    /// The render's layers (half buffers included) with the colour replaced by the denoised
    /// image and the render's own colour kept as the noisy layer (denoise::denoisedFrame;
    /// metadata denoiseFilter = auto): denoise::renderOf gives the render back.
    FrameBuffers frame;
    render::RenderStats render;    ///< the render's statistics (seconds: the render's)
    double estimatedRelMse = 0.0;  ///< of the final denoised image (estimatedRelMse)
    int refreshes = 0;             ///< auto's runs during the render
    double autoSeconds = 0.0;      ///< every auto run, the final one included
    double refreshSeconds = 0.0;   ///< the refreshes' share of autoSeconds
    /// The final auto's plan (describe(AutoPlan): "balanced", "fast with 8 members", …) and its
    /// predicted seconds (0 without a time limit).
    std::string finalPlan;
    double predictedFinalSeconds = 0.0;
    /// The plan of a final auto that passed its deadline (the limit less the cheapest plan's
    /// reserve: the machine slowed after the prediction) and was stopped, cheapestPlan() then
    /// denoising the frame (finalPlan); empty when none was.
    std::string finalStopped;
    /// Times every pixel had converged with time left and the threshold was halved (the render
    /// went on; time limit only).
    int thresholdHalvings = 0;
    double seconds = 0.0;        ///< all of it
    bool targetReached = false;  ///< stopped at the error target
    /// The time limit was too short for the first pass and the cheapest auto: the frame is that
    /// one pass, denoised by cheapestPlan().
    bool overTime = false;
};

/// Renders `renderer`'s scene with options.settings and denoises it (auto), steering the
/// adaptive passes, until the time limit, the error target, spp or convergence ends the render.
/// Under a time limit convergence does not end it: every pixel converged, the threshold is
/// halved (the map's weights doubled) and the render goes on until the time left is the final
/// auto's reserve (TimeBudget). Deterministic for any thread count without a time limit. Throws as
/// validate, the renderer and autoComposite do.
FinalResult renderFinal(render::Renderer& renderer, const FinalOptions& options);

}  // namespace glint::pipeline

// The final render's loop (final_render.h; docs/final-render.md): adaptive passes, auto on the
// frame as it grows (a refresh), the importance map from auto's error, the targets.
#include "glint/pipeline/final_render.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>

#include "glint/denoise/denoised_frame.h"
#include "glint/image/error.h"
#include "glint/pipeline/refresh.h"
#include "glint/pipeline/steering.h"
#include "glint/pipeline/time_budget.h"

namespace glint::pipeline {

namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point t) {
    return std::chrono::duration<double>(Clock::now() - t).count();
}

/// The most the threshold is lowered at convergence (2^40: past it no pixel is left to open).
constexpr double kMaxBoost = 1099511627776.0;

std::string formatted(const char* format, double a, double b, double c) {
    char buf[200];
    std::snprintf(buf, sizeof buf, format, a, b, c);
    return buf;
}

}  // namespace

Steering defaultSteering(double timeLimit, double targetError) {
    return timeLimit > 0.0 && targetError <= 0.0 ? Steering::Variance : Steering::Denoiser;
}

Steering parseSteering(const std::string& name) {
    if (name == "denoiser") return Steering::Denoiser;
    if (name == "variance") return Steering::Variance;
    if (name == "fixed") return Steering::Fixed;
    throw Error(ErrorKind::InvalidArgument,
                "unknown steering '" + name + "' (expected denoiser, variance or fixed)", {},
                "steering");
}

const char* steeringName(Steering steering) {
    switch (steering) {
        case Steering::Denoiser:
            return "denoiser";
        case Steering::Variance:
            return "variance";
        case Steering::Fixed:
            return "fixed";
    }
    return "?";
}

void validate(const FinalOptions& options) {
    auto bad = [](const std::string& where, const std::string& what) {
        throw Error(ErrorKind::InvalidArgument, what, {}, where);
    };
    if (!(options.timeLimit >= 0.0 && options.timeLimit <= render::kMaxTimeLimit))
        bad("timeLimit", "the time limit must be a number of seconds in [0, 1e7], got " +
                             numberText(options.timeLimit));
    if (!(options.targetError >= 0.0 && options.targetError <= kMaxTargetError))
        bad("targetError", "the error target must be an estimated relMSE in (0, 1e6], got " +
                               numberText(options.targetError));
    if (!(options.refreshGrowth > 1.0 && options.refreshGrowth <= 1e6))
        bad("refreshGrowth", "the refresh growth must be a factor in (1, 1e6], got " +
                                 numberText(options.refreshGrowth));
    if (!(options.sppCapRatio == 0.0 || (options.sppCapRatio >= 1.0 && options.sppCapRatio <= 1e6)))
        bad("sppCapRatio",
            "the samples cap must be 0 (off) or a factor of the mean in [1, 1e6], got " +
                numberText(options.sppCapRatio));
    if (!(options.refreshShare > 0.0 && options.refreshShare <= 1.0))
        bad("refreshShare", "the refreshes' share of the time limit must be in (0, 1], got " +
                                numberText(options.refreshShare));
    if (!(options.finalShare > 0.0 && options.finalShare <= 1.0))
        bad("finalShare", "the final auto's share of the time limit must be in (0, 1], got " +
                              numberText(options.finalShare));
    if (options.settings.spp <= 0 && options.timeLimit <= 0.0)
        bad("spp", options.targetError > 0.0
                       ? "an error target needs a time limit or a spp too (it may never be reached)"
                       : "nothing would end the render: give a time limit, an error target with a "
                         "spp, or a spp");
    render::Settings settings = options.settings;
    settings.halfBuffers = true;
    settings.timeLimit = options.timeLimit;
    render::validate(settings);
}

FinalResult renderFinal(render::Renderer& renderer, const FinalOptions& options) {
    validate(options);
    // The time since the start, on the options' clock or the steady clock.
    const Clock::time_point steadyStart = Clock::now();
    const double clockStart = options.clock ? options.clock() : 0.0;
    auto now = [&] {
        return options.clock ? options.clock() - clockStart : secondsSince(steadyStart);
    };
    auto log = [&](const std::string& line) {
        if (options.log) options.log(line);
    };
    render::Settings settings = options.settings;
    settings.halfBuffers = true;
    // On the options' clock the loop alone keeps the limit (its cancel below): the renderer's
    // steady clock must not end the render first on a slow machine.
    settings.timeLimit =
        options.clock && options.timeLimit > 0.0 ? render::kMaxTimeLimit : options.timeLimit;
    TimeBudget budget(options.timeLimit, options.refreshShare, 0.0);

    // Auto with a plan (refresh.h, as the studio's refreshes run it), timed on the options' clock.
    // With a deadline (> 0) it stops once the clock, read at kDeadlineChecks of its progress
    // reports, has passed it (Error(Cancelled), and `*late` set).
    auto denoised = [&](const FrameBuffers& frame, const AutoPlan& plan, double deadline = 0.0,
                        bool* late = nullptr) {
        const double t = now();
        AutoRun run = autoRun(options.autoOptions, plan.quality, plan.bankSize, plan.filters);
        if (deadline > 0.0) {
            // The reports are serialised (denoise/progress.h); the clock is read at the first
            // report past each 1/kDeadlineChecks of the work.
            auto next = std::make_shared<double>(0.0);
            run.autoOptions.progress = [outer = run.autoOptions.progress, next, deadline, late,
                                        &now](double fraction) {
                if (outer && !outer(fraction)) return false;
                if (fraction < *next) return true;
                *next = fraction + 1.0 / double(kDeadlineChecks);
                if (now() < deadline) return true;
                if (late) *late = true;
                return false;
            };
        }
        Denoised d = denoiseFrame(frame, run);
        d.seconds = now() - t;
        return d;
    };

    FinalResult out;
    // Auto's cost (time_budget.h): calibrated at the first frame (expectedAutoSeconds, or a probe
    // on a crop) and by each refresh; the final auto's plan is the best that fits its share.
    AutoCost cost;
    const AutoPlan most{options.quality, 0, {}};
    const AutoPlan refreshPlan{options.refreshQuality, 0, {}};
    AutoPlan finalPlan = most;
    double pixels = 0.0;
    // The final auto's plan for the time left at `t` (within its share of the limit; of the
    // plans that fit, while the render goes on the one that leaves the least error with the
    // render it leaves time for, after it the best), and the render's reserve for it.
    bool rendering = true;
    auto finalSeconds = [&](double t) {
        return std::min(options.finalShare * options.timeLimit, options.timeLimit - t);
    };
    auto plan = [&](double t) {
        const RenderTime render =
            rendering ? RenderTime{std::max(0.0, t - out.autoSeconds), options.timeLimit - t}
                      : RenderTime{};
        finalPlan = choosePlan(cost, pixels, finalSeconds(t), most, render);
        budget.expectFinal(cost.seconds(finalPlan, pixels), finalReserve(cost, finalPlan, pixels));
    };
    double frameProbe = 0.0;  // seconds of the whole frame's probe (kFrameProbeShare; 0: none)
    bool lateProbed = false;  // … and of its late run (kLateProbeShare)
    // The cost model's first calibration, on the first frame the render shows (time limit only).
    auto calibrate = [&](const FrameBuffers& frame) {
        if (!budget.timed() || cost.calibrated()) return;
        pixels = double(frame.width()) * double(frame.height());
        if (options.expectedAutoSeconds > 0.0) {
            cost.calibrate(most, pixels, options.expectedAutoSeconds);
        } else {
            // The cheapest plan, which loads nothing a first run loads once (the unet's
            // weights), on a crop: a few hundredths of the final auto's time. The fastest of
            // its runs is the machine's speed; a slower one met some other load.
            const FrameBuffers probe = probeFrame(frame, kProbeSide);
            double fastest = 0.0, slowest = 0.0;
            for (int run = 0; run < kProbeRuns; ++run) {
                const double seconds = denoised(probe, cheapestPlan()).seconds;
                out.autoSeconds += seconds;
                fastest = run == 0 ? seconds : std::min(fastest, seconds);
                slowest = std::max(slowest, seconds);
            }
            const double probePixels = double(probe.width()) * double(probe.height());
            cost.probed(probePixels, fastest);
            // Where it takes little of the limit the plan runs once on the whole frame too: what
            // a crop's pixel costs against a frame's depends on the machine (its caches), and a
            // run of a tenth of a second meets fewer of the load's moments than one of 0.01 s.
            if (probePixels < pixels &&
                cost.seconds(cheapestPlan(), pixels) <= kFrameProbeShare * options.timeLimit) {
                const double seconds = denoised(frame, cheapestPlan()).seconds;
                out.autoSeconds += seconds;
                cost.probedFrame(pixels, seconds);
                frameProbe = seconds;
                log(formatted("probe of the whole frame: auto %.3f s on %.0f pixels", seconds,
                              pixels, 0.0));
            }
            log(formatted("probe: auto %.3f s (the fastest of its runs; the slowest %.3f s) on "
                          "%.0f pixels",
                          fastest, slowest, probePixels) +
                formatted(": the final auto predicted at %.2f s", cost.seconds(most, pixels), 0,
                          0));
            plan(now());
            // A final auto on the default bank would pay the process's cold start (the unet's
            // weights and plans: 0.1–1.1 s, longer under load) inside its reserve: the
            // default bank's smallest plan on the crop pays it now, and the plan is chosen again
            // warm, from the time then left.
            if (finalPlan.filters.empty() && !cost.warm()) {
                const double seconds = denoised(probe, warmupPlan()).seconds;
                out.autoSeconds += seconds;
                cost.ran(warmupPlan());
                log(
                    formatted("warm-up: auto %.3f s on %.0f pixels (the default bank's first "
                              "run)",
                              seconds, probePixels, 0.0));
            }
        }
        plan(now());
        log("final auto planned: " + describe(finalPlan) +
            formatted(", %.2f s predicted, %.2f s reserved of %.2f", budget.expectedFinal(),
                      budget.reserve(), options.timeLimit));
    };

    // The calibration at a pass's end: the first (calibrate), then, where the whole frame was
    // probed, once more when the render is about to stop (the time left within kLateProbeShare of
    // the limit past the reserve): a load that came since the first pass slows the final auto
    // too. The slower of the two runs calibrates (a run is one moment of a load that comes and
    // goes: the limit is kept before the time is used).
    auto measure = [&](const FrameBuffers& frame) {
        calibrate(frame);
        if (frameProbe <= 0.0 || lateProbed ||
            now() + budget.reserve() + kLateProbeShare * options.timeLimit < options.timeLimit)
            return;
        lateProbed = true;
        const double seconds = denoised(frame, cheapestPlan()).seconds;
        out.autoSeconds += seconds;
        cost.probedFrame(pixels, std::max(seconds, frameProbe));
        plan(now());
        log(formatted("late probe of the whole frame: auto %.3f s; the final auto: ", seconds, 0,
                      0) +
            describe(finalPlan) +
            formatted(", %.2f s predicted, %.2f s reserved", budget.expectedFinal(),
                      budget.reserve(), 0));
    };

    std::optional<Denoised> last;  // the latest refresh's result
    double lastSpp = 0.0, startSpp = 0.0;
    double lastRefresh = 0.0;  // seconds the latest refresh took
    bool stop = false;         // the error target is reached
    int pass = 0;              // the pass under way (progress)
    const bool steered = options.steering != Steering::Fixed;
    // Auto's error is needed to steer by it, or to check the target.
    const bool autoSteers = options.steering == Steering::Denoiser || options.targetError > 0.0;
    // The map's scale: the threshold schedule's √(spp / spp at the first refresh), times 2 for
    // every halving of the threshold at convergence.
    double boost = 1.0;
    auto scaleNow = [&] { return boost * (startSpp > 0.0 ? std::sqrt(lastSpp / startSpp) : 1.0); };
    // A refresh: auto on the frame so far, when it has grown enough and the budget has room;
    // true when the schedule moved (a new map is due).
    auto refresh = [&](const FrameBuffers& frame) {
        measure(frame);
        const double spp = meanSpp(frame);
        if (lastSpp > 0.0 && spp < options.refreshGrowth * lastSpp) return false;
        if (!autoSteers) {
            // The variance schedule needs no auto: its scale follows the spp alone.
            if (startSpp == 0.0) startSpp = spp;
            lastSpp = spp;
            return true;
        }
        // A refresh is expected to take what the cost model predicts (the latest's time
        // without one).
        const double expected = cost.calibrated() ? cost.seconds(refreshPlan, pixels) : lastRefresh;
        if (!budget.refreshFits(now(), expected)) return false;
        const bool first = !last;
        last = denoised(frame, refreshPlan);
        lastRefresh = last->seconds;
        budget.refreshed(last->seconds);
        out.autoSeconds += last->seconds;
        out.refreshSeconds += last->seconds;
        ++out.refreshes;
        if (first) startSpp = spp;
        lastSpp = spp;
        log(formatted("refresh: %.1f spp a pixel, estimated relMSE %.4g (auto %.2f s)", spp,
                      last->relMse, last->seconds));
        if (budget.timed()) {
            // The whole frame's time calibrates the model better than the probe did.
            cost.calibrate(refreshPlan, pixels, last->seconds);
            plan(now());
        }
        if (options.targetError > 0.0 && last->relMse <= options.targetError) stop = true;
        return true;
    };
    // The map for the current schedule: the refresh's relative error (denoiser) or uniform.
    auto makeMap = [&](const FrameBuffers& frame) -> std::shared_ptr<const Image> {
        if (options.steering == Steering::Denoiser && last)
            return std::make_shared<const Image>(importanceFromError(last->relative, scaleNow()));
        if (!steered && boost == 1.0) return nullptr;
        return std::make_shared<const Image>(frame.width(), frame.height(), 1,
                                             float(steered ? scaleNow() : boost));
    };

    render::Callbacks callbacks;
    callbacks.progress = [&](int p, double) { pass = p; };
    // Stop at the target, or when the time left is the final auto's reserve (never in the first
    // pass: its frame must be whole).
    callbacks.cancel = [&] { return stop || (pass >= 1 && !budget.renderMayContinue(now())); };
    // The schedule's latest map, and whether the one the renderer holds has pixels capped.
    std::shared_ptr<const Image> scheduled;
    bool cappedNow = false;
    // The map handed to the renderer: the schedule's with the samples cap (steered ways only),
    // or null when the renderer's map stands (nothing moved, no pixel capped before or now).
    auto steer = [&](const FrameBuffers& frame, bool moved) -> std::shared_ptr<const Image> {
        bool capped = false;
        auto map = capSamples(scheduled, frame, steered ? options.sppCapRatio : 0.0, &capped);
        if (!moved && !capped && !cappedNow) return nullptr;
        cappedNow = capped;
        return map;
    };
    if (settings.adaptive && (steered || options.targetError > 0.0)) {
        callbacks.importance = [&](int, const FrameBuffers& frame) -> std::shared_ptr<const Image> {
            const bool moved = refresh(frame);
            if (stop || !steered) return nullptr;
            // The threshold follows the renderer's error, which falls as 1/sqrt(spp): the
            // schedule's scale keeps about as many pixels open as at the start.
            if (moved) scheduled = makeMap(frame);
            return steer(frame, moved);
        };
    }
    if (!settings.adaptive && options.targetError > 0.0) {
        // Uniform passes: the target checked after each pass.
        callbacks.passDone = [&](int, const FrameBuffers& frame) { refresh(frame); };
    } else if (budget.timed()) {
        // The cost calibrated once the frame has a sample in each half (the second pass), so
        // that the reserve stops the uniform start too.
        callbacks.passDone = [&](int, const FrameBuffers& frame) {
            if (frame.metadata().spp >= 2) measure(frame);
        };
    }
    // Every pixel converged with time left: halve the threshold and go on (a threshold met
    // early would leave the budget unused).
    if (settings.adaptive && budget.timed())
        callbacks.converged = [&](int, const FrameBuffers& frame) -> std::shared_ptr<const Image> {
            measure(frame);
            if (stop || !budget.renderMayContinue(now()) || boost > kMaxBoost) return nullptr;
            boost *= 2.0;
            ++out.thresholdHalvings;
            scheduled = makeMap(frame);
            return steer(frame, true);
        };

    render::RenderResult rendered = renderer.render(settings, callbacks);
    out.render = rendered.stats;
    out.frame = std::move(rendered.frame);
    out.frame.metadata().extra.erase("cancelled");
    // At the target the frame is the refresh's (the render stopped before the next pass took a
    // sample); otherwise auto runs on the final frame.
    out.targetReached = stop;
    if (!stop) {
        if (budget.timed()) {
            // The final auto's plan for the time left, the render's time spent: the planned one
            // when it still fits, a cheaper one when the render (its first pass, say) took
            // longer, a better one when it ended early (at its spp) and that one fits.
            rendering = false;
            calibrate(out.frame);
            const double t = now();
            const bool fits = t + cost.seconds(finalPlan, pixels) <= options.timeLimit;
            const AutoPlan best = choosePlan(cost, pixels, finalSeconds(t), most);
            if (!fits || planGain(best) > planGain(finalPlan)) plan(t);
            out.overTime = rendered.stats.passes <= 1 &&
                           now() + cost.seconds(cheapestPlan(), pixels) > options.timeLimit;
        }
        const double predicted = cost.seconds(finalPlan, pixels);
        // Under a time limit the final auto stops where only the cheapest plan's reserve is left
        // (the machine slowed after the prediction), and the cheapest plan denoises the frame.
        const double deadline =
            budget.timed() && describe(finalPlan) != describe(cheapestPlan())
                ? options.timeLimit - kFinalAutoMargin * cost.seconds(cheapestPlan(), pixels)
                : 0.0;
        const double finalStart = now();
        bool late = false;
        try {
            last = denoised(out.frame, finalPlan, deadline, &late);
        } catch (const Error& e) {
            if (e.kind() != ErrorKind::Cancelled || !late) throw;
            const double stopped = now() - finalStart;
            out.autoSeconds += stopped;
            log(formatted("final auto stopped at its deadline, %.2f s (after %.2f s, predicted "
                          "%.2f s): ",
                          deadline, stopped, predicted) +
                describe(finalPlan) + "; the cheapest plan instead");
            out.finalStopped = describe(finalPlan);
            out.predictedFinalSeconds = predicted;
            finalPlan = cheapestPlan();
            last = denoised(out.frame, finalPlan);
        }
        out.autoSeconds += last->seconds;
        log(formatted("final: %.1f spp a pixel, estimated relMSE %.4g (auto %.2f s, ",
                      meanSpp(out.frame), last->relMse, last->seconds) +
            (budget.timed() ? formatted("predicted %.2f s, ", predicted, 0, 0) : "") +
            describe(finalPlan) + ")");
    }
    out.finalPlan = describe(finalPlan);
    if (out.finalStopped.empty()) out.predictedFinalSeconds = cost.seconds(finalPlan, pixels);
    out.estimatedRelMse = last->relMse;
    out.frame = denoise::denoisedFrame(out.frame, last->result.composite, 0, 0, "auto");
    out.seconds = now();
    return out;
}

}  // namespace glint::pipeline

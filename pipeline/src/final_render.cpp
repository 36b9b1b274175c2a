// The final render's loop (final_render.h; docs/final-render.md): adaptive passes, auto on the
// frame as it grows (a refresh), the importance map from auto's error, the targets.
#include "glint/pipeline/final_render.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>

#include "glint/image/composite.h"
#include "glint/image/error.h"
#include "glint/pipeline/refresh.h"

namespace glint::pipeline {

namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point t) {
    return std::chrono::duration<double>(Clock::now() - t).count();
}

std::string formatted(const char* format, double a, double b, double c) {
    char buf[200];
    std::snprintf(buf, sizeof buf, format, a, b, c);
    return buf;
}

}  // namespace

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
                             std::to_string(options.timeLimit));
    if (!(options.targetError >= 0.0 && options.targetError <= kMaxTargetError))
        bad("targetError", "the error target must be an estimated relMSE in (0, 1e6], got " +
                               std::to_string(options.targetError));
    if (!(options.refreshGrowth > 1.0 && options.refreshGrowth <= 1e6))
        bad("refreshGrowth", "the refresh growth must be a factor in (1, 1e6], got " +
                                 std::to_string(options.refreshGrowth));
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
    const Clock::time_point start = Clock::now();
    auto log = [&](const std::string& line) {
        if (options.log) options.log(line);
    };
    render::Settings settings = options.settings;
    settings.halfBuffers = true;
    settings.timeLimit = options.timeLimit;
    const bool timed = options.timeLimit > 0.0;

    RefreshOptions refreshOptions;
    refreshOptions.growth = options.refreshGrowth;
    refreshOptions.autoOptions = options.autoOptions;
    refreshOptions.quality = options.quality;
    refreshOptions.varianceOnly = options.steering == Steering::Variance;
    Refresher refresher(refreshOptions);

    FinalResult out;
    double autoSeconds = options.expectedAutoSeconds;  // what the final auto is expected to take
    bool stop = false;                                 // the error target is reached
    int pass = 0;                                      // the pass under way (progress)
    // A refresh: auto on the frame so far, when it has grown enough; true when it ran.
    auto refresh = [&](const FrameBuffers& frame) {
        if (!refresher.due(frame)) return false;
        // No time left to use what a refresh would say: keep the map.
        if (timed && refresher.last() &&
            secondsSince(start) + 2.0 * autoSeconds >= options.timeLimit)
            return false;
        refresher.adopt(refresher.denoise(frame));
        const Denoised& last = *refresher.last();
        autoSeconds = last.seconds;
        log(formatted("refresh: %.1f spp a pixel, estimated relMSE %.4g (auto %.2f s)",
                      last.meanSpp, last.relMse, last.seconds));
        if (options.targetError > 0.0 && last.relMse <= options.targetError) stop = true;
        return true;
    };

    render::Callbacks callbacks;
    callbacks.progress = [&](int p, double) { pass = p; };
    // Stop at the target, or when the time left is what the final auto takes (never in the first
    // pass: its frame must be whole).
    callbacks.cancel = [&] {
        return stop ||
               (timed && pass >= 1 && secondsSince(start) + autoSeconds >= options.timeLimit);
    };
    const bool steered = options.steering != Steering::Fixed;
    if (settings.adaptive && (steered || options.targetError > 0.0)) {
        callbacks.importance = [&](int, const FrameBuffers& frame) -> std::shared_ptr<const Image> {
            if (!refresh(frame) || stop || !steered) return nullptr;
            return refresher.map();
        };
    } else if (!settings.adaptive && options.targetError > 0.0) {
        // Uniform passes: the target checked after each pass.
        callbacks.passDone = [&](int, const FrameBuffers& frame) { refresh(frame); };
    }

    render::RenderResult rendered = renderer.render(settings, callbacks);
    out.render = rendered.stats;
    out.frame = std::move(rendered.frame);
    out.frame.metadata().extra.erase("cancelled");
    out.overTime = timed && rendered.stats.passes <= 1 && secondsSince(start) > options.timeLimit;
    // At the target the frame is the refresh's (the render stopped before the next pass took a
    // sample); otherwise auto runs on the final frame.
    out.targetReached = stop;
    out.refreshes = refresher.refreshes();
    out.autoSeconds = refresher.autoSeconds();
    Denoised last;
    if (stop) {
        last = *refresher.last();
    } else {
        last = refresher.denoise(out.frame);
        out.autoSeconds += last.seconds;
        log(formatted("final: %.1f spp a pixel, estimated relMSE %.4g (auto %.2f s)", last.meanSpp,
                      last.relMse, last.seconds));
    }
    out.estimatedRelMse = last.relMse;
    paste(out.frame.color(), last.result.composite, 0, 0);
    out.frame.metadata().extra["denoiseFilter"] = "auto";
    out.seconds = secondsSince(start);
    return out;
}

}  // namespace glint::pipeline

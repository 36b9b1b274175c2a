// The final render's loop (final_render.h; docs/final-render.md): adaptive passes, auto on the
// frame as it grows (a refresh), the importance map from auto's error, the targets.
#include "glint/pipeline/final_render.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>

#include "glint/denoise/auto_stream.h"
#include "glint/denoise/bank.h"
#include "glint/image/composite.h"
#include "glint/image/error.h"
#include "glint/pipeline/steering.h"

namespace glint::pipeline {

namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point t) {
    return std::chrono::duration<double>(Clock::now() - t).count();
}

/// The mean of a frame's sampleCount layer.
double meanSpp(const FrameBuffers& frame) {
    double sum = 0.0;
    for (float n : frame.layer(Layer::SampleCount).data()) sum += double(n);
    return sum / double(std::size_t(frame.width()) * std::size_t(frame.height()));
}

/// Auto's result on one frame and what it says of the denoised image.
struct Denoised {
    denoise::AutoResult result;
    Image relative;  ///< relativeError of the result
    double relMse = 0.0;
    double seconds = 0.0;
};

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

    // Auto as glint-denoise auto runs it at the quality, estimating the result's error too.
    denoise::AutoOptions autoOptions = options.autoOptions;
    autoOptions.estimateError = true;
    if (autoOptions.tuning.empty())
        autoOptions.tuning = denoise::autoQualityTuning(options.quality);
    denoise::BankOptions bank;
    bank.size = denoise::autoQualityBankSize(options.quality);
    bank.prefilter = autoOptions.prefilter;
    bank.prefilterParams = autoOptions.prefilterParams;
    auto denoised = [&](const FrameBuffers& frame) {
        const Clock::time_point t = Clock::now();
        Denoised d;
        d.result = denoise::autoCompositeStreamed(frame, bank, autoOptions).result;
        d.relative = relativeError(d.result.error, d.result.composite, autoOptions.exposure);
        d.relMse = estimatedRelMse(d.relative);
        d.seconds = secondsSince(t);
        return d;
    };

    FinalResult out;
    std::optional<Denoised> last;  // the latest refresh's result
    double lastSpp = 0.0, startSpp = 0.0;
    double autoSeconds = options.expectedAutoSeconds;  // what the final auto is expected to take
    bool stop = false;                                 // the error target is reached
    int pass = 0;                                      // the pass under way (progress)
    // A refresh: auto on the frame so far, when it has grown enough; true when it ran.
    auto refresh = [&](const FrameBuffers& frame) {
        const double spp = meanSpp(frame);
        if (last && spp < options.refreshGrowth * lastSpp) return false;
        // No time left to use what a refresh would say: keep the map.
        if (timed && last && secondsSince(start) + 2.0 * autoSeconds >= options.timeLimit)
            return false;
        last = denoised(frame);
        autoSeconds = last->seconds;
        out.autoSeconds += last->seconds;
        ++out.refreshes;
        if (out.refreshes == 1) startSpp = spp;
        lastSpp = spp;
        log(formatted("refresh: %.1f spp a pixel, estimated relMSE %.4g (auto %.2f s)", spp,
                      last->relMse, last->seconds));
        if (options.targetError > 0.0 && last->relMse <= options.targetError) stop = true;
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
            // The threshold follows the renderer's error, which falls as 1/sqrt(spp): the
            // schedule's scale keeps about as many pixels open as at the start.
            const double scale = std::sqrt(lastSpp / startSpp);
            if (options.steering == Steering::Variance)
                return std::make_shared<const Image>(frame.width(), frame.height(), 1,
                                                     float(scale));
            return std::make_shared<const Image>(importanceFromError(last->relative, scale));
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
    if (!stop) {
        last = denoised(out.frame);
        out.autoSeconds += last->seconds;
        log(formatted("final: %.1f spp a pixel, estimated relMSE %.4g (auto %.2f s)",
                      meanSpp(out.frame), last->relMse, last->seconds));
    }
    out.estimatedRelMse = last->relMse;
    paste(out.frame.color(), last->result.composite, 0, 0);
    out.frame.metadata().extra["denoiseFilter"] = "auto";
    out.seconds = secondsSince(start);
    return out;
}

}  // namespace glint::pipeline

// The automatic selection's options: their validation, names and defaults, and their
// resolution for one input (sure.h, options.h).
#include "options.h"

#include <cmath>
#include <cstdio>
#include <utility>

#include "glint/denoise/bank.h"
#include "glint/image/error.h"
#include "glint/image/io.h"
#include "halves_estimator.h"
#include "stacking.h"
#include "sure_estimator.h"

namespace glint::denoise {

void validate(const AutoOptions& options) {
    if (!(options.sure.epsilon > 0.0) || !std::isfinite(options.sure.epsilon) ||
        options.sure.epsilon > 1.0)
        throw Error(ErrorKind::InvalidArgument,
                    "epsilon " + std::to_string(options.sure.epsilon) +
                        " is not a number in (0, 1] (the perturbation relative to the pixel's "
                        "sigma)",
                    {}, "--epsilon");
    if (options.window && (*options.window < 0 || *options.window > 64))
        throw Error(ErrorKind::InvalidArgument,
                    "window " + std::to_string(*options.window) +
                        " is outside 0 … 64 (the SURE maps' smoothing radius in pixels)",
                    {}, "--window");
    if (options.temperature &&
        (!(*options.temperature >= 0.0) || !std::isfinite(*options.temperature)))
        throw Error(ErrorKind::InvalidArgument,
                    "temperature " + std::to_string(*options.temperature) +
                        " is not a finite number >= 0 (0: hard per-pixel choice)",
                    {}, "--temperature");
    if (options.confidence &&
        (!(*options.confidence >= 0.0) || !std::isfinite(*options.confidence)))
        throw Error(ErrorKind::InvalidArgument,
                    "confidence " + std::to_string(*options.confidence) +
                        " is not a finite number >= 0 (standard errors a local choice must win by)",
                    {}, "--confidence");
    if (options.finer && (*options.finer < 0 || *options.finer > 6))
        throw Error(ErrorKind::InvalidArgument,
                    "finer " + std::to_string(*options.finer) +
                        " is outside 0 … 6 (how many times the window is halved for the final "
                        "choice)",
                    {}, "--finer");
    if (options.feather && (*options.feather < 0 || *options.feather > 32))
        throw Error(ErrorKind::InvalidArgument,
                    "feather " + std::to_string(*options.feather) +
                        " is outside 0 … 32 (the weight planes' smoothing radius in pixels)",
                    {}, "--feather");
    if (!(options.featherGate > 0.0) || !std::isfinite(options.featherGate))
        throw Error(ErrorKind::InvalidArgument,
                    "feather gate " + std::to_string(options.featherGate) +
                        " is not a finite number > 0 (a display-value difference; 1 is the whole "
                        "range)",
                    {}, "--feather-gate");
    if (options.shortlist < 0 || options.shortlist > 4096)
        throw Error(ErrorKind::InvalidArgument,
                    "shortlist " + std::to_string(options.shortlist) +
                        " is outside 0 … 4096 (members filtered on both halves; 0: all)",
                    {}, "--shortlist");
    if (options.stack && (*options.stack < 0 || *options.stack > int(detail::kMaxStack)))
        throw Error(ErrorKind::InvalidArgument,
                    "stack " + std::to_string(*options.stack) + " is outside 0 … " +
                        std::to_string(detail::kMaxStack) + " (members in the stacking; 0: off)",
                    {}, "--stack");
    if (options.stackWindow < 1 || options.stackWindow > 64)
        throw Error(ErrorKind::InvalidArgument,
                    "stack window " + std::to_string(options.stackWindow) +
                        " is outside 1 … 64 (the stacking's window radius in pixels)",
                    {}, "--stack-window");
    if (!(options.stackFloor >= 0.0) || !(options.stackFloor <= 100.0))
        throw Error(ErrorKind::InvalidArgument,
                    "stack floor " + std::to_string(options.stackFloor) +
                        " is not a number in 0 … 100 (the stacking's ridge floor, in units of the "
                        "members' mean squared difference from the composite)",
                    {}, "--stack-floor");
    if (options.stackSmooth < 0 || options.stackSmooth > 64)
        throw Error(ErrorKind::InvalidArgument,
                    "stack smooth " + std::to_string(options.stackSmooth) +
                        " is outside 0 … 64 (the radius over which the stacking's coefficients "
                        "are averaged; 0: off)",
                    {}, "--stack-smooth");
    if (!(options.stackRidge >= 0.0) || !std::isfinite(options.stackRidge))
        throw Error(ErrorKind::InvalidArgument,
                    "stack ridge " + std::to_string(options.stackRidge) +
                        " is not a finite number >= 0 (in units of the halves' noise)",
                    {}, "--stack-ridge");
    if (options.stackFeatureWindow < 1 || options.stackFeatureWindow > 64)
        throw Error(ErrorKind::InvalidArgument,
                    "stack feature window " + std::to_string(options.stackFeatureWindow) +
                        " is outside 1 … 64 (the radius of the features' local average)",
                    {}, "--stack-feature-window");
    // 2^64 keeps every finite radiance finite on the display (as glint-image's --exposure).
    if (!(std::fabs(options.exposure) <= kMaxExposure)) {
        char got[32];
        std::snprintf(got, sizeof got, "%g", double(options.exposure));
        throw Error(ErrorKind::InvalidArgument,
                    std::string("exposure must be a number of stops in [-64, 64], got ") + got, {},
                    "--exposure");
    }
}

SureSpace parseSureSpace(const std::string& name) {
    if (name == "display") return SureSpace::Display;
    if (name == "display-tangent") return SureSpace::DisplayTangent;
    if (name == "display-exact") return SureSpace::DisplayExact;
    if (name == "linear") return SureSpace::Linear;
    throw Error(ErrorKind::InvalidArgument,
                "unknown error space '" + name +
                    "' (expected display, display-tangent, display-exact or linear)");
}

const char* sureSpaceName(SureSpace space) {
    switch (space) {
        case SureSpace::Display:
            return "display";
        case SureSpace::DisplayTangent:
            return "display-tangent";
        case SureSpace::DisplayExact:
            return "display-exact";
        case SureSpace::Linear:
            return "linear";
    }
    return "display";
}

AutoEstimator parseAutoEstimator(const std::string& name) {
    if (name == "auto") return AutoEstimator::Auto;
    if (name == "sure") return AutoEstimator::Sure;
    if (name == "halves") return AutoEstimator::Halves;
    throw Error(ErrorKind::InvalidArgument,
                "unknown error estimator '" + name + "' (expected auto, sure or halves)");
}

const char* autoEstimatorName(AutoEstimator estimator) {
    switch (estimator) {
        case AutoEstimator::Auto:
            return "auto";
        case AutoEstimator::Sure:
            return "sure";
        case AutoEstimator::Halves:
            return "halves";
    }
    return "?";
}

AutoDefaults autoDefaults(AutoEstimator estimator) {
    if (estimator == AutoEstimator::Halves) return {8, 1.0, 0.06, 1, 5, 6};
    return {4, 3.0, 0.0, 0, 4, 0};
}

AutoEstimator resolveEstimator(AutoEstimator estimator, const FrameBuffers& frame) {
    if (estimator != AutoEstimator::Auto) return estimator;
    return frame.has(Layer::HalfColor) ? AutoEstimator::Halves : AutoEstimator::Sure;
}

void checkAutoInput(const FrameBuffers& frame, AutoEstimator estimator, const std::string& file) {
    if (resolveEstimator(estimator, frame) == AutoEstimator::Sure) {
        detail::checkSureInput(frame, file);
        return;
    }
    if (!frame.has(Layer::HalfColor))
        throw Error(ErrorKind::Format,
                    "has no halfColor layer: the halves estimator needs a render with half "
                    "buffers (glint-render --half-buffers)",
                    file, "layer 'halfColor'");
    splitHalves(frame, file);  // every half layer present, counts consistent
    detail::checkHalvesFinite(frame, file);
}

namespace detail {

AutoSettings resolveSettings(const FilterBank& bank, const FrameBuffers& frame,
                             const AutoOptions& options) {
    validate(options);
    if (bank.size() == 0) throw Error(ErrorKind::InvalidArgument, "the bank has no members");
    if (frame.width() != bank.frameWidth() || frame.height() != bank.frameHeight() ||
        hashFrame(frame) != bank.inputHash())
        throw Error(ErrorKind::InvalidArgument,
                    "the bank was computed from another image than the one given");
    AutoSettings s;
    s.estimator = resolveEstimator(options.estimator, frame);
    s.halves = s.estimator == AutoEstimator::Halves;
    const AutoDefaults defaults = autoDefaults(s.estimator);
    const bool halves = s.halves;
    if (options.space == SureSpace::DisplayExact && !halves)
        throw Error(ErrorKind::InvalidArgument,
                    "the exact display space needs the halves estimator (SURE needs a "
                    "differentiable error: use display or linear)",
                    {}, "--space");
    if (options.stack.value_or(0) > 0 && !halves)
        throw Error(ErrorKind::InvalidArgument,
                    "stacking fits each half on the other: it needs the halves estimator (an "
                    "input rendered with --half-buffers)",
                    {}, "--stack");
    if (options.stack.value_or(0) > 0 && !options.symmetric)
        throw Error(ErrorKind::InvalidArgument, "stacking fits both halves: it cannot be one-sided",
                    {}, "--stack");
    // The stacking's features (docs/auto.md, "Stacking"): those asked for must be in the input,
    // with their halves; unset, those it has.
    const auto hasFeature = [&](Layer layer) {
        return frame.has(layer) && frame.has(*halfLayer(layer));
    };
    s.stackAlbedo = options.stackAlbedo.value_or(hasFeature(Layer::Albedo));
    s.stackNormal = options.stackNormal.value_or(hasFeature(Layer::Normal));
    if (halves && options.symmetric && options.stack.value_or(defaults.stack) > 0) {
        const std::pair<bool, Layer> features[] = {{s.stackAlbedo, Layer::Albedo},
                                                   {s.stackNormal, Layer::Normal}};
        for (const auto& [wanted, layer] : features) {
            if (!wanted) continue;
            for (Layer l : {layer, *halfLayer(layer)})
                if (!frame.has(l))
                    throw Error(ErrorKind::Format,
                                "has no " + std::string(layerDisplayName(l)) +
                                    " layer: the stacking's feature regressors need it "
                                    "(--stack-features names the ones to use; none: off)",
                                {}, "layer '" + std::string(layerDisplayName(l)) + "'");
        }
    }
    s.window = options.window.value_or(defaults.window);
    s.confidence = options.confidence.value_or(defaults.confidence);
    s.temperature = options.temperature.value_or(defaults.temperature);
    s.finer = options.finer.value_or(defaults.finer);
    s.feather = options.feather.value_or(defaults.feather);
    // Validation as checkAutoInput's, without a second split (the halves' estimator checks them).
    if (!halves || !frame.has(Layer::HalfColor))
        checkAutoInput(frame, s.estimator);
    else
        checkHalvesFinite(frame, {});
    s.secant = halves && options.space == SureSpace::Display;
    s.tangent = options.space == SureSpace::DisplayTangent ||
                (!halves && options.space == SureSpace::Display);
    const std::size_t n = bank.size();
    s.shortlisted =
        halves && options.symmetric && options.shortlist > 0 && std::size_t(options.shortlist) < n;
    s.bothHalves = options.symmetric && !s.shortlisted;
    s.stack = options.stack.value_or(options.symmetric ? defaults.stack : 0);
    s.space = options.space;
    s.exposure = options.exposure;
    s.shortlist = options.shortlist;
    s.featherGate = options.featherGate;
    s.sure = options.sure;
    s.stackWindow = options.stackWindow;
    s.stackRidge = options.stackRidge;
    s.stackFloor = options.stackFloor;
    s.stackSmooth = options.stackSmooth;
    s.stackFeatureWindow = options.stackFeatureWindow;
    s.prefilter = options.prefilter;
    s.prefilterParams = options.prefilterParams;
    return s;
}

}  // namespace detail

}  // namespace glint::denoise

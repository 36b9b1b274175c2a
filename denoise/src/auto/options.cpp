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
    (void)resolveAutoTuning(options, AutoEstimator::Halves);
    // 2^64 keeps every finite radiance finite on the display (as glint-image's --exposure).
    if (!(std::fabs(options.exposure) <= kMaxExposure)) {
        char got[32];
        std::snprintf(got, sizeof got, "%g", double(options.exposure));
        throw Error(ErrorKind::InvalidArgument,
                    std::string("exposure must be a number of stops in [-64, 64], got ") + got, {},
                    "--exposure");
    }
}

AutoEstimator parseAutoEstimator(const std::string& name) {
    if (name == "auto") return AutoEstimator::Auto;
    if (name == "sure") return AutoEstimator::Sure;
    if (name == "halves") return AutoEstimator::Halves;
    if (name == "image") return AutoEstimator::Image;
    throw Error(ErrorKind::InvalidArgument,
                "unknown error estimator '" + name + "' (expected auto, sure, halves or image)");
}

const char* autoEstimatorName(AutoEstimator estimator) {
    switch (estimator) {
        case AutoEstimator::Auto:
            return "auto";
        case AutoEstimator::Sure:
            return "sure";
        case AutoEstimator::Halves:
            return "halves";
        case AutoEstimator::Image:
            return "image";
    }
    return "?";
}

AutoEstimator resolveEstimator(AutoEstimator estimator, const FrameBuffers& frame) {
    if (estimator != AutoEstimator::Auto) return estimator;
    // Halves > SURE with the render's variance > the image-only estimate.
    if (frame.has(Layer::HalfColor)) return AutoEstimator::Halves;
    return frame.has(Layer::Variance) ? AutoEstimator::Sure : AutoEstimator::Image;
}

namespace {

// The render's statistics describe the render's colour, not one a filter or auto has replaced
// (colourIsDenoised).
void checkColourIsTheRenders(const FrameBuffers& frame, AutoEstimator resolved,
                             const std::string& file) {
    if (!colourIsDenoised(frame)) return;
    const std::string mark = denoisedMark(frame);
    throw Error(
        ErrorKind::InvalidArgument,
        "its colour is already denoised (" + mark + ") while its " +
            (resolved == AutoEstimator::Halves ? "half buffers are" : "variance is") +
            " the render's, which no longer describe it: " +
            (keepsRender(frame)
                 ? std::string("denoise the render it keeps (its noisy layer: renderOf, "
                               "glint.render_of)")
                 : std::string("denoise the render itself (glint-render's output), or "
                               "estimate from the image alone (--estimator image)")),
        file,
        mark.rfind("layer", 0) == 0 ? mark : "metadata '" + mark.substr(0, mark.find(':')) + "'");
}

}  // namespace

void checkAutoInput(const FrameBuffers& frame, AutoEstimator estimator, const std::string& file) {
    const AutoEstimator resolved = resolveEstimator(estimator, frame);
    if (resolved == AutoEstimator::Image) {
        detail::checkImageNoiseInput(frame, file);
        return;
    }
    checkColourIsTheRenders(frame, resolved, file);
    if (resolved == AutoEstimator::Sure) {
        detail::checkSureInput(frame, file);
        return;
    }
    if (!frame.has(Layer::HalfColor))
        throw Error(ErrorKind::Format,
                    "has no halfColor layer: the halves estimator needs a render with half "
                    "buffers (glint-render --set halfBuffers=true)",
                    file, "layer 'halfColor'");
    checkHalves(frame, file);  // every half layer present, counts consistent
    detail::checkHalvesFinite(frame, file);
}

namespace detail {

ImageNoiseOptions imageNoiseOptions(const ParamValues& tuning) {
    ImageNoiseOptions o;
    o.window = int(tuning.at("noiseWindow"));
    o.alpha = tuning.at("noiseAlpha");
    o.tail = tuning.at("noiseTail") != 0.0;
    return o;
}

}  // namespace detail

FrameBuffers withImageNoiseVariance(const FrameBuffers& frame, const AutoOptions& options) {
    validate(options);
    checkAutoInput(frame, AutoEstimator::Image);
    FrameBuffers out = frame.sharedCopy();  // only the variance is new
    WorkContext work;
    out.set(Layer::Variance,
            detail::estimateImageNoise(
                frame, detail::imageNoiseOptions(resolveAutoTuning(options, AutoEstimator::Image)),
                work));
    return out;
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
    const bool halves = s.halves;
    ParamValues t = resolveAutoTuning(options, s.estimator);
    const auto given = [&](const char* name) { return options.tuning.count(name) != 0; };
    const bool symmetric = t["oneSided"] == 0.0;
    s.space = SureSpace(int(t["space"]));
    if (s.space == SureSpace::DisplayExact && !halves)
        throw Error(ErrorKind::InvalidArgument,
                    "the exact display space needs the halves estimator (SURE needs a "
                    "differentiable error: use display or linear)",
                    {}, "--space");
    if (given("stack") && t["stack"] > 0.0 && !halves)
        throw Error(ErrorKind::InvalidArgument,
                    "stacking fits each half on the other: it needs the halves estimator (an "
                    "input rendered with --set halfBuffers=true)",
                    {}, "--stack");
    if (given("stack") && t["stack"] > 0.0 && !symmetric)
        throw Error(ErrorKind::InvalidArgument, "stacking fits both halves: it cannot be one-sided",
                    {}, "--stack");
    // The stacking's features (docs/auto.md, "Stacking"): those asked for (on) must be in the
    // input, with their halves; auto, those it has.
    const auto hasFeature = [&](Layer layer) {
        return frame.has(layer) && frame.has(*halfLayer(layer));
    };
    const auto feature = [&](const char* name, Layer layer) {
        const int choice = int(t[name]);  // auto, on, off
        return choice == 0 ? hasFeature(layer) : choice == 1;
    };
    s.stackAlbedo = feature("stackAlbedo", Layer::Albedo);
    s.stackNormal = feature("stackNormal", Layer::Normal);
    s.stack = halves && symmetric ? int(t["stack"]) : 0;
    if (s.stack > 0) {
        const std::pair<bool, Layer> features[] = {{s.stackAlbedo, Layer::Albedo},
                                                   {s.stackNormal, Layer::Normal}};
        for (const auto& [wanted, layer] : features) {
            if (!wanted) continue;
            for (Layer l : {layer, *halfLayer(layer)})
                if (!frame.has(l))
                    throw Error(ErrorKind::Format,
                                "has no " + std::string(layerDisplayName(l)) +
                                    " layer: the stacking's feature regressors need it "
                                    "(--stack-albedo and --stack-normal: auto or off)",
                                {}, "layer '" + std::string(layerDisplayName(l)) + "'");
        }
    }
    s.window = int(t["window"]);
    s.confidence = t["confidence"];
    s.familywise = t["margin"] == 1.0;  // family
    s.temperature = t["temperature"];
    s.finer = int(t["finer"]);
    s.feather = int(t["feather"]);
    // Validation as checkAutoInput's, without a second split (the halves' estimator checks them).
    if (!halves || !frame.has(Layer::HalfColor)) {
        checkAutoInput(frame, s.estimator);
    } else {
        checkColourIsTheRenders(frame, s.estimator, {});
        checkHalvesFinite(frame, {});
    }
    s.secant = halves && s.space == SureSpace::Display;
    s.tangent = s.space == SureSpace::DisplayTangent || (!halves && s.space == SureSpace::Display);
    const std::size_t n = bank.size();
    s.shortlist = int(t["shortlist"]);
    s.shortlisted = halves && symmetric && s.shortlist > 0 && std::size_t(s.shortlist) < n;
    s.rechosen = halves && !symmetric && s.shortlist > 0 && std::size_t(s.shortlist) < n;
    s.bothHalves = symmetric && !s.shortlisted;
    s.exposure = options.exposure;
    s.featherGate = t["featherGate"];
    s.sure.epsilon = t["epsilon"];
    s.sure.seed = options.seed;
    s.sure.analyticDivergence = t["numericDivergence"] == 0.0;
    s.imageNoise = imageNoiseOptions(t);
    s.stackWindow = int(t["stackWindow"]);
    s.stackRidge = t["stackRidge"];
    s.stackFloor = t["stackFloor"];
    s.stackSmooth = int(t["stackSmooth"]);
    s.stackFeatureWindow = int(t["stackFeatureWindow"]);
    s.stackNoiseGate = t["stackNoiseGate"];
    s.prefilter = options.prefilter;
    s.prefilterParams = options.prefilterParams;
    s.estimateError = options.estimateError;
    if (s.estimateError && !halves)
        throw Error(ErrorKind::InvalidArgument,
                    "the result's error is estimated on the halves: it needs the halves estimator "
                    "(an input rendered with half buffers)",
                    {}, "estimateError");
    return s;
}

}  // namespace detail

}  // namespace glint::denoise

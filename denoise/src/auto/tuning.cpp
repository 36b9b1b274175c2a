// The automatic selection's tuning map (auto.h): its parameters, their defaults with each
// estimator, and their validation. glint-lab auto's flags and the tuning table of
// docs/lab/auto-tuning.md are generated from these specs (lab/cli/auto_command.cpp).
#include <cmath>
#include <string>

#include "glint/denoise/auto.h"
#include "glint/image/error.h"
#include "stacking.h"

namespace glint::denoise {

namespace {

ParamSpec integer(const char* name, const char* label, int min, int max, int value,
                  const char* help) {
    return ParamSpec(name, label, min, max, value, ParamScale::Linear, true, help);
}

ParamSpec real(const char* name, const char* label, double min, double max, double value,
               const char* help) {
    return ParamSpec(name, label, min, max, value, ParamScale::Linear, false, help);
}

std::vector<ParamSpec> makeSpecs() {
    const char* features[] = {"auto", "on", "off"};
    return {
        ParamSpec::choice("space", "error space",
                          {"display", "display-tangent", "display-exact", "linear"}, 0,
                          "the error estimated: of display values (exposure, clamp, sRGB) by the "
                          "secant (halves) or the tangent (SURE) at the bank's median, by the "
                          "tangent for both, of display values exactly (halves only), or linear"),
        integer("oneSided", "one-sided", 0, 1, 0,
                "halves: filter half A only (half the time, noisier estimates; no stacking)"),
        integer("shortlist", "shortlist", 0, 4096, 16,
                "halves: the members that win the most pixels in a first choice, the final "
                "choice among them (both sides: filtered on B too; one side: on the same "
                "maps) (0: all)"),
        integer("window", "window radius (px)", 0, 64, 8,
                "radius of the box over which the error maps are averaged before the choice"),
        real("confidence", "confidence (standard errors)", 0.0, 1000.0, 1.0,
             "standard errors of the local mean by which a member must beat the baseline"),
        ParamSpec::choice("margin", "confidence of", {"each", "family"}, 0,
                          "each: the confidence bounds the chance that each candidate beats the "
                          "baseline by noise alone; family: that any does (the margin grows "
                          "with the candidates)"),
        integer("finer", "finer windows", 0, 6, 1,
                "times the window is halved for the final choice, which keeps the lowest score"),
        real("temperature", "temperature (noise units)", 0.0, 1000.0, 0.06,
             "0: a hard per-pixel choice; > 0: soft weights, in units of the smoothed noise"),
        integer("feather", "feather radius (px)", 0, 32, 5,
                "radius over which each member's weights are smoothed before the composite "
                "(0: off)"),
        real("featherGate", "feather gate", 1e-6, 1e6, 0.2,
             "display difference past which a member gets no feathered weight"),
        integer("stack", "stacked members", 0, int(detail::kMaxStack), 6,
                "halves, both sides: members of largest weight whose local ridge regression "
                "corrects the composite (0: off)"),
        integer("stackWindow", "stacking window (px)", 1, 64, 6,
                "radius of the stacking's regression window"),
        real("stackRidge", "stacking ridge", 0.0, 1e6, 0.5,
             "the stacking's ridge, in units of the halves' noise"),
        real("stackFloor", "stacking ridge floor", 0.0, 100.0, 0.1,
             "the ridge's floor, in units of the regressors' mean squared deviation from the "
             "composite"),
        integer("stackSmooth", "coefficient smoothing (px)", 0, 64, 8,
                "radius over which each pixel averages the coefficients fitted around it (0: its "
                "own)"),
        ParamSpec::choice("stackAlbedo", "albedo regressor", {features, features + 3}, 0,
                          "the stacking also fits the albedo's local deviation (auto: when the "
                          "input has it)"),
        ParamSpec::choice("stackNormal", "normal regressors", {features, features + 3}, 0,
                          "the stacking also fits the normal's local deviations (auto: when the "
                          "input has it)"),
        integer("stackFeatureWindow", "feature window (px)", 1, 64, 3,
                "radius of the features' local average in the stacking"),
        real("stackNoiseGate", "stacking noise gate (standard errors)", 0.0, 1000.0, 3.0,
             "the stacking moves no pixel by more than this many standard errors of the "
             "render's mean there, or by more than the composite's distance from that mean "
             "where it is larger (0: off)"),
        ParamSpec("epsilon", "SURE perturbation", 1e-9, 1.0, 0.01, ParamScale::Log, false,
                  "SURE: the perturbation, relative to the pixel's sigma"),
        integer("numericDivergence", "numeric divergence", 0, 1, 0,
                "SURE: estimate every filter's divergence by Monte Carlo, even where the filter "
                "gives it"),
        integer("noiseWindow", "noise window (px)", 1, 16, 3,
                "image-only estimator: radius of the window whose residuals give a pixel's noise "
                "level"),
        real("noiseAlpha", "noise brightness exponent", 0.0, 2.0, 1.0,
             "image-only estimator: the noise variance scales as the smooth value to this power "
             "within the window (0: uniform there)"),
        integer("noiseTail", "noise tail factor", 0, 1, 1,
                "image-only estimator: raise the level by the frame's tail factor for "
                "heavy-tailed (firefly) noise (0: the window's median alone)"),
    };
}

}  // namespace

std::string autoTuningFlag(const std::string& name) {
    std::string flag = "--";
    for (char c : name) {
        if (c >= 'A' && c <= 'Z') {
            flag += '-';
            flag += char(c - 'A' + 'a');
        } else {
            flag += c;
        }
    }
    return flag;
}

const std::vector<ParamSpec>& autoTuningSpecs() {
    static const std::vector<ParamSpec> specs = makeSpecs();
    return specs;
}

ParamValues autoTuningDefaults(AutoEstimator estimator) {
    ParamValues values;
    for (const ParamSpec& spec : autoTuningSpecs()) values[spec.name] = spec.defaultValue;
    if (estimator == AutoEstimator::Sure || estimator == AutoEstimator::Image) {
        // SURE's maps are less noisy per pixel: a narrower window, a higher bar, a hard choice
        // (docs/auto.md, "Choice"); it cannot stack.
        values["window"] = 4;
        values["confidence"] = 3;
        values["finer"] = 0;
        values["temperature"] = 0;
        values["feather"] = 4;
        values["stack"] = 0;
    }
    return values;
}

ParamValues resolveAutoTuning(const AutoOptions& options, AutoEstimator estimator) {
    const std::vector<ParamSpec>& specs = autoTuningSpecs();
    ParamValues values = autoTuningDefaults(estimator);
    // One-sided halves and a result that may not be stacked: no stacking unless asked for.
    if (options.tuning.count("oneSided") && options.tuning.at("oneSided") != 0.0)
        values["stack"] = 0;
    if (!options.allowStacking) values["stack"] = 0;
    for (const auto& [name, value] : options.tuning) {
        const ParamSpec* spec = findParam(specs, name);
        if (!spec) {
            std::string names;
            for (const ParamSpec& s : specs) names += (names.empty() ? "" : ", ") + s.name;
            throw Error(ErrorKind::InvalidArgument,
                        "unknown tuning parameter '" + name + "' (expected one of " + names + ")");
        }
        const std::string range = spec->isChoice() ? "one of the options"
                                                   : formatParamValue(*spec, spec->min) + " … " +
                                                         formatParamValue(*spec, spec->max);
        if (!(value >= spec->min && value <= spec->max) ||
            ((spec->integer || spec->isChoice()) && value != std::floor(value)))
            throw Error(ErrorKind::InvalidArgument,
                        spec->name + " " + formatParamValue(*spec, value) + " is outside " + range +
                            (spec->integer ? ", an integer" : "") + " (" + spec->help + ")",
                        {}, autoTuningFlag(spec->name));
        values[name] = value;
    }
    if (!options.allowStacking && values["stack"] > 0.0)
        throw Error(ErrorKind::InvalidArgument,
                    "stacking is not allowed here (the result must be a blend of the members)", {},
                    "--stack");
    return values;
}

}  // namespace glint::denoise

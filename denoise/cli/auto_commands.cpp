// glint-denoise auto: the automatic local baseline — every bank member's per-pixel error
// estimated by SURE from the render's variance or by cross-validation on its halves (no
// reference), a per-pixel choice among them, written as a layered EXR (docs/auto.md). Also the
// oracle's "auto" column (autoOracleColumn).
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <sstream>

#include "cli_boundary.h"
#include "commands.h"
#include "glint/denoise/auto_stream.h"
#include "glint/denoise/bank.h"
#include "glint/denoise/prefilter.h"
#include "glint/denoise/registry.h"
#include "glint/denoise/sure.h"
#include "glint/image/composite.h"
#include "glint/image/error.h"
#include "glint/image/io.h"
#include "glint/image/metrics.h"

namespace glint::denoise::cli {

namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using Clock = std::chrono::steady_clock;

// Errors about the input's content (a missing variance layer, NaN) name the input file.
[[noreturn]] void rethrowNaming(const Error& e, const std::string& file) {
    if (e.file().empty()) throw Error(e.kind(), e.message(), file, e.where());
    throw e;
}

struct AutoArgs {
    std::string input, bank, out, reference, choiceMap, filters, space = "display",
                                                                 estimator = "auto";
    std::string stackFeatures;  ///< empty: the features the input has
    // Integers are parsed strictly from their text (parseInteger, parseUnsigned); "": not given.
    std::string size = "64", shortlist = "16",
                stackWindow = std::to_string(AutoOptions{}.stackWindow),
                stackSmooth = std::to_string(AutoOptions{}.stackSmooth),
                stackFeatureWindow = std::to_string(AutoOptions{}.stackFeatureWindow);
    double stackRidge = AutoOptions{}.stackRidge, stackFloor = AutoOptions{}.stackFloor;
    std::string window, finer, feather, stack;
    double featherGate = 0.2;
    std::string bankSeed = "1", seed = "1";
    std::optional<double> temperature;
    double epsilon = 0.01;
    std::optional<double> confidence;
    float exposure = 0.0f;
    bool prefilter = false, json = false, oneSided = false;
};

// Refuses before any work outputs that would replace one of the command's inputs.
void checkOutputsAreNoInputs(const AutoArgs& a) {
    for (const auto& [output, flag] :
         {std::pair{a.out, "--out"}, std::pair{a.choiceMap, "--choice-map"}})
        glint::cli::checkOutputIsNoInput(output, flag,
                                         {{a.input, "IN"}, {a.reference, "--reference"}});
    checkOutputIsNoBankFile(a.out, "--out", a.bank);
    checkOutputIsNoBankFile(a.choiceMap, "--choice-map", a.bank);
}

// The best member's result over the bank's region: the bank's own, or (a bank streamed
// without results) the member applied once more to the input the bank saw.
Image bestMemberResult(const FilterBank& bank, const FrameBuffers& frame, int best,
                       const BankOptions& bankOptions) {
    const auto m = std::size_t(best);
    if (!bank.results().empty()) return bank.result(m);
    const BankMember& member = bank.members()[m];
    FilterOptions fo;
    fo.region = bank.region();
    const FrameBuffers input = bankOptions.prefilter
                                   ? prefilterFeatures(frame, bankOptions.prefilterParams)
                                   : FrameBuffers{};
    return applyFilter(findFilter(member.filter), bankOptions.prefilter ? input : frame,
                       member.params, fo);
}

void runAuto(const AutoArgs& a) {
    // Everything that needs no image is checked first; nothing is written before the end.
    glint::cli::checkOutputPath(a.out, {".exr"}, "--out");
    if (!a.choiceMap.empty()) glint::cli::checkOutputPath(a.choiceMap, {".png"}, "--choice-map");
    checkOutputsAreNoInputs(a);
    glint::cli::removeTemporariesOnSignal({a.out, a.choiceMap});
    AutoOptions options;
    options.window = parseOptionalInteger(a.window, "--window");
    options.temperature = a.temperature;
    options.confidence = a.confidence;
    options.finer = parseOptionalInteger(a.finer, "--finer");
    options.feather = parseOptionalInteger(a.feather, "--feather");
    options.featherGate = a.featherGate;
    options.sure.epsilon = a.epsilon;
    options.sure.seed = glint::cli::parseUnsigned(a.seed, glint::cli::kMaxSeed, "--seed");
    options.exposure = a.exposure;
    options.symmetric = !a.oneSided;
    options.shortlist = parseInteger(a.shortlist, "--shortlist");
    options.stack = parseOptionalInteger(a.stack, "--stack");
    options.stackWindow = parseInteger(a.stackWindow, "--stack-window");
    options.stackRidge = a.stackRidge;
    options.stackSmooth = parseInteger(a.stackSmooth, "--stack-smooth");
    options.stackFloor = a.stackFloor;
    options.stackFeatureWindow = parseInteger(a.stackFeatureWindow, "--stack-feature-window");
    // Unset: the features the input has; a list: exactly those (each must be there).
    if (!a.stackFeatures.empty()) options.stackAlbedo = options.stackNormal = false;
    if (!a.stackFeatures.empty() && a.stackFeatures != "none")
        for (const std::string& name : splitList(a.stackFeatures)) {
            if (name == "albedo")
                options.stackAlbedo = true;
            else if (name == "normal")
                options.stackNormal = true;
            else
                throw Error(ErrorKind::InvalidArgument,
                            "unknown stacking feature '" + name +
                                "' (expected a comma-separated list of albedo, normal; or none)",
                            "command line", "--stack-features");
        }
    try {
        options.estimator = parseAutoEstimator(a.estimator);
    } catch (const Error& e) {
        throw Error(ErrorKind::InvalidArgument, e.message(), "command line", "--estimator");
    }
    try {
        options.space = parseSureSpace(a.space);
    } catch (const Error& e) {
        throw Error(ErrorKind::InvalidArgument, e.message(), "command line", "--space");
    }
    validate(options);
    BankOptions bankOptions;
    bankOptions.size = parseInteger(a.size, "--size");
    bankOptions.seed = glint::cli::parseUnsigned(a.bankSeed, glint::cli::kMaxSeed, "--bank-seed");
    bankOptions.filters = splitList(a.filters);
    bankOptions.prefilter = a.prefilter;
    if (a.bank.empty()) {
        validate(bankOptions);
    } else {
        std::error_code ec;
        if (!fs::is_directory(a.bank, ec))
            throw Error(ErrorKind::Io,
                        "no bank folder here; build one with `glint-denoise bank IN --out DIR`",
                        a.bank, "--bank");
        bankOptions = readBankOptions(a.bank);
    }
    options.prefilter = bankOptions.prefilter;
    options.prefilterParams = bankOptions.prefilterParams;

    const FrameBuffers frame = readExr(a.input);
    // SURE needs the variance layer, the halves every half layer, both finite values: say so
    // before building anything.
    try {
        checkAutoInput(frame, options.estimator, a.input);
        if (options.space == SureSpace::DisplayExact &&
            resolveEstimator(options.estimator, frame) != AutoEstimator::Halves)
            throw Error(ErrorKind::InvalidArgument,
                        "the exact display space needs the halves estimator (a render with "
                        "--half-buffers)",
                        "command line", "--space");
    } catch (const Error& e) {
        rethrowNaming(e, a.input);
    }
    std::optional<FrameBuffers> reference;
    if (!a.reference.empty()) reference = readReference(a.reference, frame.width(), frame.height());

    const bool tty = isatty(fileno(stderr)) != 0 && !a.json;
    auto progressLine = [tty](const char* what) -> ProgressFn {
        if (!tty) return {};
        return [what](double f) {
            std::fprintf(stderr, "\rglint-denoise: %s %3d%%", what, int(f * 100.0 + 0.5));
            return true;
        };
    };
    // Without a bank folder, the members are filtered strip by strip and never held all at once
    // (autoCompositeStreamed; docs/auto.md, "Memory"); with one, its results are read.
    const bool streamed = a.bank.empty();
    const auto t0 = Clock::now();
    FilterBank bank;
    if (!streamed) {
        bank = openBank(frame, a.bank, progressLine("bank"));
        if (tty) std::fprintf(stderr, "\n");
    }
    const double bankSeconds = secondsSince(t0);
    const auto t1 = Clock::now();
    options.progress = progressLine(streamed ? "auto" : "SURE");
    AutoResult result;
    try {
        if (streamed) {
            StreamedAuto s = autoCompositeStreamed(frame, bankOptions, options);
            bank = std::move(s.bank);
            result = std::move(s.result);
        } else {
            result = autoComposite(bank, frame, options);
        }
    } catch (const Error& e) {
        rethrowNaming(e, a.input);
    }
    if (tty) std::fprintf(stderr, "\n");
    const double sureSeconds = secondsSince(t1);

    // The output: every input layer, the colour replaced by the composite over the bank's region.
    FrameBuffers out = frame;
    paste(out.color(), result.composite, bank.region().x0, bank.region().y0);
    out.metadata().extra["denoiseFilter"] = std::string("auto");

    int analytic = 0;
    for (bool b : result.analytic) analytic += b ? 1 : 0;
    json report{
        {"input", a.input},
        {"output", a.out},
        {"bank", a.bank.empty() ? json(nullptr) : json(a.bank)},
        {"members", bank.size()},
        {"membersUsed", result.layers.size()},
        {"analyticDivergence", analytic},
        {"region", {bank.region().x0, bank.region().x1, bank.region().y0, bank.region().y1}},
        {"space", a.space},
        {"estimator", autoEstimatorName(result.estimator)},
        {"symmetric", options.symmetric},
        {"shortlist", options.shortlist},
        {"window", options.window.value_or(autoDefaults(result.estimator).window)},
        {"confidence", options.confidence.value_or(autoDefaults(result.estimator).confidence)},
        {"temperature", options.temperature.value_or(autoDefaults(result.estimator).temperature)},
        {"finer", options.finer.value_or(autoDefaults(result.estimator).finer)},
        {"feather", options.feather.value_or(autoDefaults(result.estimator).feather)},
        {"featherGate", options.featherGate},
        {"stack", result.stacked},
        {"stackWindow", options.stackWindow},
        {"stackRidge", options.stackRidge},
        {"stackFloor", options.stackFloor},
        {"stackSmooth", options.stackSmooth},
        {"stackFeatures", result.stackFeatures},
        {"stackFeatureWindow", options.stackFeatureWindow},
        {"epsilon", a.epsilon},
        {"seed", options.sure.seed},
        {"bestMember", memberJson(bank, result.bestMember)},
        {"bestMemberEstimatedMse", result.estimatedMse[std::size_t(result.bestMember)]},
        {"bankSeconds", bankSeconds},
        {"sureSeconds", sureSeconds}};
    if (reference) {
        report["reference"] = a.reference;
        const std::optional<Rect> crop = bank.region();
        report["metricsInput"] = metricsOf(frame.color(), reference->color(), crop);
        report["metrics"] = metricsOf(out.color(), reference->color(), crop);
        FrameBuffers single = frame;
        paste(single.color(), bestMemberResult(bank, frame, result.bestMember, bankOptions),
              bank.region().x0, bank.region().y0);
        report["metricsBestMember"] = metricsOf(single.color(), reference->color(), crop);
    }
    // Written last, so that an error before leaves no output file behind.
    if (!a.choiceMap.empty()) {
        DisplayOptions d;
        d.falseColorChannel = 0;
        d.falseColorLo = 0.0f;
        d.falseColorHi = float(std::max<std::size_t>(bank.size(), 2) - 1);
        writePng(result.choice, a.choiceMap, d);
    }
    writeExr(out, a.out);
    if (a.json) {
        printJson(report);
        return;
    }
    std::printf(
        "auto: %zu of %zu members used over %dx%d, errors by %s (bank %.2f s, %.2f s) -> %s\n",
        result.layers.size(), bank.size(), bank.region().width(), bank.region().height(),
        result.estimator == AutoEstimator::Halves ? "cross-validation on the halves" : "SURE",
        bankSeconds, sureSeconds, a.out.c_str());
    const BankMember& best = bank.members()[std::size_t(result.bestMember)];
    std::printf("  smallest estimated error as a single member: #%d %s\n", result.bestMember,
                best.filter.c_str());
    if (reference) {
        auto ssimOf = [](const json& m) {
            return m["ssim"].is_null() ? -1.0 : m["ssim"].get<double>();
        };
        std::printf("  SSIM against %s: noisy %.4f, that member %.4f, auto %.4f\n",
                    a.reference.c_str(), ssimOf(report["metricsInput"]),
                    ssimOf(report["metricsBestMember"]), ssimOf(report["metrics"]));
    }
}

}  // namespace

json autoOracleColumn(const FilterBank& bank, const FrameBuffers& frame, const Image& reference,
                      const std::string& bankDir) {
    try {
        checkAutoInput(frame, AutoEstimator::Auto);
    } catch (const Error& e) {
        return {{"ssim", nullptr}, {"note", e.where() + ": " + e.message()}};
    }
    AutoOptions options;
    const BankOptions bankOptions = readBankOptions(bankDir);
    options.prefilter = bankOptions.prefilter;
    options.prefilterParams = bankOptions.prefilterParams;
    const auto t0 = Clock::now();
    const AutoResult r = autoComposite(bank, frame, options);
    const double seconds = secondsSince(t0);
    MetricOptions mo;
    return {{"ssim", ssim(r.composite, reference.crop(bank.region()), mo).value},
            {"membersUsed", r.layers.size()},
            {"estimator", autoEstimatorName(r.estimator)},
            {"bestMember", memberJson(bank, r.bestMember)},
            {"seconds", seconds}};
}

std::vector<Command> addAutoCommands(CLI::App& app) {
    auto a = std::make_shared<AutoArgs>();
    CLI::App* cmd = app.add_subcommand(
        "auto", "Per-pixel filter choice by SURE over a bank (no reference needed)");
    cmd->add_option("IN", a->input,
                    "Input layered EXR with the variance layer (SURE) or half buffers")
        ->required();
    cmd->add_option("--out", a->out, "Output layered EXR (the colour is the auto composite)")
        ->required();
    cmd->add_option("--bank", a->bank,
                    "Bank folder of IN (glint-denoise bank); without it a bank is built in "
                    "memory");
    cmd->add_option("--reference", a->reference, "Reference EXR: print SSIM/PSNR/relMSE");
    cmd->add_option("--size", a->size, "Without --bank: Latin-hypercube members (1 … 4096)");
    cmd->add_option("--bank-seed", a->bankSeed,
                    "Without --bank: seed of the Latin hypercube (0 … 2^63 - 1)");
    cmd->add_option("--filters", a->filters, "Without --bank: only these filters, comma-separated");
    cmd->add_flag("--prefilter", a->prefilter, "Without --bank: build on prefiltered features");
    cmd->add_option(
        "--window", a->window,
        "Radius of the error maps' box smoothing (0 … 64; default 4 for SURE, 8 for the "
        "halves)");
    cmd->add_option("--temperature", a->temperature,
                    "0: hard per-pixel choice; > 0: soft weights (in units of the noise variance; "
                    "default 0 for SURE, 0.06 for the halves)");
    cmd->add_option(
        "--confidence", a->confidence,
        "Standard errors by which a local choice must beat the baseline (>= 0; default 3 "
        "for SURE, 1 for the halves)");
    cmd->add_option("--finer", a->finer,
                    "Times the window is halved for the final choice, which keeps the lowest "
                    "score (0 … 6; default 0 for SURE, 1 for the halves)");
    cmd->add_option("--feather", a->feather,
                    "Radius over which each member's weights are smoothed before the composite "
                    "(0 … 32; 0: off; default 4 for SURE, 5 for the halves)");
    cmd->add_option("--feather-gate", a->featherGate,
                    "No feathered weight where a member's display value is farther than this from "
                    "the unfeathered composite's (> 0; default 0.2)");
    cmd->add_option("--epsilon", a->epsilon, "Perturbation relative to the pixel's sigma");
    cmd->add_option("--seed", a->seed, "Seed of the random +-1 perturbation (0 … 2^63 - 1)");
    cmd->add_option(
        "--space", a->space,
        "display (default) | display-tangent | display-exact (halves only) | linear: the "
        "error estimated");
    cmd->add_option("--exposure", a->exposure,
                    "Exposure of the display transform (stops, -64 … 64)");
    cmd->add_option("--estimator", a->estimator,
                    "auto (default: halves when IN has half buffers, else sure) | sure | halves");
    cmd->add_flag("--one-sided", a->oneSided,
                  "Halves: filter only half A (half the time, noisier estimates)");
    cmd->add_option("--shortlist", a->shortlist,
                    "Halves: filter only the K members with the most weight after a one-sided "
                    "first choice on both halves, and choose among them (default 16; 0: all)");
    cmd->add_option("--stack", a->stack,
                    "Halves: correct the composite per pixel by a local ridge regression of each "
                    "half on the K members of most weight on the other half (0 … 16; 0: off; "
                    "default 6 for the halves, 0 one-sided or for SURE)");
    cmd->add_option("--stack-window", a->stackWindow,
                    "Radius of the stacking's window in pixels (1 … 64; default 6)");
    cmd->add_option("--stack-ridge", a->stackRidge,
                    "The stacking's ridge in units of the halves' noise (>= 0; default 0.5)");
    cmd->add_option("--stack-floor", a->stackFloor,
                    "The stacking's ridge floor in units of the members' mean squared difference "
                    "from the composite (0 … 100; default 0.1)");
    cmd->add_option("--stack-smooth", a->stackSmooth,
                    "Radius over which each pixel averages the coefficients fitted around it "
                    "(0 … 64; 0: its own; default 8)");
    cmd->add_option("--stack-features", a->stackFeatures,
                    "The features whose local deviations the stacking also fits, "
                    "comma-separated: albedo, normal; none: the members only (default: those "
                    "the input has)");
    cmd->add_option("--stack-feature-window", a->stackFeatureWindow,
                    "Radius of the features' local average in the stacking (1 … 64; default 3)");
    cmd->add_option("--choice-map", a->choiceMap, "Write the chosen member per pixel as a PNG");
    cmd->add_flag("--json", a->json, "Print one JSON object on stdout");
    return {{cmd, [a] { runAuto(*a); }}};
}

}  // namespace glint::denoise::cli

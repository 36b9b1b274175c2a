// glint-denoise auto: the automatic local baseline — every bank member's per-pixel error
// estimated by SURE from the render's variance or by cross-validation on its halves (no
// reference), a per-pixel choice among them, written as a layered EXR (docs/auto.md).
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <sstream>
#include <utility>

#include "auto_args.h"
#include "cli_boundary.h"
#include "commands.h"
#include "glint/denoise/auto.h"
#include "glint/denoise/auto_stream.h"
#include "glint/denoise/bank.h"
#include "glint/denoise/prefilter.h"
#include "glint/denoise/registry.h"
#include "glint/image/composite.h"
#include "glint/image/error.h"
#include "glint/image/io.h"
#include "glint/image/memory.h"
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

// The tuning map from the flags given: each value parsed as its spec reads it, errors naming
// the flag (the range is checked by validate).
ParamValues parseTuning(const AutoArgs& a) {
    ParamValues tuning;
    for (const auto& [name, text] : a.tuning) {
        const ParamSpec& spec = *findParam(autoTuningSpecs(), name);
        // Integers strictly, as every integer flag ("0x4", "4.0" and "4 " are refused).
        if (spec.integer && !spec.isChoice()) {
            const std::string flag = autoTuningFlag(name);
            tuning[name] = parseInteger(text, flag.c_str());
            continue;
        }
        try {
            tuning[name] = parseParamValue(spec, text);
        } catch (const Error& e) {
            throw Error(ErrorKind::InvalidArgument, e.message(), "command line",
                        autoTuningFlag(name));
        }
    }
    return tuning;
}

// --noise-out: the variance of the mean SURE used (the image-only estimate or the render's
// variance layer) as the colour of an EXR.
void writeNoise(const FrameBuffers& frame, const AutoOptions& options, const std::string& path) {
    FrameBuffers noise(frame.width(), frame.height());
    noise.set(Layer::Color, options.estimator == AutoEstimator::Image
                                ? withImageNoiseVariance(frame, options).layer(Layer::Variance)
                                : frame.layer(Layer::Variance));
    writeExr(noise, path);
}

// How the output names an estimator.
const char* estimatorText(AutoEstimator estimator) {
    switch (estimator) {
        case AutoEstimator::Halves:
            return "cross-validation on the halves";
        case AutoEstimator::Image:
            return "SURE with the image-only noise estimate";
        default:
            return "SURE";
    }
}

// Refuses before any work outputs that would replace one of the command's inputs.
void checkOutputsAreNoInputs(const AutoArgs& a) {
    for (const auto& [output, flag] :
         {std::pair{a.out, "--out"}, std::pair{a.choiceMap, "--choice-map"},
          std::pair{a.noiseOut, "--noise-out"}})
        glint::cli::checkOutputIsNoInput(output, flag,
                                         {{a.input, "IN"}, {a.reference, "--reference"}});
    checkOutputIsNoBankFile(a.out, "--out", a.bank);
    checkOutputIsNoBankFile(a.choiceMap, "--choice-map", a.bank);
    checkOutputIsNoBankFile(a.noiseOut, "--noise-out", a.bank);
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

// Whether a bank folder's results, read whole, fit `limit` (0: the memory available) beside the
// selection's own budget (docs/auto-memory.md); else its members are applied again.
bool bankFolderFits(const FrameBuffers& frame, const BankOptions& bankOptions,
                    std::uint64_t limit) {
    const std::uint64_t need =
        saturatingAdd(estimateMemory(frame, bankOptions), autoMemoryBudget(limit));
    return need <= (limit > 0 ? limit : availableMemory());
}

// Refuses, naming `file` and the first missing layer, a --filters list none of whose filters
// can run on `frame` for want of feature layers (NFOR's albedo, normal and depth, say).
void checkFiltersCanRun(const FrameBuffers& frame, const BankOptions& options,
                        const std::string& file) {
    if (options.filters.empty()) return;
    std::string firstMissing, filterName;
    for (const std::string& name : options.filters) {
        const Filter& f = findFilter(name);
        std::string missing;
        for (Layer l : f.requiredLayers(resolveParams(f, options.filterParams.count(name)
                                                             ? options.filterParams.at(name)
                                                             : ParamValues{})))
            if (!frame.has(l))
                missing += (missing.empty() ? "" : ", ") + std::string(layerDisplayName(l));
        if (missing.empty()) return;
        if (firstMissing.empty()) {
            firstMissing = missing;
            filterName = name;
        }
    }
    throw Error(ErrorKind::Format,
                "has no " + firstMissing + " layer(s): filter '" + filterName +
                    "' needs them and no other filter of --filters can run",
                file, "layer '" + firstMissing.substr(0, firstMissing.find(',')) + "'");
}

// With the image-only estimator (asked for, or auto's fallback on a render with neither half
// buffers nor a variance layer): says so on stderr. The filters see the frame as the renderer
// wrote it: a variance layer that --estimator image leaves unused is dropped before the bank is
// built here (a bank folder was built from the frame as it is).
void useImageNoise(FrameBuffers& frame, AutoOptions& options, const AutoArgs& a) {
    if (resolveEstimator(options.estimator, frame) != AutoEstimator::Image) return;
    if (options.estimator == AutoEstimator::Auto)
        std::fprintf(stderr,
                     "glint-denoise: %s has neither half buffers nor a variance layer: auto falls "
                     "back to the image-only noise estimator (SURE with the variance estimated "
                     "from the image)\n",
                     a.input.c_str());
    else if (frame.has(Layer::Variance))
        std::fprintf(stderr,
                     "glint-denoise: --estimator image: the variance layer of %s is not used; "
                     "the image-only estimate replaces it\n",
                     a.input.c_str());
    options.estimator = AutoEstimator::Image;
    if (a.bank.empty()) frame.remove(Layer::Variance);
}

}  // namespace

void runAuto(const AutoArgs& a) {
    if (a.input.empty() || a.out.empty())
        throw Error(ErrorKind::InvalidArgument, "IN and --out are required", "command line",
                    a.input.empty() ? "IN" : "--out");
    // Everything that needs no image is checked first; nothing is written before the end.
    glint::cli::checkOutputPath(a.out, {".exr"}, "--out");
    if (!a.choiceMap.empty()) glint::cli::checkOutputPath(a.choiceMap, {".png"}, "--choice-map");
    if (!a.noiseOut.empty()) glint::cli::checkOutputPath(a.noiseOut, {".exr"}, "--noise-out");
    checkOutputsAreNoInputs(a);
    checkSessionOutput(
        a.session, "--session", {{a.input, "IN"}, {a.reference, "--reference"}, {a.bank, "--bank"}},
        {{a.out, "--out"}, {a.choiceMap, "--choice-map"}, {a.noiseOut, "--noise-out"}});
    checkOutputIsNoBankFile(a.session, "--session", a.bank);
    glint::cli::removeTemporariesOnSignal({a.out, a.choiceMap, a.noiseOut});
    AutoQuality quality = AutoQuality::Balanced;
    try {
        quality = parseAutoQuality(a.quality);
    } catch (const Error& e) {
        throw Error(ErrorKind::InvalidArgument, e.message(), "command line", "--quality");
    }
    AutoOptions options;
    // The quality's tuning, then each tuning flag given (glint-lab's) over it.
    options.tuning = autoQualityTuning(quality);
    for (const auto& [name, value] : parseTuning(a)) options.tuning[name] = value;
    options.seed = glint::cli::parseUnsigned(a.seed, glint::cli::kMaxSeed, "--seed");
    options.exposure = a.exposure;
    try {
        options.estimator = parseAutoEstimator(a.estimator);
    } catch (const Error& e) {
        throw Error(ErrorKind::InvalidArgument, e.message(), "command line", "--estimator");
    }
    validate(options);
    const std::uint64_t memoryLimit =
        a.memoryLimit.empty() ? 0 : parseMemorySize(a.memoryLimit, "--memory-limit");
    BankOptions bankOptions;
    bankOptions.size =
        a.size.empty() ? autoQualityBankSize(quality) : parseInteger(a.size, "--size");
    bankOptions.seed = glint::cli::parseUnsigned(a.bankSeed, glint::cli::kMaxSeed, "--bank-seed");
    bankOptions.filters = splitList(a.filters);
    bankOptions.filterParams = parseFilterParams(a.filterParams, "--filter-param");
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
    bankOptions.memoryLimit = memoryLimit;
    options.memoryLimit = memoryLimit;
    options.prefilter = bankOptions.prefilter;
    options.prefilterParams = bankOptions.prefilterParams;

    InputFrame input = readInput(a.input);  // a denoised file's colour stays outside the region
    FrameBuffers& frame = input.frame;
    // SURE needs the variance layer, the halves every half layer, both finite values: say so
    // before building anything.
    try {
        if (a.bank.empty()) checkFiltersCanRun(frame, bankOptions, a.input);
        checkAutoInput(frame, options.estimator, a.input);
        useImageNoise(frame, options, a);
        if (!a.noiseOut.empty() &&
            resolveEstimator(options.estimator, frame) == AutoEstimator::Halves)
            throw Error(ErrorKind::InvalidArgument,
                        "the halves estimator uses no variance of the mean to write (--noise-out "
                        "is for SURE and the image-only estimator)",
                        "command line", "--noise-out");
        const ParamSpec& space = *findParam(autoTuningSpecs(), "space");
        if (options.tuning.count("space") &&
            space.choices[std::size_t(options.tuning.at("space"))] == "display-exact" &&
            resolveEstimator(options.estimator, frame) != AutoEstimator::Halves)
            throw Error(ErrorKind::InvalidArgument,
                        "the exact display space needs the halves estimator (a render with "
                        "--set halfBuffers=true)",
                        "command line", "--space");
    } catch (const Error& e) {
        rethrowNaming(e, a.input);
    }
    if (!a.session.empty() && bankOptions.region &&
        *bankOptions.region != Rect{0, frame.width(), 0, frame.height()})
        throw Error(ErrorKind::InvalidArgument,
                    "a session starts from a bank over the whole frame; the bank " + a.bank +
                        " covers a region of it",
                    "command line", "--session");
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
    // The selection applies the members tile by tile, the tiles' height from --memory-limit
    // (autoCompositeStreamed; docs/auto-memory.md). A bank folder's stored results are read
    // instead when they fit in memory beside it; else its members (the same options) are
    // applied again: the same result.
    sayInput(input);
    const bool readFolder = !a.bank.empty() && bankFolderFits(frame, bankOptions, memoryLimit);
    if (!a.bank.empty() && !readFolder)
        std::fprintf(stderr,
                     "glint-denoise: the members of the bank %s are applied again tile by tile "
                     "(its stored results do not fit in memory)\n",
                     a.bank.c_str());
    // A default bank, built here or reopened from its folder, says once what
    // it goes without.
    const json leftOut = reportLeftOutFilters(bankOptions);
    const auto t0 = Clock::now();
    FilterBank bank;
    if (readFolder) {
        bank = openBank(frame, a.bank, progressLine("bank"));
        if (tty) std::fprintf(stderr, "\n");
    }
    const double bankSeconds = secondsSince(t0);
    const auto t1 = Clock::now();
    options.progress = progressLine("auto");
    AutoResult result;
    try {
        if (!readFolder) {
            StreamedAuto s = autoCompositeStreamed(frame, bankOptions, options);
            bank = std::move(s.bank);
            result = std::move(s.result);
            if (!s.warning.empty())
                std::fprintf(stderr, "glint-denoise: warning: %s\n", s.warning.c_str());
        } else {
            result = autoComposite(bank, frame, options);
        }
    } catch (const Error& e) {
        rethrowNaming(e, a.input);
    }
    if (tty) std::fprintf(stderr, "\n");
    const double sureSeconds = secondsSince(t1);
    const json unavailable = reportUnavailableMembers(bank, a.bank.empty() ? a.input : a.bank);

    // The output: every input layer (shared, not copied), the colour replaced by the composite
    // over the bank's region (outside it, a denoised file's own), the render's kept as noisy.
    FrameBuffers out = denoisedFrame(frame, result.composite, bank.region().x0, bank.region().y0,
                                     "auto", input.shown ? &*input.shown : nullptr);

    int analytic = 0;
    for (bool b : result.analytic) analytic += b ? 1 : 0;
    json report{{"input", a.input},
                {"output", a.out},
                {"bank", a.bank.empty() ? json(nullptr) : json(a.bank)},
                {"members", bank.size()},
                {"membersUsed", result.layers.size()},
                {"analyticDivergence", analytic},
                {"region", rectJson(bank.region())},
                {"estimator", autoEstimatorName(result.estimator)},
                {"quality", autoQualityName(quality)},
                {"seed", options.seed},
                {"tileRows", result.tileRows},
                {"stackFeatures", result.stackFeatures},
                {"bestMember", memberJson(bank, result.bestMember)},
                {"bestMemberEstimatedMse", result.estimatedMse[std::size_t(result.bestMember)]},
                {"bankSeconds", bankSeconds},
                {"sureSeconds", sureSeconds}};
    if (!leftOut.empty()) report["leftOut"] = leftOut;
    // Each member's share of the blend: its weight plane's mean over the region.
    json layers = json::array();
    for (const AutoLayer& l : result.layers) {
        double sum = 0.0;
        for (float w : l.weights.data()) sum += double(w);
        layers.push_back(
            {{"member", l.member},
             {"filter", bank.members()[std::size_t(l.member)].filter},
             {"share", sum / double(std::max<std::size_t>(l.weights.pixelCount(), 1))}});
    }
    report["layers"] = layers;
    // Every tuning parameter as used (choices by their option name).
    const ParamValues tuning = resolveAutoTuning(options, result.estimator);
    for (const ParamSpec& spec : autoTuningSpecs()) {
        const double v = tuning.at(spec.name);
        if (spec.isChoice())
            report[spec.name] = formatParamValue(spec, v);
        else if (spec.integer)
            report[spec.name] = std::int64_t(v);
        else
            report[spec.name] = v;
    }
    report["stack"] = result.stacked;
    if (!unavailable.empty()) report["unavailable"] = unavailable;
    if (reference) {
        report["reference"] = a.reference;
        const std::optional<Rect> crop = bank.region();
        report["metricsInput"] = metricsOf(std::as_const(frame).color(), reference->color(), crop);
        report["metrics"] = metricsOf(out.color(), reference->color(), crop);
        Image single = std::as_const(frame).color();
        paste(single, bestMemberResult(bank, frame, result.bestMember, bankOptions),
              bank.region().x0, bank.region().y0);
        report["metricsBestMember"] = metricsOf(single, reference->color(), crop);
    }
    // Written last, so that an error before leaves no output file behind.
    if (!a.choiceMap.empty()) writeChoiceMap(result.choice, bank.size(), a.choiceMap);
    if (!a.noiseOut.empty()) writeNoise(frame, options, a.noiseOut);
    if (!a.session.empty()) {
        report["session"] = a.session;
        report["sessionLayers"] = writeAutoSession(a.session, frame, bankOptions, bank, result);
    }
    writeExr(out, a.out);
    if (a.json) {
        printJson(report);
        return;
    }
    std::printf(
        "auto: %zu of %zu members used over %dx%d, errors by %s (bank %.2f s, %.2f s) -> %s\n",
        result.layers.size(), bank.size(), bank.region().width(), bank.region().height(),
        estimatorText(result.estimator), bankSeconds, sureSeconds, a.out.c_str());
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

void addTuningFlag(CLI::App* cmd, const std::shared_ptr<AutoArgs>& a, const ParamSpec& spec) {
    const std::string flag = autoTuningFlag(spec.name);
    std::string help = spec.help;
    if (isTuningSwitch(spec)) {
        cmd->add_flag_callback(
            flag, [a, name = spec.name] { a->tuning[name] = "1"; }, help);
        return;
    }
    const double s = autoTuningDefaults(AutoEstimator::Sure).at(spec.name);
    help += " (";
    if (spec.isChoice()) {
        for (std::size_t i = 0; i < spec.choices.size(); ++i)
            help += (i ? " | " : "") + spec.choices[i];
        help += "; ";
    } else {
        help += formatParamValue(spec, spec.min) + " … " + formatParamValue(spec, spec.max) + "; ";
    }
    help += "default " + formatParamValue(spec, spec.defaultValue);
    if (s != spec.defaultValue) help += ", with SURE " + formatParamValue(spec, s);
    help += ")";
    cmd->add_option_function<std::string>(
        flag, [a, name = spec.name](const std::string& text) { a->tuning[name] = text; }, help);
}

bool isTuningSwitch(const ParamSpec& spec) {
    // A choice of two names is an option that takes one of them, not a switch.
    return !spec.isChoice() && spec.integer && spec.min == 0.0 && spec.max == 1.0 &&
           spec.defaultValue == 0.0;
}

CLI::App* addAutoFlags(CLI::App& app, const std::shared_ptr<AutoArgs>& a) {
    CLI::App* cmd = app.add_subcommand(
        "auto",
        "Denoise a render without a reference: many filter settings are tried and each pixel "
        "takes those whose error it estimates lowest there");
    cmd->add_option("IN", a->input,
                    "The render: a layered EXR (Glint's, with half buffers or its variance layer, "
                    "or any renderer's)");
    cmd->add_option("--out", a->out,
                    "The denoised render: a layered EXR with every layer of IN, its colour "
                    "denoised");
    cmd->add_option("--quality", a->quality,
                    "fast | balanced | best: fast tries 32 filter settings and checks each on "
                    "one half of the samples (about 0.7 × the time), best tries 128 (about 1.4 × "
                    "the time); default balanced, 64 settings");
    cmd->add_option("--bank", a->bank,
                    "A bank folder of IN (glint-denoise bank) to reuse; without it the filter "
                    "settings are tried here");
    cmd->add_option("--filters", a->filters,
                    "Without --bank: try only these filters, comma-separated (glint-denoise "
                    "list)");
    cmd->add_option("--estimator", a->estimator,
                    "How each setting's error is estimated: auto (default: from IN's half "
                    "buffers, else its variance layer, else the image alone) | halves | sure | "
                    "image");
    cmd->add_option("--exposure", a->exposure,
                    "The exposure you view the image at (stops, -64 … 64): errors are weighed as "
                    "they look there");
    cmd->add_option("--seed", a->seed,
                    "Seed of the estimate's random numbers (0 … 2^63 - 1): the same seed, the same "
                    "image");
    cmd->add_option("--memory-limit", a->memoryLimit,
                    "Memory the selection may use besides IN (e.g. 1G; default 1.25G, or less "
                    "when less is available or GLINT_MEMORY_LIMIT says so): a smaller limit "
                    "cuts the frame into more tiles, the same result");
    cmd->add_option("--session", a->session,
                    "Also write a painting session NAME.glint-session.json that starts from the "
                    "result: the filters as layers and auto's correction, its image OUT's "
                    "colour (open it in Glint Studio to paint, or glint-denoise composite)");
    cmd->add_flag("--json", a->json, "Print one JSON object on stdout");
    return cmd;
}

std::vector<Command> addAutoCommands(CLI::App& app) {
    auto a = std::make_shared<AutoArgs>();
    CLI::App* cmd = addAutoFlags(app, a);
    return {{cmd, [a] { runAuto(*a); }}};
}

}  // namespace glint::denoise::cli

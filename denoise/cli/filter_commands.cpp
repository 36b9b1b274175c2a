// glint-denoise list | apply: the registered filters and their parameters; one filter applied
// to a layered EXR (docs/denoise.md).
#include <chrono>
#include <cstdio>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cli_boundary.h"
#include "commands.h"
#include "glint/denoise/denoised_frame.h"
#include "glint/denoise/filter.h"
#include "glint/denoise/prefilter.h"
#include "glint/denoise/registry.h"
#include "glint/image/composite.h"
#include "glint/image/error.h"
#include "glint/image/io.h"
#include "glint/image/metrics.h"

namespace glint::denoise::cli {

namespace {

using nlohmann::json;

struct ApplyOptions {
    std::string input;
    std::string filter;
    std::vector<std::string> params;
    bool prefilter = false;
    std::string roi;
    std::string output;
    std::string reference;
    bool json = false;
};

// Prints one parameter table as text.
void printParams(const json& params) {
    for (const json& p : params) {
        char line[512];
        if (p.value("kind", "") == "strings") {
            std::snprintf(line, sizeof line, "    %-16s %-8s default %s  %s\n",
                          p["name"].get<std::string>().c_str(), "list",
                          p["defaultStrings"].dump().c_str(), p["help"].get<std::string>().c_str());
        } else if (p.contains("choices")) {
            std::string options;
            for (const auto& c : p["choices"])
                options += (options.empty() ? "" : "|") + c.get<std::string>();
            std::snprintf(
                line, sizeof line, "    %-16s %-8s %s default %s  %s\n",
                p["name"].get<std::string>().c_str(), "choice", options.c_str(),
                p["choices"][std::size_t(p["default"].get<double>())].get<std::string>().c_str(),
                p["help"].get<std::string>().c_str());
        } else {
            std::snprintf(
                line, sizeof line, "    %-16s %-8s [%g, %g] default %g%s  %s\n",
                p["name"].get<std::string>().c_str(), p["scale"].get<std::string>().c_str(),
                p["min"].get<double>(), p["max"].get<double>(), p["default"].get<double>(),
                p["integer"].get<bool>() ? " (integer)" : "", p["help"].get<std::string>().c_str());
        }
        std::cout << line;
    }
}

// `glint-denoise list`: every filter's description and parameter table, and the prefilter's.
void runList(bool asJson) {
    json all = json::array();
    for (const Filter* f : allFilters()) {
        json entry{{"name", f->name()}, {"description", f->description()}};
        json layers = json::array();
        for (Layer l : f->requiredLayers(resolveParams(*f, {})))
            layers.push_back(layerDisplayName(l));
        entry["requiredLayers"] = layers;
        entry["params"] = describe(f->params());
        all.push_back(entry);
    }
    const json prefilter{
        {"description", "Variance-aware smoothing of albedo, normal and depth (--prefilter)."},
        {"params", describe(prefilterParams())}};
    if (asJson) {
        std::cout << json{{"filters", all}, {"prefilter", prefilter}}.dump(2) << "\n";
        return;
    }
    for (const json& f : all) {
        std::cout << f["name"].get<std::string>() << "\n  " << f["description"].get<std::string>()
                  << "\n";
        if (!f["requiredLayers"].empty()) {
            std::cout << "  needs layers:";
            for (const auto& l : f["requiredLayers"]) std::cout << " " << l.get<std::string>();
            std::cout << "\n";
        }
        printParams(f["params"]);
        std::cout << "\n";
    }
    std::cout << "prefilter (--prefilter, prefilter.NAME=VALUE)\n  "
              << prefilter["description"].get<std::string>() << "\n";
    printParams(prefilter["params"]);
}

// `glint-denoise apply`: filter the colour of IN (optionally within a ROI) and write OUT.
void runApply(const ApplyOptions& opt) {
    glint::cli::checkOutputPath(opt.output, {".exr"}, "--out");
    glint::cli::checkOutputIsNoInput(opt.output, "--out",
                                     {{opt.input, "IN"}, {opt.reference, "--reference"}});
    glint::cli::removeTemporariesOnSignal({opt.output});
    const Filter& filter = findFilter(opt.filter);
    // Validate everything that does not need the image before reading it: the prefilter's
    // parameters (prefilter.NAME=VALUE), then the filter's.
    std::vector<std::string> given = opt.params;
    const ParamValues prefilterValues = takePrefilterParams(given, opt.prefilter, "--param");
    const ParamValues params = parseParams(
        given, filter.params(), "filter '" + std::string(filter.name()) + "'", "--param");
    // A filter that cannot run here (an external program not allowed) stops before any work.
    if (const std::string why = filter.unavailable(params); !why.empty())
        throw Error(ErrorKind::InvalidArgument, "unavailable: " + why, {},
                    "filter '" + std::string(filter.name()) + "'");

    InputFrame input = readInput(opt.input);  // a denoised file's colour stays outside --roi
    FrameBuffers& frame = input.frame;
    const Rect bounds{0, frame.width(), 0, frame.height()};
    std::optional<Rect> roi;
    if (!opt.roi.empty()) roi = parseRegion(opt.roi, frame.width(), frame.height(), opt.input);
    std::optional<FrameBuffers> reference;
    if (!opt.reference.empty())
        reference = readReference(opt.reference, frame.width(), frame.height());

    const auto t0 = std::chrono::steady_clock::now();
    if (opt.prefilter) frame = prefilterFeatures(frame, prefilterValues);
    const auto t1 = std::chrono::steady_clock::now();
    Image filtered;
    try {
        FilterOptions options;
        options.region = roi;
        filtered = applyFilter(filter, frame, params, options);
    } catch (const Error& e) {
        // Name the input file for errors about its content (missing layers...).
        if (e.file().empty()) throw Error(e.kind(), e.message(), opt.input, e.where());
        throw;
    }
    const auto t2 = std::chrono::steady_clock::now();
    sayInput(input);  // after the filter's checks: bad input gets one line

    // The output frame: every input layer, the colour replaced inside the region (outside it, the
    // file's own), the render's kept as the noisy layer.
    const Rect region = roi.value_or(bounds);
    const FrameBuffers out = denoisedFrame(frame, filtered, region.x0, region.y0, filter.name(),
                                           input.shown ? &*input.shown : nullptr);

    json report{{"input", opt.input},
                {"output", opt.output},
                {"filter", filter.name()},
                {"params", paramsJson(params)},
                {"prefilter", opt.prefilter},
                {"width", frame.width()},
                {"height", frame.height()},
                {"prefilterSeconds", std::chrono::duration<double>(t1 - t0).count()},
                {"filterSeconds", std::chrono::duration<double>(t2 - t1).count()}};
    if (roi) report["roi"] = rectJson(*roi);
    if (reference) {
        report["reference"] = opt.reference;
        // Metric errors (e.g. a reference that is NaN everywhere) name the files involved.
        try {
            report["metricsInput"] = metricsOf(frame.color(), reference->color(), roi);
            report["metrics"] = metricsOf(out.color(), reference->color(), roi);
        } catch (const Error& e) {
            throw Error(e.kind(), e.message() + " (against reference " + opt.reference + ")",
                        opt.input, "--reference");
        }
    }
    // Written last, so that an error in the metrics leaves no output file behind.
    writeExr(out, opt.output);
    if (opt.json) {
        printJson(report);
        return;
    }
    std::printf("%s: %s %dx%d%s in %.3f s -> %s\n", filter.name().data(), opt.input.c_str(),
                frame.width(), frame.height(), roi ? " (roi)" : "",
                report["filterSeconds"].get<double>(), opt.output.c_str());
    if (reference) {
        const json& a = report["metricsInput"];
        const json& b = report["metrics"];
        auto ssimText = [](const json& v) {
            if (v.is_null()) return std::string("n/a (region < 11x11)");
            char text[32];
            std::snprintf(text, sizeof text, "%.4f", v.get<double>());
            return std::string(text);
        };
        std::printf("  vs %s%s:  SSIM %s -> %s   PSNR %.2f -> %.2f dB   relMSE %.5g -> %.5g\n",
                    opt.reference.c_str(), roi ? " (roi)" : "", ssimText(a["ssim"]).c_str(),
                    ssimText(b["ssim"]).c_str(), a["psnr"].get<double>(), b["psnr"].get<double>(),
                    a["relmse"].get<double>(), b["relmse"].get<double>());
    }
}

}  // namespace

std::vector<Command> addFilterCommands(CLI::App& app) {
    auto listJson = std::make_shared<bool>(false);
    CLI::App* listCmd = app.add_subcommand("list", "Every filter with its parameter table");
    listCmd->add_flag("--json", *listJson, "Print JSON instead of text");

    auto apply = std::make_shared<ApplyOptions>();
    CLI::App* applyCmd = app.add_subcommand("apply", "Filter the colour of a layered EXR");
    applyCmd->add_option("IN", apply->input, "Input layered EXR")->required();
    applyCmd->add_option("--filter", apply->filter, "Filter name (see `glint-denoise list`)")
        ->required();
    applyCmd
        ->add_option("--param", apply->params,
                     "Filter parameter name=value (repeatable); with --prefilter, "
                     "prefilter.radius|sigmaSpatial|varianceScale=value sets the prefilter's")
        ->take_all();
    applyCmd->add_flag("--prefilter", apply->prefilter,
                       "Prefilter the albedo/normal/depth layers first (written to OUT)");
    applyCmd->add_option("--roi", apply->roi,
                         "Filter only x0,x1,y0,y1 (half-open); the rest of OUT is the input");
    applyCmd->add_option("--out", apply->output, "Output layered EXR")->required();
    applyCmd->add_option("--reference", apply->reference,
                         "Reference EXR: print SSIM/PSNR/relMSE of input and output");
    applyCmd->add_flag("--json", apply->json, "Print one JSON object on stdout");
    return {{listCmd, [listJson] { runList(*listJson); }},
            {applyCmd, [apply] { runApply(*apply); }}};
}

}  // namespace glint::denoise::cli

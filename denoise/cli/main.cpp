// glint-denoise: list the registered filters, or apply one to a layered EXR (docs/denoise.md).
#include <CLI/CLI.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <string>
#include <vector>
#include "cli_boundary.h"

#include "glint/denoise/filter.h"
#include "glint/denoise/prefilter.h"
#include "glint/denoise/registry.h"
#include "glint/image/composite.h"
#include "glint/image/error.h"
#include "glint/image/io.h"
#include "glint/image/metrics.h"

namespace {

using glint::Error;
using glint::ErrorKind;
using nlohmann::json;

struct ApplyOptions {
    std::string input;
    std::string filter;
    std::vector<std::string> params;
    bool prefilter = false;
    std::vector<std::string> prefilterParams;
    std::string roi;
    std::string output;
    std::string reference;
    bool json = false;
};

// Splits "name=value"; `option` names the flag in the error.
std::pair<std::string, std::string> splitKeyValue(const std::string& text,
                                                  const std::string& option) {
    const auto eq = text.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == text.size())
        throw Error(ErrorKind::InvalidArgument,
                    "'" + text + "' is not of the form name=value (e.g. sigma=2.5)", {}, option);
    return {text.substr(0, eq), text.substr(eq + 1)};
}

// Parses every "name=value" against `specs` (a choice takes an option name or its index) and
// resolves them; `owner` names the filter or the prefilter in errors.
glint::denoise::ParamValues parseParams(const std::vector<std::string>& given,
                                        const std::vector<glint::denoise::ParamSpec>& specs,
                                        const std::string& owner, const std::string& option) {
    glint::denoise::ParamValues values;
    for (const std::string& text : given) {
        const auto [key, value] = splitKeyValue(text, option);
        const glint::denoise::ParamSpec* spec = glint::denoise::findParam(specs, key);
        if (!spec) {
            values[key] = 0.0;  // resolveParams names the valid parameters
            continue;
        }
        try {
            values[key] = glint::denoise::parseParamValue(*spec, value);
        } catch (const Error& e) {
            throw Error(e.kind(), e.message(), {}, option);
        }
    }
    try {
        return glint::denoise::resolveParams(specs, values, owner);
    } catch (const Error& e) {
        throw Error(e.kind(), e.message(), {}, option);
    }
}

// Parses "x0,x1,y0,y1" (half-open pixel rectangle).
glint::Rect parseRect(const std::string& text) {
    std::vector<int> v;
    std::stringstream in(text);
    std::string item;
    while (std::getline(in, item, ',')) {
        char* end = nullptr;
        const long n = std::strtol(item.c_str(), &end, 10);
        if (item.empty() || *end != '\0' || n < 0 || n > 1 << 24)
            throw Error(ErrorKind::InvalidArgument,
                        "'" + text + "' is not x0,x1,y0,y1 (four integers in [0, 2^24])", {},
                        "--roi");
        v.push_back(int(n));
    }
    if (v.size() != 4)
        throw Error(ErrorKind::InvalidArgument, "'" + text + "' is not x0,x1,y0,y1 (four integers)",
                    {}, "--roi");
    return {v[0], v[1], v[2], v[3]};
}

// The parameter table of a filter or of the prefilter.
json describe(const std::vector<glint::denoise::ParamSpec>& specs) {
    json params = json::array();
    for (const glint::denoise::ParamSpec& s : specs) {
        json p{{"name", s.name},
               {"label", s.label},
               {"min", s.min},
               {"max", s.max},
               {"default", s.defaultValue},
               {"scale", s.scale == glint::denoise::ParamScale::Log ? "log" : "linear"},
               {"integer", s.integer},
               {"help", s.help}};
        if (s.isChoice()) p["choices"] = s.choices;
        params.push_back(p);
    }
    return params;
}

// Prints one parameter table as text.
void printParams(const json& params) {
    for (const json& p : params) {
        char line[512];
        if (p.contains("choices")) {
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
    for (const glint::denoise::Filter* f : glint::denoise::allFilters()) {
        json entry{{"name", f->name()}, {"description", f->description()}};
        json layers = json::array();
        for (glint::Layer l : f->requiredLayers(glint::denoise::resolveParams(*f, {})))
            layers.push_back(glint::layerDisplayName(l));
        entry["requiredLayers"] = layers;
        entry["params"] = describe(f->params());
        all.push_back(entry);
    }
    const json prefilter{
        {"description", "Variance-aware smoothing of albedo, normal and depth (--prefilter)."},
        {"params", describe(glint::denoise::prefilterParams())}};
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
    std::cout << "prefilter (--prefilter, --prefilter-param)\n  "
              << prefilter["description"].get<std::string>() << "\n";
    printParams(prefilter["params"]);
}

json metricsOf(const glint::Image& image, const glint::Image& reference,
               const std::optional<glint::Rect>& crop) {
    glint::MetricOptions o;
    o.crop = crop;
    // SSIM needs its 11x11 window: null for a smaller region (a small --roi is fine otherwise).
    const glint::Rect region = crop.value_or(image.bounds());
    const bool ssimFits = region.width() >= 11 && region.height() >= 11;
    return {{"ssim", ssimFits ? json(glint::ssim(image, reference, o).value) : json(nullptr)},
            {"psnr", glint::psnr(image, reference, o).value},
            {"relmse", glint::relMse(image, reference, o).value}};
}

// `glint-denoise apply`: filter the colour of IN (optionally within a ROI) and write OUT.
void runApply(const ApplyOptions& opt) {
    const glint::denoise::Filter& filter = glint::denoise::findFilter(opt.filter);
    // Validate everything that does not need the image before reading it.
    const glint::denoise::ParamValues params = parseParams(
        opt.params, filter.params(), "filter '" + std::string(filter.name()) + "'", "--param");
    const glint::denoise::ParamValues prefilterParams =
        parseParams(opt.prefilterParams, glint::denoise::prefilterParams(), "feature prefilter",
                    "--prefilter-param");
    if (!opt.prefilterParams.empty() && !opt.prefilter)
        throw Error(ErrorKind::InvalidArgument, "given without --prefilter", {},
                    "--prefilter-param");

    glint::FrameBuffers frame = glint::readExr(opt.input);
    const glint::Rect bounds{0, frame.width(), 0, frame.height()};
    std::optional<glint::Rect> roi;
    if (!opt.roi.empty()) {
        roi = parseRect(opt.roi);
        if (roi->empty() || glint::intersect(*roi, bounds) != *roi)
            throw Error(ErrorKind::InvalidArgument,
                        "'" + opt.roi + "' is empty or outside the " +
                            std::to_string(frame.width()) + "x" + std::to_string(frame.height()) +
                            " image (x0,x1,y0,y1, half-open)",
                        opt.input, "--roi");
    }
    std::optional<glint::FrameBuffers> reference;
    if (!opt.reference.empty()) {
        reference = glint::readExr(opt.reference);
        if (reference->width() != frame.width() || reference->height() != frame.height())
            throw Error(ErrorKind::InvalidArgument,
                        "reference is " + std::to_string(reference->width()) + "x" +
                            std::to_string(reference->height()) + ", the input " +
                            std::to_string(frame.width()) + "x" + std::to_string(frame.height()),
                        opt.reference);
    }

    const auto t0 = std::chrono::steady_clock::now();
    if (opt.prefilter) frame = glint::denoise::prefilterFeatures(frame, prefilterParams);
    const auto t1 = std::chrono::steady_clock::now();
    glint::Image filtered;
    try {
        glint::denoise::FilterOptions options;
        options.region = roi;
        filtered = glint::denoise::applyFilter(filter, frame, params, options);
    } catch (const Error& e) {
        // Name the input file for errors about its content (missing layers...).
        if (e.file().empty()) throw Error(e.kind(), e.message(), opt.input, e.where());
        throw;
    }
    const auto t2 = std::chrono::steady_clock::now();

    // The output frame: every input layer, the colour replaced inside the region.
    glint::FrameBuffers out = frame;
    const glint::Rect region = roi.value_or(bounds);
    glint::paste(out.color(), filtered, region.x0, region.y0);
    out.metadata().extra["denoiseFilter"] = std::string(filter.name());

    json report{{"input", opt.input},
                {"output", opt.output},
                {"filter", filter.name()},
                {"params", params},
                {"prefilter", opt.prefilter},
                {"width", frame.width()},
                {"height", frame.height()},
                {"prefilterSeconds", std::chrono::duration<double>(t1 - t0).count()},
                {"filterSeconds", std::chrono::duration<double>(t2 - t1).count()}};
    if (roi) report["roi"] = {roi->x0, roi->x1, roi->y0, roi->y1};
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
    glint::writeExr(out, opt.output);
    if (opt.json) {
        std::cout << report.dump(-1, ' ', false, json::error_handler_t::replace) << "\n";
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

int main(int argc, char** argv) {
    CLI::App app{"List Glint's denoising filters or apply one to a layered EXR.", "glint-denoise"};
    app.require_subcommand(1);

    bool listJson = false;
    CLI::App* listCmd = app.add_subcommand("list", "Every filter with its parameter table");
    listCmd->add_flag("--json", listJson, "Print JSON instead of text");

    ApplyOptions apply;
    CLI::App* applyCmd = app.add_subcommand("apply", "Filter the colour of a layered EXR");
    applyCmd->add_option("IN", apply.input, "Input layered EXR")->required();
    applyCmd->add_option("--filter", apply.filter, "Filter name (see `glint-denoise list`)")
        ->required();
    applyCmd->add_option("--param", apply.params, "Filter parameter name=value (repeatable)")
        ->take_all();
    applyCmd->add_flag("--prefilter", apply.prefilter,
                       "Prefilter the albedo/normal/depth layers first (written to OUT)");
    applyCmd->add_option("--prefilter-param", apply.prefilterParams,
                         "Prefilter parameter radius|sigmaSpatial|varianceScale=value");
    applyCmd->add_option("--roi", apply.roi,
                         "Filter only x0,x1,y0,y1 (half-open); the rest of OUT is the input");
    applyCmd->add_option("--out", apply.output, "Output layered EXR")->required();
    applyCmd->add_option("--reference", apply.reference,
                         "Reference EXR: print SSIM/PSNR/relMSE of input and output");
    applyCmd->add_flag("--json", apply.json, "Print one JSON object on stdout");

    if (const auto code = glint::cli::parseCommandLine(app, argc, argv, "glint-denoise"))
        return *code;
    return glint::cli::runGuarded("glint-denoise", [&] {
        if (*listCmd) runList(listJson);
        if (*applyCmd) runApply(apply);
        return 0;
    });
}

// Helpers shared by glint-denoise's subcommands (commands.h).
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <sstream>

#include "cli_boundary.h"
#include "commands.h"
#include "glint/denoise/auto.h"
#include "glint/denoise/bank.h"
#include "glint/denoise/external.h"
#include "glint/denoise/prefilter.h"
#include "glint/denoise/registry.h"
#include "glint/image/error.h"
#include "glint/image/io.h"
#include "glint/image/metrics.h"

namespace glint::denoise::cli {

using nlohmann::json;

double secondsSince(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

std::vector<std::string> splitList(const std::string& text) {
    std::vector<std::string> out;
    std::stringstream in(text);
    std::string item;
    while (std::getline(in, item, ','))
        if (!item.empty()) out.push_back(item);
    return out;
}

json memberJson(const FilterBank& bank, int m) {
    if (m < 0) return nullptr;
    const BankMember& b = bank.members()[std::size_t(m)];
    return {{"index", m},
            {"filter", b.filter},
            {"params", paramsJson(b.params)},
            {"default", b.isDefault}};
}

json paramsJson(const ParamValues& params) {
    json out = json::object();
    for (const auto& [name, value] : params) out[name] = value;
    for (const auto& [name, list] : params.strings) out[name] = list;
    return out;
}

// Splits "name=value"; `option` names the flag in the error.
std::pair<std::string, std::string> splitKeyValue(const std::string& text,
                                                  const std::string& option) {
    const auto eq = text.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == text.size())
        throw Error(ErrorKind::InvalidArgument,
                    "'" + text + "' is not of the form name=value (e.g. sigma=2.5)", {}, option);
    return {text.substr(0, eq), text.substr(eq + 1)};
}

namespace {

// Every "name=value" read against `specs`, unresolved (an unknown name is kept for
// resolveParams to name with the valid ones).
ParamValues readParamTexts(const std::vector<std::string>& given,
                           const std::vector<ParamSpec>& specs, const std::string& option) {
    ParamValues values;
    for (const std::string& text : given) {
        const auto [key, value] = splitKeyValue(text, option);
        const ParamSpec* spec = findParam(specs, key);
        if (!spec) {
            values[key] = 0.0;  // resolveParams names the valid parameters
            continue;
        }
        try {
            setParamFromText(*spec, value, values);
        } catch (const Error& e) {
            throw Error(e.kind(), e.message(), {}, option);
        }
    }
    return values;
}

}  // namespace

// Parses every "name=value" against `specs` (a choice takes an option name or its index) and
// resolves them; `owner` names the filter or the prefilter in errors.
ParamValues parseParams(const std::vector<std::string>& given, const std::vector<ParamSpec>& specs,
                        const std::string& owner, const std::string& option) {
    const ParamValues values = readParamTexts(given, specs, option);
    try {
        return resolveParams(specs, values, owner);
    } catch (const Error& e) {
        throw Error(e.kind(), e.message(), {}, option);
    }
}

ParamValues takePrefilterParams(std::vector<std::string>& given, bool prefilter,
                                const std::string& option) {
    static const std::string prefix = "prefilter.";
    std::vector<std::string> items;
    std::erase_if(given, [&](const std::string& text) {
        if (text.rfind(prefix, 0) != 0) return false;
        items.push_back(text.substr(prefix.size()));
        return true;
    });
    if (!items.empty() && !prefilter)
        throw Error(ErrorKind::InvalidArgument,
                    "'" + prefix + items.front() + "' given without --prefilter", {}, option);
    return parseParams(items, prefilterParams(), "feature prefilter", option);
}

std::map<std::string, ParamValues> parseFilterParams(const std::vector<std::string>& given,
                                                     const std::string& option) {
    // "FILTER.NAME=VALUE" grouped by filter as "NAME=VALUE".
    std::map<std::string, std::vector<std::string>> byFilter;
    for (const std::string& text : given) {
        const std::size_t dot = text.find('.'), eq = text.find('=');
        if (dot == std::string::npos || dot == 0 || (eq != std::string::npos && eq < dot))
            throw Error(ErrorKind::InvalidArgument,
                        "'" + text +
                            "' is not of the form filter.name=value (e.g. "
                            "external.command=[\"/opt/bin/tool\",\"{color}\",\"{output}\"])",
                        {}, option);
        byFilter[text.substr(0, dot)].push_back(text.substr(dot + 1));
    }
    std::map<std::string, ParamValues> fixed;
    for (const auto& [name, texts] : byFilter) {
        const Filter* filter = nullptr;
        try {
            filter = &findFilter(name);
        } catch (const Error& e) {
            throw Error(e.kind(), e.message(), {}, option);
        }
        ParamValues values = readParamTexts(texts, filter->params(), option);
        // Checked as the filter's parameters, kept as given: only these are fixed.
        try {
            resolveParams(*filter, values);
        } catch (const Error& e) {
            throw Error(e.kind(), e.where() + ": " + e.message(), {}, option);
        }
        fixed[name] = std::move(values);
    }
    return fixed;
}

int parseInteger(const std::string& text, const char* flag) {
    int value = 0;
    const char* end = text.data() + text.size();
    const auto [stop, ec] = std::from_chars(text.data(), end, value);
    if (ec == std::errc::result_out_of_range)
        throw Error(ErrorKind::InvalidArgument,
                    "'" + text + "' is far outside the accepted range (see --help)", {}, flag);
    if (text.empty() || ec != std::errc() || stop != end)
        throw Error(ErrorKind::InvalidArgument, "expected a decimal integer, got '" + text + "'",
                    {}, flag);
    return value;
}

std::optional<int> parseOptionalInteger(const std::string& text, const char* flag) {
    if (text.empty()) return std::nullopt;
    return parseInteger(text, flag);
}

double parseNumber(const std::string& text, const char* flag) {
    double value = 0.0;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (ec != std::errc() || end != text.data() + text.size())
        throw Error(ErrorKind::InvalidArgument, "'" + text + "' is not a number", {}, flag);
    return value;
}

void checkOutsideSessionFolder(const std::string& output, const char* outputFlag,
                               const std::string& session, const char* sessionFlag) {
    namespace fs = std::filesystem;
    if (output.empty() || session.empty()) return;
    const fs::path sessionPath(session);
    const fs::path side = sessionPath.parent_path() / sessionPath.stem();
    const fs::path outFolder =
        fs::path(output).parent_path().empty() ? fs::path(".") : fs::path(output).parent_path();
    std::error_code ec;
    if (fs::equivalent(outFolder, side, ec) && !ec)
        throw Error(ErrorKind::InvalidArgument,
                    "'" + output + "' lies in the side folder of the session given by " +
                        sessionFlag + " ('" + side.string() +
                        "'); writing there would replace the session's own files",
                    {}, outputFlag);
}

void checkOutputIsNoBankFile(const std::string& output, const char* outputFlag,
                             const std::string& bankDir) {
    namespace fs = std::filesystem;
    if (output.empty() || bankDir.empty()) return;
    std::error_code ec;
    for (const fs::directory_entry& entry : fs::directory_iterator(bankDir, ec))
        glint::cli::checkOutputIsNoInput(output, outputFlag, {{entry.path().string(), "--bank"}});
}

// Parses "x0,x1,y0,y1" (half-open pixel rectangle).
Rect parseRect(const std::string& text, const std::string& option) {
    std::vector<int> v;
    std::stringstream in(text);
    std::string item;
    while (std::getline(in, item, ',')) {
        char* end = nullptr;
        const long n = std::strtol(item.c_str(), &end, 10);
        if (item.empty() || *end != '\0' || n < 0 || n > 1 << 24)
            throw Error(ErrorKind::InvalidArgument,
                        "'" + text + "' is not x0,x1,y0,y1 (four integers in [0, 2^24])", {},
                        option);
        v.push_back(int(n));
    }
    if (v.size() != 4)
        throw Error(ErrorKind::InvalidArgument, "'" + text + "' is not x0,x1,y0,y1 (four integers)",
                    {}, option);
    return {v[0], v[1], v[2], v[3]};
}

std::string regionProblem(const Rect& r, int width, int height) {
    auto bound = [](const char* name, int v) {
        return std::string(name) + " = " + std::to_string(v);
    };
    const std::string size = std::to_string(width) + "x" + std::to_string(height);
    if (r.x1 <= r.x0)
        return bound("x1", r.x1) + " is not greater than " + bound("x0", r.x0) +
               ": the region is empty (x0,x1,y0,y1, half-open)";
    if (r.y1 <= r.y0)
        return bound("y1", r.y1) + " is not greater than " + bound("y0", r.y0) +
               ": the region is empty (x0,x1,y0,y1, half-open)";
    if (r.x1 > width)
        return bound("x1", r.x1) + " is past the width " + std::to_string(width) +
               ": the region lies outside the " + size + " image";
    if (r.y1 > height)
        return bound("y1", r.y1) + " is past the height " + std::to_string(height) +
               ": the region lies outside the " + size + " image";
    return "";
}

Rect parseRegion(const std::string& text, int width, int height, const std::string& file,
                 const std::string& option) {
    const Rect roi = parseRect(text, option);
    const std::string problem = regionProblem(roi, width, height);
    if (!problem.empty())
        throw Error(ErrorKind::InvalidArgument, "'" + text + "': " + problem, file, option);
    return roi;
}

json rectJson(const Rect& r) {
    return {r.x0, r.x1, r.y0, r.y1};
}

void writeChoiceMap(const Image& choice, std::size_t members, const std::string& path) {
    DisplayOptions d;
    d.falseColorChannel = 0;
    d.falseColorLo = 0.0f;
    d.falseColorHi = float(std::max<std::size_t>(members, 2) - 1);
    writePng(choice, path, d);
}

AutoOptions autoOptionsOfBank(const std::string& bankDir) {
    const BankOptions bankOptions = readBankOptions(bankDir);
    AutoOptions options;
    options.prefilter = bankOptions.prefilter;
    options.prefilterParams = bankOptions.prefilterParams;
    return options;
}

InputFrame readInput(const std::string& path) {
    FrameBuffers file = readExr(path);
    InputFrame in;
    in.note = renderOfNote(file, path);
    if (!in.note.empty()) in.shown = file.color();
    in.frame = renderOf(file);
    return in;
}

void sayInput(const InputFrame& input) {
    if (!input.note.empty()) std::fprintf(stderr, "glint-denoise: %s", input.note.c_str());
}

FrameBuffers readReference(const std::string& path, int width, int height) {
    FrameBuffers reference = readExr(path);
    if (reference.width() != width || reference.height() != height)
        throw Error(ErrorKind::InvalidArgument,
                    "reference is " + std::to_string(reference.width()) + "x" +
                        std::to_string(reference.height()) + ", the input " +
                        std::to_string(width) + "x" + std::to_string(height),
                    path);
    return reference;
}

json metricsOf(const Image& image, const Image& reference, const std::optional<Rect>& crop) {
    MetricOptions o;
    o.crop = crop;
    // SSIM needs its 11x11 window: null for a smaller region (a small --roi is fine otherwise).
    const Rect region = crop.value_or(image.bounds());
    const bool ssimFits = region.width() >= 11 && region.height() >= 11;
    return {{"ssim", ssimFits ? json(ssim(image, reference, o).value) : json(nullptr)},
            {"psnr", psnr(image, reference, o).value},
            {"relmse", relMse(image, reference, o).value}};
}

json describe(const std::vector<ParamSpec>& specs) {
    json params = json::array();
    for (const ParamSpec& s : specs) {
        json p{{"name", s.name},
               {"label", s.label},
               {"min", s.min},
               {"max", s.max},
               {"default", s.defaultValue},
               {"softMin", s.softMin},
               {"softMax", s.softMax},
               {"scale", s.scale == ParamScale::Log ? "log" : "linear"},
               {"integer", s.integer},
               {"help", s.help}};
        if (s.isChoice()) p["choices"] = s.choices;
        if (s.isStrings) {
            p["kind"] = "strings";
            p["defaultStrings"] = s.defaultStrings;
        }
        params.push_back(p);
    }
    return params;
}

json reportLeftOutFilters(const BankOptions& options) {
    json list = json::array();
    if (!options.filters.empty()) return list;
    std::vector<LeftOutFilter> leftOut;
    defaultBankFilters(&leftOut);
    for (const LeftOutFilter& f : leftOut) {
        std::fprintf(stderr, "glint-denoise: note: the bank goes on without '%s': %s\n",
                     f.name.c_str(), oneLine(f.reason).c_str());
        list.push_back({{"filter", f.name}, {"reason", f.reason}});
    }
    return list;
}

void printJson(const json& j) {
    std::cout << j.dump(-1, ' ', false, json::error_handler_t::replace) << "\n";
}

json reportUnavailableMembers(const FilterBank& bank, const std::string& source) {
    json list = json::array();
    for (const UnavailableMember& u : bank.unavailable()) {
        const std::string params =
            paramsSummary(findFilter(u.member.filter).params(), u.member.params);
        std::fprintf(stderr,
                     "glint-denoise: warning: %s: bank member %s (%s) is unavailable and left "
                     "out: %s\n",
                     source.c_str(), u.member.filter.c_str(), params.c_str(), u.reason.c_str());
        list.push_back({{"filter", u.member.filter},
                        {"params", paramsJson(u.member.params)},
                        {"reason", u.reason}});
    }
    return list;
}

void allowCommands(const std::vector<std::string>& given) {
    allowCommandsFromFile(allowedCommandsFile());
    for (const std::string& program : given) allowCommand(program);
}

}  // namespace glint::denoise::cli

// Helpers shared by glint-denoise's subcommands (commands.h).
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <sstream>

#include "commands.h"
#include "glint/denoise/bank.h"
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
    return {{"index", m}, {"filter", b.filter}, {"params", b.params}, {"default", b.isDefault}};
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

// Parses every "name=value" against `specs` (a choice takes an option name or its index) and
// resolves them; `owner` names the filter or the prefilter in errors.
ParamValues parseParams(const std::vector<std::string>& given, const std::vector<ParamSpec>& specs,
                        const std::string& owner, const std::string& option) {
    ParamValues values;
    for (const std::string& text : given) {
        const auto [key, value] = splitKeyValue(text, option);
        const ParamSpec* spec = findParam(specs, key);
        if (!spec) {
            values[key] = 0.0;  // resolveParams names the valid parameters
            continue;
        }
        try {
            values[key] = parseParamValue(*spec, value);
        } catch (const Error& e) {
            throw Error(e.kind(), e.message(), {}, option);
        }
    }
    try {
        return resolveParams(specs, values, owner);
    } catch (const Error& e) {
        throw Error(e.kind(), e.message(), {}, option);
    }
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

Rect parseRegion(const std::string& text, int width, int height, const std::string& file,
                 const std::string& option) {
    const Rect roi = parseRect(text, option);
    if (roi.empty() || intersect(roi, Rect{0, width, 0, height}) != roi)
        throw Error(ErrorKind::InvalidArgument,
                    "'" + text + "' is empty or outside the " + std::to_string(width) + "x" +
                        std::to_string(height) + " image (x0,x1,y0,y1, half-open)",
                    file, option);
    return roi;
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
        params.push_back(p);
    }
    return params;
}

void printJson(const json& j) {
    std::cout << j.dump(-1, ' ', false, json::error_handler_t::replace) << "\n";
}

}  // namespace glint::denoise::cli

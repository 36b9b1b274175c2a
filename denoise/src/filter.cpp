// Parameter parsing and resolution, and the checked entry point shared by every filter.
#include "glint/denoise/filter.h"

#include <tbb/task_arena.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <sstream>

#include "glint/image/error.h"

namespace glint::denoise {

namespace {

// "name [min, max] (integer)" or "name: a|b|c" for every parameter, for error messages.
std::string describeParams(const std::vector<ParamSpec>& specs) {
    std::ostringstream out;
    bool first = true;
    for (const ParamSpec& spec : specs) {
        out << (first ? "" : ", ") << spec.name;
        if (spec.isStrings) {
            out << " (list of strings)";
        } else if (spec.isChoice()) {
            out << " (";
            for (std::size_t i = 0; i < spec.choices.size(); ++i)
                out << (i ? "|" : "") << spec.choices[i];
            out << ")";
        } else {
            out << " [" << spec.min << ", " << spec.max << "]"
                << (spec.integer ? " (integer)" : "");
        }
        first = false;
    }
    if (first) out << "(none)";
    return out.str();
}

std::string optionList(const ParamSpec& spec) {
    std::string list;
    for (const std::string& c : spec.choices) list += (list.empty() ? "" : ", ") + c;
    return list;
}

}  // namespace

const ParamSpec* findParam(const std::vector<ParamSpec>& specs, std::string_view name) {
    for (const ParamSpec& spec : specs)
        if (spec.name == name) return &spec;
    return nullptr;
}

double parseParamValue(const ParamSpec& spec, const std::string& text) {
    if (spec.isChoice())
        for (std::size_t i = 0; i < spec.choices.size(); ++i)
            if (spec.choices[i] == text) return double(i);
    char* end = nullptr;
    const double v = text.empty() ? 0.0 : std::strtod(text.c_str(), &end);
    if (text.empty() || end == nullptr || *end != '\0') {
        if (spec.isChoice())
            throw Error(ErrorKind::InvalidArgument, "'" + text + "' is not an option of '" +
                                                        spec.name + "' (expected one of " +
                                                        optionList(spec) + ")");
        throw Error(ErrorKind::InvalidArgument,
                    "'" + text + "' is not a number (parameter '" + spec.name + "')");
    }
    // strtod reads "nan", "inf" and overflows (1e400) to infinity: none is a parameter value.
    if (!std::isfinite(v))
        throw Error(ErrorKind::InvalidArgument,
                    "'" + text + "' is not a finite number (parameter '" + spec.name + "')");
    return v;
}

std::string formatParamValue(const ParamSpec& spec, double value) {
    if (spec.isChoice() && value == std::floor(value) && value >= 0.0 &&
        value < double(spec.choices.size()))
        return spec.choices[std::size_t(value)];
    char text[64];
    std::snprintf(text, sizeof text, "%.9g", value);
    return text;
}

void setParamFromText(const ParamSpec& spec, const std::string& text, ParamValues& values) {
    if (!spec.isStrings) {
        values[spec.name] = parseParamValue(spec, text);
        return;
    }
    std::vector<std::string> list{text};
    if (!text.empty() && text.front() == '[') {
        const nlohmann::json array = nlohmann::json::parse(text, nullptr, false);
        if (!array.is_array())
            throw Error(ErrorKind::InvalidArgument,
                        "'" + text + "' is not a JSON array of strings (parameter '" + spec.name +
                            "', e.g. [\"/opt/bin/tool\", \"{color}\"])");
        list.clear();
        for (const auto& item : array) {
            if (!item.is_string())
                throw Error(ErrorKind::InvalidArgument, "item " + item.dump() + " of '" + text +
                                                            "' is not a string (parameter '" +
                                                            spec.name + "')");
            list.push_back(item.get<std::string>());
        }
    }
    values[spec.name] = 0.0;
    values.strings[spec.name] = std::move(list);
}

std::string formatParam(const ParamSpec& spec, const ParamValues& values) {
    if (!spec.isStrings) {
        const auto it = values.find(spec.name);
        return formatParamValue(spec, it == values.end() ? spec.defaultValue : it->second);
    }
    const auto it = values.strings.find(spec.name);
    return nlohmann::json(it == values.strings.end() ? spec.defaultStrings : it->second)
        .dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

namespace {

// `item` as one word of a POSIX shell: as it is when every byte is safe there (UTF-8 included),
// else in single quotes (a quote inside written '\'').
std::string shellWord(const std::string& item) {
    auto safe = [](unsigned char c) {
        return std::isalnum(c) || c >= 0x80 ||
               std::string_view("_@%+=:,./{}-").find(char(c)) != std::string_view::npos;
    };
    if (!item.empty() && std::all_of(item.begin(), item.end(), safe)) return item;
    std::string quoted = "'";
    for (char c : item) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return quoted + "'";
}

// A path item by its file name: "--in=/a/b/c.exr" -> "--in=…/c.exr"; other items unchanged.
std::string byFileName(const std::string& item) {
    const std::size_t slash = item.find('/'), last = item.rfind('/');
    if (slash == std::string::npos || last + 1 == item.size()) return item;
    const std::size_t eq = item.find('=');
    const std::size_t keep = eq != std::string::npos && eq < slash ? eq + 1 : 0;
    const std::string shorter = item.substr(0, keep) + "…/" + item.substr(last + 1);
    return shorter.size() < item.size() ? shorter : item;
}

// "[a b 'c d']": the items as shell words.
std::string bracketed(const std::vector<std::string>& items) {
    std::string text = "[";
    for (std::size_t i = 0; i < items.size(); ++i) text += (i ? " " : "") + shellWord(items[i]);
    return text + "]";
}

}  // namespace

std::string paramSummary(const ParamSpec& spec, const ParamValues& values, std::size_t maxChars) {
    if (!spec.isStrings) return formatParam(spec, values);
    const auto it = values.strings.find(spec.name);
    std::vector<std::string> items = it == values.strings.end() ? spec.defaultStrings : it->second;
    std::string text = bracketed(items);
    // The arguments' paths by their file names, from the last.
    for (std::size_t i = items.size(); i-- > 1 && text.size() > maxChars;) {
        items[i] = byFileName(items[i]);
        text = bracketed(items);
    }
    if (text.size() <= maxChars) return text;
    // Then the tail: whole items while they fit, and " …]"; the program's path by its file
    // name only when it alone does not fit.
    const std::string tail = " …]";
    if (!items.empty() && 1 + shellWord(items[0]).size() + tail.size() > maxChars)
        items[0] = byFileName(items[0]);
    std::string cut = "[";
    for (std::size_t i = 0; i < items.size(); ++i) {
        const std::string word = (i ? " " : "") + shellWord(items[i]);
        if (i > 0 && cut.size() + word.size() + tail.size() > maxChars) break;
        cut += word;
    }
    return cut + tail;
}

std::string paramsSummary(const std::vector<ParamSpec>& specs, const ParamValues& values) {
    std::string text;
    for (const ParamSpec& spec : specs)
        if (values.count(spec.name) || values.strings.count(spec.name))
            text += (text.empty() ? "" : " ") + spec.name + "=" + paramSummary(spec, values);
    return text;
}

ParamValues resolveParams(const std::vector<ParamSpec>& specs, const ParamValues& given,
                          const std::string& where) {
    // Reject names the owner does not know, and lists for numbers.
    for (const auto& [name, value] : given)
        if (!findParam(specs, name))
            throw Error(
                ErrorKind::InvalidArgument,
                "unknown parameter '" + name + "'; valid parameters: " + describeParams(specs), {},
                where);
    for (const auto& [name, list] : given.strings) {
        const ParamSpec* spec = findParam(specs, name);
        if (!spec || !spec->isStrings)
            throw Error(ErrorKind::InvalidArgument,
                        (spec ? "parameter '" + name + "' is a number, not a list of strings"
                              : "unknown parameter '" + name + "'") +
                            "; valid parameters: " + describeParams(specs),
                        {}, where);
    }
    // Fill in defaults and check the values given. A list of strings keeps the number 0 beside
    // its list, so that code reading numbers (sliders, the bank's sampler) treats it as fixed.
    ParamValues resolved;
    for (const ParamSpec& spec : specs) {
        if (spec.isStrings) {
            const auto it = given.strings.find(spec.name);
            resolved.strings[spec.name] =
                it == given.strings.end() ? spec.defaultStrings : it->second;
        }
        auto it = given.find(spec.name);
        const double value = it == given.end() ? spec.defaultValue : it->second;
        std::ostringstream range;
        if (spec.isChoice())
            range << "0 … " << spec.choices.size() - 1 << " (" << optionList(spec) << ")";
        else
            range << "[" << spec.min << ", " << spec.max << "]";
        if (std::isnan(value) || value < spec.min || value > spec.max)
            throw Error(ErrorKind::InvalidArgument,
                        "parameter '" + spec.name + "' = " + formatParamValue(spec, value) +
                            (std::isnan(value) ? " is not a number in its range "
                                               : " is outside its range ") +
                            range.str() + "; valid parameters: " + describeParams(specs),
                        {}, where);
        if (spec.integer && value != std::floor(value))
            throw Error(ErrorKind::InvalidArgument,
                        "parameter '" + spec.name + "' = " + formatParamValue(spec, value) +
                            " must be an integer in " + range.str(),
                        {}, where);
        resolved[spec.name] = value;
    }
    return resolved;
}

ParamValues resolveParams(const Filter& filter, const ParamValues& given) {
    return resolveParams(filter.params(), given, "filter '" + std::string(filter.name()) + "'");
}

Image applyFilter(const Filter& filter, const FrameBuffers& frame, const ParamValues& params,
                  const FilterOptions& options) {
    const std::string where = "filter '" + std::string(filter.name()) + "'";
    if (!frame.has(Layer::Color) || frame.width() <= 0 || frame.height() <= 0)
        throw Error(ErrorKind::InvalidArgument, "the frame has no colour layer or is empty", {},
                    where);
    if (options.threads < 0 || options.threads > 4096)
        throw Error(ErrorKind::InvalidArgument,
                    "threads = " + std::to_string(options.threads) + " must be in [0, 4096]", {},
                    where);
    const ParamValues resolved = resolveParams(filter, params);
    if (const std::string why = filter.unavailable(resolved); !why.empty())
        throw Error(ErrorKind::InvalidArgument, "unavailable: " + why, {}, where);
    // Check the feature layers the filter needs, naming every missing one.
    const std::vector<Layer> required = filter.requiredLayers(resolved);
    std::string missing, needed;
    for (Layer layer : required) {
        const std::string name(layerDisplayName(layer));
        needed += (needed.empty() ? "" : ", ") + name;
        if (!frame.has(layer)) missing += (missing.empty() ? "" : ", ") + name;
    }
    if (!missing.empty()) {
        std::string present;
        for (int l = 0; l < kLayerCount; ++l)
            if (frame.has(Layer(l)))
                present += (present.empty() ? "" : ", ") + std::string(layerDisplayName(Layer(l)));
        throw Error(ErrorKind::InvalidArgument,
                    "missing feature layer(s) " + missing + "; the filter needs " + needed +
                        " with these parameters; the frame has " + present,
                    {}, where);
    }
    const Rect bounds{0, frame.width(), 0, frame.height()};
    const Rect region = options.region.value_or(bounds);
    if (region.empty() || intersect(region, bounds) != region)
        throw Error(ErrorKind::InvalidArgument,
                    "region of interest x [" + std::to_string(region.x0) + ", " +
                        std::to_string(region.x1) + "), y [" + std::to_string(region.y0) + ", " +
                        std::to_string(region.y1) + ") is empty or outside the " +
                        std::to_string(frame.width()) + "x" + std::to_string(frame.height()) +
                        " frame",
                    {}, where);
    WorkContext work(options.progress);
    work.expectWork(region.height());
    auto run = [&] {
        Image out = filter.apply(frame, resolved, region, work);
        work.throwIfCancelled();
        GLINT_CHECK(
            out.width() == region.width() && out.height() == region.height() && out.channels() == 3,
            "a filter returned an image of the wrong size");
        work.finish();
        return out;
    };
    if (options.threads == 0) return run();
    tbb::task_arena arena(options.threads);
    return arena.execute(run);
}

}  // namespace glint::denoise

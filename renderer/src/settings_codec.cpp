#include "glint/render/settings_codec.h"

#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <sstream>
#include <vector>

#include <nlohmann/json.hpp>

#include "glint/image/error.h"
#include "settings_json.h"

namespace glint::render {

namespace {

using nlohmann::json;

// The most a Metropolis count may be (bootstrap paths, chains, groups).
constexpr std::int64_t kMaxMltCount = std::int64_t(1) << 40;
constexpr double kMaxMltWeight = 1e6;
// The least noiseThreshold the codec reads (0 and below are refused).
constexpr double kMinNoiseThreshold = 1e-9;

/// A named setting and how to reach its field: get gives the text, set takes a text the spec
/// has already checked.
struct NamedField {
    SettingSpec spec;
    std::string (*get)(const Settings&);
    void (*set)(Settings&, const std::string&);
};

std::string shortestReal(double v) {
    std::array<char, 32> buf{};
    const auto [end, ec] = std::to_chars(buf.data(), buf.data() + buf.size(), v);
    return std::string(buf.data(), end);
}

std::int64_t integerOf(const std::string& text) {
    return std::stoll(text);
}

const std::array<NamedField, 24>& namedFields() {
    using K = SettingKind;
    static const std::array<NamedField, 24> table{{
        {{"spp", K::Integer, 1, kMaxSpp, 0, 0, "", true, "samples per pixel"},
         [](const Settings& s) { return std::to_string(s.spp); },
         [](Settings& s, const std::string& t) { s.spp = int(integerOf(t)); }},
        {{"seed", K::Integer, 0, std::int64_t(kMaxSeed), 0, 0, "", true,
          "seed of the per-pixel random streams"},
         [](const Settings& s) { return std::to_string(s.seed); },
         [](Settings& s, const std::string& t) { s.seed = std::uint64_t(integerOf(t)); }},
        {{"integrator", K::Choice, 0, 0, 0, 0, "path mlt", true,
          "path tracer or Metropolis (docs/metropolis.md)"},
         [](const Settings& s) { return std::string(integratorName(s.integrator)); },
         [](Settings& s, const std::string& t) { s.integrator = parseIntegrator(t); }},
        {{"mis", K::Choice, 0, 0, 0, 0, "power balance none", true,
          "multiple importance sampling heuristic (power: beta = 2)"},
         [](const Settings& s) { return std::string(misName(s.mis)); },
         [](Settings& s, const std::string& t) { s.mis = parseMis(t); }},
        {{"strategy", K::Choice, 0, 0, 0, 0, "bsdf light", true,
          "the single strategy used with mis none"},
         [](const Settings& s) { return std::string(strategyName(s.strategy)); },
         [](Settings& s, const std::string& t) { s.strategy = parseStrategy(t); }},
        {{"sampler", K::Choice, 0, 0, 0, 0, "stratified independent sobol zsobol", true,
          "where a camera sample's random numbers come from"},
         [](const Settings& s) { return std::string(samplerName(s.sampler)); },
         [](Settings& s, const std::string& t) { s.sampler = parseSampler(t); }},
        {{"maxDepth", K::Integer, 1, kMaxDepth, 0, 0, "", true,
          "maximum number of bounces (1 = direct lighting only)"},
         [](const Settings& s) { return std::to_string(s.maxDepth); },
         [](Settings& s, const std::string& t) { s.maxDepth = int(integerOf(t)); }},
        {{"rrDepth", K::Integer, 0, kMaxDepth, 0, 0, "", true,
          "Russian roulette starts after this many bounces"},
         [](const Settings& s) { return std::to_string(s.rrDepth); },
         [](Settings& s, const std::string& t) { s.rrDepth = int(integerOf(t)); }},
        {{"halfBuffers", K::Boolean, 0, 0, 0, 0, "", true,
          "split the samples into two independent halves and also produce the half-buffer "
          "layers (an unbiased error estimate for auto)"},
         [](const Settings& s) { return std::string(s.halfBuffers ? "true" : "false"); },
         [](Settings& s, const std::string& t) { s.halfBuffers = t == "true"; }},
        {{"positionLayer", K::Boolean, 0, 0, 0, 0, "", false,
          "also write the world-space position layer"},
         [](const Settings& s) { return std::string(s.positionLayer ? "true" : "false"); },
         [](Settings& s, const std::string& t) { s.positionLayer = t == "true"; }},
        {{"textureCacheMb", K::Integer, 1, kMaxTextureCacheMb, 0, 0, "", false,
          "megabytes of texture tiles held in memory"},
         [](const Settings& s) { return std::to_string(s.textureCacheMb); },
         [](Settings& s, const std::string& t) { s.textureCacheMb = int(integerOf(t)); }},
        {{"accel", K::Choice, 0, 0, 0, 0, "auto triangles clusters", false,
          "what the BVH is built over (auto: clusters above 2^21 triangles)"},
         [](const Settings& s) { return std::string(accelName(s.accel)); },
         [](Settings& s, const std::string& t) { s.accel = parseAccel(t); }},
        {{"adaptive", K::Boolean, 0, 0, 0, 0, "", true,
          "adaptive sampling: after minSpp, samples only where the estimated error is above "
          "noiseThreshold, up to spp"},
         [](const Settings& s) { return std::string(s.adaptive ? "true" : "false"); },
         [](Settings& s, const std::string& t) { s.adaptive = t == "true"; }},
        {{"noiseThreshold", K::Real, 0, 0, kMinNoiseThreshold, kMaxNoiseThreshold, "", true,
          "adaptive: a pixel's estimated relative error below which it takes no more samples "
          "(Cycles' noise threshold)"},
         [](const Settings& s) { return shortestReal(s.noiseThreshold); },
         [](Settings& s, const std::string& t) { s.noiseThreshold = std::stod(t); }},
        {{"minSpp", K::Integer, 0, kMaxSpp, 0, 0, "", true,
          "adaptive: samples every pixel takes first (0: automatic, 64 at a threshold of 0.01)"},
         [](const Settings& s) { return std::to_string(s.minSpp); },
         [](Settings& s, const std::string& t) { s.minSpp = int(integerOf(t)); }},
        {{"adaptiveError", K::Choice, 0, 0, 0, 0, "half whole", true,
          "adaptive: estimate the error from the odd half of the samples (the even half stays "
          "unbiased) or from all of them"},
         [](const Settings& s) { return std::string(adaptiveErrorName(s.adaptiveError)); },
         [](Settings& s, const std::string& t) { s.adaptiveError = parseAdaptiveError(t); }},
        {{"mltLarge", K::Real, 0, 0, 0.0, kMaxMltWeight, "", true, "mlt: weight of large steps"},
         [](const Settings& s) { return shortestReal(s.mlt.largeStep); },
         [](Settings& s, const std::string& t) { s.mlt.largeStep = std::stod(t); }},
        {{"mltSmall", K::Real, 0, 0, 0.0, kMaxMltWeight, "", true, "mlt: weight of small steps"},
         [](const Settings& s) { return shortestReal(s.mlt.smallStep); },
         [](Settings& s, const std::string& t) { s.mlt.smallStep = std::stod(t); }},
        {{"mltLens", K::Real, 0, 0, 0.0, kMaxMltWeight, "", true,
          "mlt: weight of lens perturbations"},
         [](const Settings& s) { return shortestReal(s.mlt.lens); },
         [](Settings& s, const std::string& t) { s.mlt.lens = std::stod(t); }},
        {{"mltLight", K::Real, 0, 0, 0.0, kMaxMltWeight, "", true,
          "mlt: weight of light perturbations"},
         [](const Settings& s) { return shortestReal(s.mlt.light); },
         [](Settings& s, const std::string& t) { s.mlt.light = std::stod(t); }},
        {{"mltBootstrap", K::Integer, 1, kMaxMltCount, 0, 0, "", true, "mlt: bootstrap paths"},
         [](const Settings& s) { return std::to_string(s.mlt.bootstrap); },
         [](Settings& s, const std::string& t) { s.mlt.bootstrap = integerOf(t); }},
        {{"mltChains", K::Integer, 2, kMaxMltCount, 0, 0, "", true,
          "mlt: Markov chains (a multiple of mltGroups)"},
         [](const Settings& s) { return std::to_string(s.mlt.chains); },
         [](Settings& s, const std::string& t) { s.mlt.chains = int(integerOf(t)); }},
        {{"mltGroups", K::Integer, 2, kMaxMltCount, 0, 0, "", true,
          "mlt: batches of chains for the variance"},
         [](const Settings& s) { return std::to_string(s.mlt.groups); },
         [](Settings& s, const std::string& t) { s.mlt.groups = int(integerOf(t)); }},
        {{"mltFeatureSpp", K::Integer, 1, kMaxSpp, 0, 0, "", true,
          "mlt: spp of the path-traced pass that gives the feature layers"},
         [](const Settings& s) { return std::to_string(s.mlt.featureSpp); },
         [](Settings& s, const std::string& t) { s.mlt.featureSpp = int(integerOf(t)); }},
    }};
    return table;
}

const NamedField& namedField(const SettingSpec& spec) {
    for (const NamedField& f : namedFields())
        if (std::string_view(f.spec.name) == spec.name) return f;
    GLINT_CHECK(false, "a SettingSpec of settingSpecs()");
    return namedFields()[0];
}

/// A choice's names as a sentence: "\"auto\", \"triangles\" or \"clusters\"" (quoted, for JSON).
std::string choiceSentence(const SettingSpec& spec) {
    std::vector<std::string> names;
    std::istringstream in(spec.choices);
    for (std::string name; in >> name;) names.push_back("\"" + name + "\"");
    std::string out;
    for (std::size_t i = 0; i < names.size(); ++i)
        out += (i == 0 ? "" : i + 1 == names.size() ? " or " : ", ") + names[i];
    return out;
}

bool isMltSetting(const SettingSpec& spec) {
    return std::string_view(spec.name).starts_with("mlt");
}

/// The settings of adaptive sampling other than the switch itself.
bool isAdaptiveDetail(const SettingSpec& spec) {
    const std::string_view name = spec.name;
    return name == "noiseThreshold" || name == "minSpp" || name == "adaptiveError";
}

}  // namespace

std::span<const SettingSpec> settingSpecs() {
    static const std::vector<SettingSpec> specs = [] {
        std::vector<SettingSpec> out;
        for (const NamedField& f : namedFields()) out.push_back(f.spec);
        return out;
    }();
    return specs;
}

const SettingSpec* findSetting(std::string_view name) {
    for (const NamedField& f : namedFields())
        if (name == f.spec.name) return &f.spec;
    return nullptr;
}

std::string settingFlag(const SettingSpec& spec) {
    std::string flag = "--";
    for (const char* c = spec.name; *c; ++c) {
        if (std::isupper(static_cast<unsigned char>(*c)))
            flag += '-', flag += char(std::tolower(static_cast<unsigned char>(*c)));
        else
            flag += *c;
    }
    return flag;
}

SettingValues parseSettingAssignments(const std::vector<std::string>& items,
                                      const std::string& where) {
    SettingValues values;
    for (const std::string& item : items) {
        const std::size_t eq = item.find('=');
        const std::string name = item.substr(0, eq);
        if (eq == std::string::npos || !findSetting(name)) {
            std::string names;
            for (const SettingSpec& spec : settingSpecs())
                names += (names.empty() ? "" : ", ") + std::string(spec.name);
            throw Error(
                ErrorKind::InvalidArgument,
                "'" + item + "': expected name=value, the name a render setting (" + names + ")",
                "command line", where);
        }
        values[name] = item.substr(eq + 1);
    }
    return values;
}

std::string settingAssignmentsHelp(const std::string& keys) {
    return "a render setting name=value (repeatable), scene.json's render keys: " + keys +
           ", … (docs/scene-format.md)";
}

std::string settingText(const Settings& settings, const SettingSpec& spec) {
    return namedField(spec).get(settings);
}

void setSetting(Settings& settings, const SettingSpec& spec, std::string_view text,
                const std::string& file, const std::string& where) {
    auto bad = [&](const std::string& expected) {
        throw Error(ErrorKind::Format,
                    "expected " + expected + ", got \"" + std::string(text) + "\"", file, where);
    };
    const char* begin = text.data();
    const char* end = text.data() + text.size();
    switch (spec.kind) {
        case SettingKind::Integer: {
            // The whole text, in range: "1e12", " 4" and "-1" for a seed are refused, not read
            // in part or wrapped.
            std::int64_t v = 0;
            const auto [at, ec] = std::from_chars(begin, end, v);
            if (text.empty() || ec != std::errc() || at != end || v < spec.lo || v > spec.hi)
                bad("an integer in [" + std::to_string(spec.lo) + ", " + std::to_string(spec.hi) +
                    "]");
            break;
        }
        case SettingKind::Real: {
            double v = 0.0;
            const auto [at, ec] = std::from_chars(begin, end, v);
            if (text.empty() || ec != std::errc() || at != end || !std::isfinite(v) ||
                v < spec.min || v > spec.max) {
                std::ostringstream range;
                range << "a number in [" << spec.min << ", " << spec.max << "]";
                bad(range.str());
            }
            break;
        }
        case SettingKind::Boolean:
            if (text != "true" && text != "false") bad("true or false");
            break;
        case SettingKind::Choice:
            break;  // the field's parser names the choices
    }
    try {
        namedField(spec).set(settings, std::string(text));
    } catch (const Error& e) {
        throw Error(ErrorKind::Format, e.message(), file, where);
    }
}

SettingValues encodeSettings(const Settings& settings, const std::vector<std::string>& names) {
    SettingValues values;
    if (names.empty()) {
        for (const NamedField& f : namedFields()) values[f.spec.name] = f.get(settings);
        return values;
    }
    for (const std::string& name : names) {
        const SettingSpec* spec = findSetting(name);
        GLINT_CHECK(spec != nullptr);
        values[name] = settingText(settings, *spec);
    }
    return values;
}

Settings decodeSettings(const SettingValues& values, Settings settings, const std::string& file,
                        const std::string& pointer) {
    // In the table's order, so that the first bad value named is the same for any map.
    for (const NamedField& f : namedFields()) {
        const auto it = values.find(f.spec.name);
        if (it != values.end())
            setSetting(settings, f.spec, it->second, file, pointer + f.spec.name);
    }
    return settings;
}

std::string renderBlockJson(const Settings& settings) {
    json block = json::object();
    for (const NamedField& f : namedFields()) {
        const std::string text = f.get(settings);
        switch (f.spec.kind) {
            case SettingKind::Integer:
                block[f.spec.name] = integerOf(text);
                break;
            case SettingKind::Real:
                block[f.spec.name] = std::stod(text);
                break;
            case SettingKind::Boolean:
                block[f.spec.name] = text == "true";
                break;
            case SettingKind::Choice:
                block[f.spec.name] = text;
                break;
        }
    }
    return block.dump();
}

void recordSettings(const Settings& settings, FrameMetadata& metadata) {
    metadata.spp = settings.spp;
    metadata.seed = settings.seed;
    metadata.integrator = integratorName(settings.integrator);
    for (const NamedField& f : namedFields()) {
        const std::string_view name = f.spec.name;
        if (!f.spec.recorded || name == "spp" || name == "seed" || name == "integrator") continue;
        if (name == "strategy" && settings.mis != MisHeuristic::None) continue;
        if (isMltSetting(f.spec) && settings.integrator != Integrator::Mlt) continue;
        // A uniform render records nothing of adaptive sampling (its file stays as it was).
        if ((name == "adaptive" || isAdaptiveDetail(f.spec)) && !settings.adaptive) continue;
        metadata.extra[f.spec.name] = f.get(settings);
    }
}

Settings recordedSettings(const FrameMetadata& metadata, Settings settings,
                          const std::string& file) {
    if (metadata.spp > 0) settings.spp = metadata.spp;
    settings.seed = metadata.seed;
    if (metadata.integrator == "path" || metadata.integrator == "mlt")
        settings.integrator = parseIntegrator(metadata.integrator);
    for (const NamedField& f : namedFields()) {
        const std::string_view name = f.spec.name;
        if (name == "spp" || name == "seed" || name == "integrator") continue;
        const auto it = metadata.extra.find(f.spec.name);
        if (it != metadata.extra.end())
            setSetting(settings, f.spec, it->second, file, "glint:" + std::string(name));
    }
    return settings;
}

void readSettingsJson(const glint::JsonReader& reader, const json& block, const std::string& where,
                      Settings& settings) {
    std::vector<const char*> names;
    for (const NamedField& f : namedFields()) names.push_back(f.spec.name);
    reader.requireObject(block, where, names);
    for (const NamedField& f : namedFields()) {
        const auto it = block.find(f.spec.name);
        if (it == block.end()) continue;
        const std::string at = where + "/" + f.spec.name;
        // The JSON types: numbers, true/false, names; then the text the table reads.
        std::string text;
        switch (f.spec.kind) {
            case SettingKind::Integer:
                text = std::to_string(reader.integer(*it, at, f.spec.lo, f.spec.hi));
                break;
            case SettingKind::Real:
                text = shortestReal(reader.number(*it, at, f.spec.min, f.spec.max));
                break;
            case SettingKind::Boolean:
                text = reader.boolean(*it, at) ? "true" : "false";
                break;
            case SettingKind::Choice:
                if (!it->is_string())
                    reader.fail(
                        at, "expected " + choiceSentence(f.spec) + ", got " + describeJson(*it));
                text = it->get<std::string>();
                break;
        }
        setSetting(settings, f.spec, text, reader.file(), at);
    }
}

}  // namespace glint::render

#include "model/session_state.h"

#include <algorithm>
#include <charconv>
#include <cstdint>
#include <sstream>

#include "glint/image/error.h"
#include "model/document.h"

namespace glint::studio {

namespace {

constexpr const char* kLookPrefix = "look/";

std::string formatValue(const std::array<double, 3>& v) {
    std::ostringstream s;
    s.precision(17);
    s << v[0] << ' ' << v[1] << ' ' << v[2];
    return s.str();
}

bool parseValue(const std::string& text, std::array<double, 3>& v) {
    std::istringstream s(text);
    s >> v[0] >> v[1] >> v[2];
    return !s.fail();
}

const std::string* find(const std::map<std::string, std::string>& state, const char* key) {
    auto it = state.find(key);
    return it == state.end() ? nullptr : &it->second;
}

}  // namespace

std::string lookKey(const std::string& item, const std::string& property) {
    return kLookPrefix + item + "/" + property;
}

void writeDocumentState(const std::vector<render::LookItem>& look, const render::Settings& settings,
                        std::map<std::string, std::string>& state) {
    for (const render::LookItem& item : look)
        for (const render::LookProperty& p : item.properties)
            state[lookKey(item.name, p.name)] = formatValue(p.value);
    state["spp"] = std::to_string(settings.spp);
    state["seed"] = std::to_string(settings.seed);
    state["integrator"] = render::integratorName(settings.integrator);
    state["mis"] = render::misName(settings.mis);
    state["halves"] = settings.halfBuffers ? "1" : "0";
}

render::Settings readSettings(const std::map<std::string, std::string>& state,
                              render::Settings settings, const std::string& file,
                              const std::string& pointer) {
    // Strictly, with the renderer's limits (render::validate): a bad value is an error naming
    // the file and the key, never a value quietly made up from part of the text.
    auto bad = [&](const char* key, const std::string& expected, const std::string& text) {
        throw Error(ErrorKind::Format, "expected " + expected + ", got \"" + text + "\"", file,
                    pointer + key);
    };
    auto integer = [&](const char* key, const std::string& text, std::uint64_t lo,
                       std::uint64_t hi) {
        std::uint64_t v = 0;
        const char* end = text.data() + text.size();
        const auto [at, ec] = std::from_chars(text.data(), end, v);
        if (ec != std::errc() || at != end || v < lo || v > hi)
            bad(key, "an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]",
                text);
        return v;
    };
    if (const std::string* v = find(state, "spp"))
        settings.spp = int(integer("spp", *v, 1, std::uint64_t(render::kMaxSpp)));
    if (const std::string* v = find(state, "seed"))
        settings.seed = integer("seed", *v, 0, render::kMaxSeed);
    if (const std::string* v = find(state, "integrator")) {
        if (*v != "path" && *v != "mlt") bad("integrator", "path or mlt", *v);
        settings.integrator = render::parseIntegrator(*v);
    }
    if (const std::string* v = find(state, "mis")) {
        if (*v != "power" && *v != "balance" && *v != "none")
            bad("mis", "power, balance or none", *v);
        settings.mis = render::parseMis(*v);
    }
    if (const std::string* v = find(state, "halves")) {
        if (*v != "0" && *v != "1") bad("halves", "0 or 1", *v);
        settings.halfBuffers = *v == "1";
    }
    return settings;
}

std::vector<render::LookItem> readLook(const std::map<std::string, std::string>& state,
                                       std::vector<render::LookItem> look) {
    for (render::LookItem& item : look)
        for (render::LookProperty& p : item.properties) {
            const auto it = state.find(lookKey(item.name, p.name));
            std::array<double, 3> value{};
            if (it != state.end() && parseValue(it->second, value)) p.value = value;
        }
    return look;
}

std::string applyLook(const std::map<std::string, std::string>& state, Document& document) {
    std::string skipped;
    // Only the properties the scene has: a key of another scene is ignored.
    for (const render::LookItem& item : std::vector<render::LookItem>(document.look()))
        for (const render::LookProperty& p : item.properties) {
            const auto it = state.find(lookKey(item.name, p.name));
            if (it == state.end()) continue;
            std::array<double, 3> value{};
            if (!parseValue(it->second, value)) {
                skipped += (skipped.empty() ? "" : ", ") + item.name + "/" + p.name;
                continue;
            }
            if (value == p.value) continue;
            try {
                document.setLook(item.name, p.name, value, false);
            } catch (const Error&) {
                skipped += (skipped.empty() ? "" : ", ") + item.name + "/" + p.name;
            }
        }
    return skipped;
}

}  // namespace glint::studio

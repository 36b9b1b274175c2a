#include "model/session_state.h"

#include <algorithm>
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
                              render::Settings settings) {
    // Each key on its own: one unreadable value does not lose the others.
    auto attempt = [](auto&& fn) {
        try {
            fn();
        } catch (const std::exception&) {
        }
    };
    if (const std::string* v = find(state, "spp"))
        attempt([&] { settings.spp = std::clamp(std::stoi(*v), 1, render::kMaxSpp); });
    if (const std::string* v = find(state, "seed"))
        attempt(
            [&] { settings.seed = std::min<std::uint64_t>(std::stoull(*v), render::kMaxSeed); });
    if (const std::string* v = find(state, "integrator"))
        attempt([&] { settings.integrator = render::parseIntegrator(*v); });
    if (const std::string* v = find(state, "mis"))
        attempt([&] { settings.mis = render::parseMis(*v); });
    if (const std::string* v = find(state, "halves")) settings.halfBuffers = *v == "1";
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

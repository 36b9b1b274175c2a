#include "model/session_state.h"

#include <algorithm>
#include <sstream>

#include "glint/image/error.h"
#include "glint/render/settings_codec.h"
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

const std::vector<std::string>& userSettingNames() {
    static const std::vector<std::string> names = {"spp", "seed", "integrator", "mis",
                                                   "halfBuffers"};
    return names;
}

std::string lookKey(const std::string& item, const std::string& property) {
    return kLookPrefix + item + "/" + property;
}

void writeDocumentState(const std::vector<render::LookItem>& look, const render::Settings& settings,
                        std::map<std::string, std::string>& state) {
    for (const render::LookItem& item : look)
        for (const render::LookProperty& p : item.properties)
            state[lookKey(item.name, p.name)] = formatValue(p.value);
    for (const auto& [name, value] : render::encodeSettings(settings, userSettingNames()))
        state[name] = value;
}

render::Settings readSettings(const std::map<std::string, std::string>& state,
                              render::Settings settings, const std::string& file,
                              const std::string& pointer) {
    // Strictly, with the renderer's limits (the settings codec): a bad value is an error naming
    // the file and the key, never a value quietly made up from part of the text.
    render::SettingValues values;
    for (const std::string& name : userSettingNames())
        if (const std::string* v = find(state, name.c_str())) values[name] = *v;
    // Sessions and journals written before the codec kept half buffers as "halves": "0" / "1".
    const std::string* halves = find(state, "halves");
    if (halves && !values.count("halfBuffers")) {
        if (*halves != "0" && *halves != "1")
            throw Error(ErrorKind::Format, "expected 0 or 1, got \"" + *halves + "\"", file,
                        pointer + "halves");
        values["halfBuffers"] = *halves == "1" ? "true" : "false";
    }
    return render::decodeSettings(values, settings, file, pointer);
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

#include "json_reader.h"

#include <vector>

namespace glint::denoise::detail {

using nlohmann::json;

ParamValues JsonReader::params(const json& value, const std::string& where) const {
    if (!value.is_object()) fail(where, "expected an object of parameters");
    ParamValues params;
    for (const auto& item : value.items()) {
        const std::string at = where + "/" + item.key();
        if (!item.value().is_array()) {
            params[item.key()] = number(item.value(), at, -1e30, 1e30);
            continue;
        }
        std::vector<std::string> list;
        for (std::size_t i = 0; i < item.value().size(); ++i)
            list.push_back(string(item.value()[i], at + "/" + std::to_string(i)));
        params[item.key()] = 0.0;
        params.strings[item.key()] = std::move(list);
    }
    return params;
}

json paramsJson(const ParamValues& params) {
    json out = json::object();
    for (const auto& [name, value] : params) out[name] = value;
    for (const auto& [name, list] : params.strings) out[name] = list;
    return out;
}

}  // namespace glint::denoise::detail

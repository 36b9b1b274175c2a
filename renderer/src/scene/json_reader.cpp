#include "scene/json_reader.h"

namespace glint::render::detail {

Vec3 JsonReader::vec3(const nlohmann::json& value, const std::string& where, double lo,
                      double hi) const {
    if (!value.is_array() || value.size() != 3)
        fail(where, "expected an array of 3 numbers, got " + describeJson(value));
    Vec3 v;
    for (int i = 0; i < 3; ++i) v[i] = number(value[i], where + "/" + std::to_string(i), lo, hi);
    return v;
}

}  // namespace glint::render::detail

#include "scene/json_reader.h"

#include <climits>
#include <cmath>
#include <sstream>

#include "glint/image/error.h"

namespace glint::render::detail {

namespace {
std::string describe(const nlohmann::json& value) {
    std::string text = value.dump();
    if (text.size() > 40) text = text.substr(0, 37) + "...";
    return text;
}
}  // namespace

void JsonReader::fail(const std::string& where, const std::string& message) const {
    throw Error(ErrorKind::Format, message, m_file.string(), where.empty() ? "/" : where);
}

void JsonReader::requireObject(const nlohmann::json& value, const std::string& where,
                               std::initializer_list<const char*> allowed) const {
    if (!value.is_object()) fail(where, "expected an object, got " + describe(value));
    for (const auto& item : value.items()) {
        bool known = false;
        for (const char* key : allowed) known = known || item.key() == key;
        if (known) continue;
        std::ostringstream list;
        const char* sep = "";
        for (const char* key : allowed) list << sep << key, sep = ", ";
        fail(where + "/" + item.key(),
             "unknown key '" + item.key() + "' (expected one of: " + list.str() + ")");
    }
}

float JsonReader::number(const nlohmann::json& value, const std::string& where, double lo,
                         double hi) const {
    if (!value.is_number()) fail(where, "expected a number, got " + describe(value));
    const double v = value.get<double>();
    if (!std::isfinite(v) || v < lo || v > hi) {
        std::ostringstream msg;
        msg << "expected a number in [" << lo << ", " << hi << "], got " << describe(value);
        fail(where, msg.str());
    }
    return float(v);
}

long long JsonReader::integer(const nlohmann::json& value, const std::string& where, long long lo,
                              long long hi) const {
    if (!value.is_number_integer()) fail(where, "expected an integer, got " + describe(value));
    // An unsigned value beyond long long (e.g. 2^64 - 1) is reported as written, not wrapped.
    const bool huge = value.is_number_unsigned() &&
                      value.get<unsigned long long>() > (unsigned long long)LLONG_MAX;
    const long long v = huge ? LLONG_MAX : value.get<long long>();
    if (huge || v < lo || v > hi) {
        std::ostringstream msg;
        msg << "expected an integer in [" << lo << ", " << hi << "], got ";
        if (huge)
            msg << value.get<unsigned long long>();
        else
            msg << v;
        fail(where, msg.str());
    }
    return v;
}

std::string JsonReader::string(const nlohmann::json& value, const std::string& where) const {
    if (!value.is_string()) fail(where, "expected a string, got " + describe(value));
    return value.get<std::string>();
}

Vec3 JsonReader::vec3(const nlohmann::json& value, const std::string& where, double lo,
                      double hi) const {
    if (!value.is_array() || value.size() != 3)
        fail(where, "expected an array of 3 numbers, got " + describe(value));
    Vec3 v;
    for (int i = 0; i < 3; ++i) v[i] = number(value[i], where + "/" + std::to_string(i), lo, hi);
    return v;
}

}  // namespace glint::render::detail

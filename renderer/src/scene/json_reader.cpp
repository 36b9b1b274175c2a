#include "scene/json_reader.h"

#include <algorithm>
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

void throwMalformedJson(const nlohmann::json::exception& e, std::string_view text,
                        const std::string& file, const std::string& within) {
    // Turn the byte offset into a line and column. A number the parser cannot hold
    // (-1e400: out_of_range) has no offset; its text, quoted in the message, is found.
    std::string msg = e.what();
    std::size_t byte = 0;
    if (const auto* pe = dynamic_cast<const nlohmann::json::parse_error*>(&e)) {
        byte = pe->byte;
    } else {
        const auto q0 = msg.find('\''), q1 = msg.rfind('\'');
        if (q0 != std::string::npos && q1 > q0) {
            const auto at = text.find(msg.substr(q0 + 1, q1 - q0 - 1));
            if (at != std::string::npos) byte = at + 1;
        }
    }
    byte = std::min<std::size_t>(byte, text.size());
    int line = 1, column = 1;
    for (std::size_t i = 0; i + 1 < byte; ++i) {
        if (text[i] == '\n')
            ++line, column = 1;
        else
            ++column;
    }
    // Drop nlohmann's "[json.exception.x.n] parse error at line 1, column 2: " prefix.
    const auto bracket = msg.find("] ");
    if (bracket != std::string::npos) msg = msg.substr(bracket + 2);
    const auto colon = msg.find(": ", msg.find("parse error"));
    if (msg.rfind("parse error", 0) == 0 && colon != std::string::npos) msg = msg.substr(colon + 2);
    throw Error(ErrorKind::Format, "malformed JSON: " + msg, file,
                "line " + std::to_string(line) + ", column " + std::to_string(column) + within);
}

void JsonReader::fail(const std::string& where, const std::string& message) const {
    throw Error(ErrorKind::Format, message, m_file.string(), where.empty() ? "/" : where);
}

void JsonReader::requireObject(const nlohmann::json& value, const std::string& where,
                               std::initializer_list<const char*> allowed) const {
    requireObject(value, where, std::vector<std::string>(allowed.begin(), allowed.end()));
}

void JsonReader::requireObject(const nlohmann::json& value, const std::string& where,
                               const std::vector<std::string>& allowed) const {
    if (!value.is_object()) fail(where, "expected an object, got " + describe(value));
    for (const auto& item : value.items()) {
        bool known = false;
        for (const std::string& key : allowed) known = known || item.key() == key;
        if (known) continue;
        std::ostringstream list;
        const char* sep = "";
        for (const std::string& key : allowed) list << sep << key, sep = ", ";
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

#include "glint/image/internal/json_reader.h"

#include <sys/stat.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "glint/image/error.h"

namespace glint {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// "line L, column C" of the 1-based byte offset `byte` of `text` (1, 1 for offset 0).
std::string lineAndColumn(std::string_view text, std::size_t byte) {
    byte = std::min(byte, text.size());
    int line = 1, column = 1;
    for (std::size_t i = 0; i + 1 < byte; ++i) {
        if (text[i] == '\n')
            ++line, column = 1;
        else
            ++column;
    }
    return "line " + std::to_string(line) + ", column " + std::to_string(column);
}

}  // namespace

std::string readJsonText(const fs::path& path, const std::string& what) {
    const std::string file = path.string();
    // stat, not std::filesystem: a name the file system refuses (too long) is "missing" here too.
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0) throw Error(ErrorKind::Io, what + " not found", file);
    if (S_ISDIR(st.st_mode))
        throw Error(ErrorKind::Io, "is a folder, expected a " + what + " (a JSON file)", file);
    if (!S_ISREG(st.st_mode))
        throw Error(ErrorKind::Io,
                    "is not a regular file (a device, pipe or socket), expected a " + what, file);
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(ErrorKind::Io, "cannot read the " + what, file);
    std::ostringstream text;
    text << in.rdbuf();
    if (in.bad()) throw Error(ErrorKind::Io, "cannot read the " + what, file);
    return text.str();
}

void throwMalformedJson(const json::exception& e, std::string_view text, const std::string& file,
                        const std::string& within) {
    // The byte offset of the fault. A number the parser cannot hold (-1e400: out_of_range) has
    // none; its text, quoted in the message, is found in the document.
    std::string msg = e.what();
    std::size_t byte = 0;
    if (const auto* pe = dynamic_cast<const json::parse_error*>(&e)) {
        byte = pe->byte;
    } else {
        const auto q0 = msg.find('\''), q1 = msg.rfind('\'');
        if (q0 != std::string::npos && q1 > q0) {
            const auto at = text.find(msg.substr(q0 + 1, q1 - q0 - 1));
            if (at != std::string_view::npos) byte = at + 1;
        }
    }
    // Drop nlohmann's "[json.exception.x.n] parse error at line 1, column 2: " prefix.
    const auto bracket = msg.find("] ");
    if (bracket != std::string::npos) msg = msg.substr(bracket + 2);
    const auto colon = msg.find(": ", msg.find("parse error"));
    if (msg.rfind("parse error", 0) == 0 && colon != std::string::npos) msg = msg.substr(colon + 2);
    throw Error(ErrorKind::Format, "malformed JSON: " + msg, file,
                lineAndColumn(text, byte) + within);
}

json parseJsonText(std::string_view text, const std::string& file, const std::string& within) {
    try {
        return json::parse(text);
    } catch (const json::exception& e) {
        throwMalformedJson(e, text, file, within);
    }
}

std::string describeJson(const json& value) {
    std::string text = value.dump(-1, ' ', false, json::error_handler_t::replace);
    if (text.size() > 40) text = text.substr(0, 37) + "...";
    return text;
}

void JsonReader::fail(const std::string& where, const std::string& message) const {
    throw Error(ErrorKind::Format, message, m_file, where.empty() ? "/" : where);
}

void JsonReader::requireObject(const json& value, const std::string& where,
                               std::span<const char* const> allowed) const {
    if (!value.is_object()) fail(where, "expected an object, got " + describeJson(value));
    for (const auto& item : value.items()) {
        bool known = false;
        for (const char* key : allowed) known = known || item.key() == key;
        if (known) continue;
        std::string list;
        for (const char* key : allowed) list += (list.empty() ? "" : ", ") + std::string(key);
        fail(where + "/" + item.key(),
             "unknown key '" + item.key() + "' (expected one of: " + list + ")");
    }
}

void JsonReader::requireObject(const json& value, const std::string& where,
                               const std::vector<std::string>& allowed) const {
    std::vector<const char*> keys;
    keys.reserve(allowed.size());
    for (const std::string& key : allowed) keys.push_back(key.c_str());
    requireObject(value, where, std::span<const char* const>(keys.data(), keys.size()));
}

const json& JsonReader::at(const json& object, const std::string& key,
                           const std::string& where) const {
    if (!object.is_object()) fail(where, "expected an object, got " + describeJson(object));
    const auto it = object.find(key);
    if (it == object.end()) fail(where + "/" + key, "missing required key '" + key + "'");
    return *it;
}

double JsonReader::number(const json& value, const std::string& where, double lo, double hi) const {
    if (!value.is_number()) fail(where, "expected a number, got " + describeJson(value));
    const double v = value.get<double>();
    if (!std::isfinite(v) || v < lo || v > hi) {
        std::ostringstream msg;
        msg << "expected a number in [" << lo << ", " << hi << "], got " << describeJson(value);
        fail(where, msg.str());
    }
    return v;
}

std::int64_t JsonReader::integer(const json& value, const std::string& where, std::int64_t lo,
                                 std::int64_t hi) const {
    const std::string range = "[" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
    if (!value.is_number_integer())
        fail(where, "expected an integer in " + range + ", got " + describeJson(value));
    // The parser keeps non-negative integers unsigned; one above INT64_MAX is in no range here.
    bool ok = false;
    if (value.is_number_unsigned()) {
        const std::uint64_t u = value.get<std::uint64_t>();
        ok = u <= std::uint64_t(INT64_MAX) && std::int64_t(u) >= lo && std::int64_t(u) <= hi;
    } else {
        const std::int64_t v = value.get<std::int64_t>();
        ok = v >= lo && v <= hi;
    }
    if (!ok) fail(where, "expected an integer in " + range + ", got " + describeJson(value));
    return value.get<std::int64_t>();
}

std::uint64_t JsonReader::unsignedInteger(const json& value, const std::string& where,
                                          std::uint64_t hi) const {
    if (!value.is_number_unsigned() || value.get<std::uint64_t>() > hi)
        fail(where,
             "expected an integer in [0, " + std::to_string(hi) + "], got " + describeJson(value));
    return value.get<std::uint64_t>();
}

std::string JsonReader::string(const json& value, const std::string& where) const {
    if (!value.is_string()) fail(where, "expected a string, got " + describeJson(value));
    return value.get<std::string>();
}

bool JsonReader::boolean(const json& value, const std::string& where) const {
    if (!value.is_boolean()) fail(where, "expected true or false, got " + describeJson(value));
    return value.get<bool>();
}

const json& JsonReader::array(const json& value, const std::string& where, std::size_t size) const {
    if (!value.is_array() || (size > 0 && value.size() != size))
        fail(where, (size > 0 ? "expected an array of " + std::to_string(size) + " values"
                              : std::string("expected an array")) +
                        ", got " + describeJson(value));
    return value;
}

}  // namespace glint

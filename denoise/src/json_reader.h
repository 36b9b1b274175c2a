// Reading the JSON files of the denoise module that people write or edit (paint scripts,
// session files, bank indexes): every error is one glint::Error(Format) naming the file and the
// place, a line and column for malformed text or the JSON pointer of the offending value.
#pragma once

#include <cstdint>
#include <filesystem>
#include <initializer_list>
#include <string>

#include <nlohmann/json.hpp>

#include "glint/denoise/filter.h"

namespace glint::denoise::detail {

/// The text of the JSON file `path`, described as `what` ("paint script", "session file") in
/// errors. Throws glint::Error(Io) for a folder, something that is not a regular file (a device,
/// a pipe), a missing or an unreadable file — each said as such.
std::string readJsonText(const std::filesystem::path& path, const std::string& what);

/// Parses JSON text. Throws glint::Error(Format) naming `file` and "line L, column C": malformed
/// or truncated text, and numbers JSON cannot hold as a double (1e400: "number overflow").
nlohmann::json parseJsonText(const std::string& text, const std::string& file);

/// Typed, checked access to the values of a parsed document: errors name the file and the JSON
/// pointer of the value ("/" for the root).
class JsonReader {
  public:
    explicit JsonReader(std::string file) : m_file(std::move(file)) {}
    const std::string& file() const { return m_file; }

    /// Throws glint::Error(Format) at `where`.
    [[noreturn]] void fail(const std::string& where, const std::string& message) const;
    /// `value` must be an object whose keys are all in `allowed` (an unknown key, such as a
    /// misspelt one, is named with its pointer and the keys expected there).
    void requireObject(const nlohmann::json& value, const std::string& where,
                       std::initializer_list<const char*> allowed) const;
    /// The member `key` of the object `object` (at `where`); an error names it when missing.
    const nlohmann::json& at(const nlohmann::json& object, const std::string& key,
                             const std::string& where) const;
    /// A finite number in [lo, hi].
    double number(const nlohmann::json& value, const std::string& where, double lo,
                  double hi) const;
    /// An integer in [lo, hi] (a number with a fraction, or 1e3 written as a float, is not one).
    std::int64_t integer(const nlohmann::json& value, const std::string& where, std::int64_t lo,
                         std::int64_t hi) const;
    /// An unsigned integer in [0, hi].
    std::uint64_t unsignedInteger(const nlohmann::json& value, const std::string& where,
                                  std::uint64_t hi) const;
    std::string string(const nlohmann::json& value, const std::string& where) const;
    bool boolean(const nlohmann::json& value, const std::string& where) const;
    /// A parameter block ({"name": number or list of strings}); the names and kinds are checked
    /// by resolveParams.
    ParamValues params(const nlohmann::json& value, const std::string& where) const;
    /// An array (of any length when `size` is 0, else of exactly `size` elements).
    const nlohmann::json& array(const nlohmann::json& value, const std::string& where,
                                std::size_t size = 0) const;

  private:
    std::string m_file;
};

/// Parameter values as one JSON object: numbers, and lists of strings as arrays.
nlohmann::json paramsJson(const ParamValues& params);

/// Short text of a JSON value for messages (at most ~40 characters).
std::string describeJson(const nlohmann::json& value);

}  // namespace glint::denoise::detail

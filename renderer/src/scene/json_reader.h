// Checked access to scene.json values: every error names the file and the JSON path.
#pragma once

#include <filesystem>
#include <initializer_list>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "vecmath.h"

namespace glint::render::detail {

/// Throws the glint::Error(Format) for nlohmann-json's exception `e` on `text`: "malformed
/// JSON: what" at "line L, column C" (`within` appended to the place, e.g. " of the JSON chunk");
/// a number the parser cannot hold (1e400), which nlohmann reports without an offset, is found
/// by its text.
[[noreturn]] void throwMalformedJson(const nlohmann::json::exception& e, std::string_view text,
                                     const std::string& file, const std::string& within = "");

/// Reads typed values out of a parsed JSON document, throwing glint::Error(Format) with
/// file = the scene file and where = the JSON pointer of the offending value.
class JsonReader {
  public:
    explicit JsonReader(std::filesystem::path file) : m_file(std::move(file)) {}

    const std::filesystem::path& file() const { return m_file; }

    /// Throws Error(Format) at `where`.
    [[noreturn]] void fail(const std::string& where, const std::string& message) const;
    /// The value must be an object whose keys are all in `allowed`.
    void requireObject(const nlohmann::json& value, const std::string& where,
                       std::initializer_list<const char*> allowed) const;
    /// The same with a list made at run time (a shape's keys, from the asset formats).
    void requireObject(const nlohmann::json& value, const std::string& where,
                       const std::vector<std::string>& allowed) const;
    /// A finite number in [lo, hi].
    float number(const nlohmann::json& value, const std::string& where, double lo, double hi) const;
    /// An integer in [lo, hi].
    long long integer(const nlohmann::json& value, const std::string& where, long long lo,
                      long long hi) const;
    /// A string.
    std::string string(const nlohmann::json& value, const std::string& where) const;
    /// An array of three finite numbers, each in [lo, hi].
    Vec3 vec3(const nlohmann::json& value, const std::string& where, double lo = -1e30,
              double hi = 1e30) const;

  private:
    std::filesystem::path m_file;
};

}  // namespace glint::render::detail

// Reading the JSON files people write or edit (scene.json, glTF documents, paint scripts,
// session files, bank indexes): every error is one glint::Error(Format) naming the file and the
// place — "line L, column C" for malformed text, the JSON pointer of the offending value
// otherwise. Internal to Glint: the renderer and the denoiser build on it (image/CMakeLists.txt,
// glint_image_internal); never installed, since it speaks nlohmann-json.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <initializer_list>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

namespace glint {

/// The text of the JSON file `path`, described as `what` ("paint script", "session file") in
/// errors. Throws glint::Error(Io) for a folder, something that is not a regular file (a device,
/// a pipe), a missing or an unreadable file — each said as such.
std::string readJsonText(const std::filesystem::path& path, const std::string& what);

/// Throws the glint::Error(Format) for nlohmann-json's exception `e` on `text`: "malformed JSON:
/// what" at "line L, column C" (`within` appended to the place, e.g. " of the JSON chunk"). A
/// number the parser cannot hold (1e400, "number overflow"), which nlohmann reports without an
/// offset, is found by its text.
[[noreturn]] void throwMalformedJson(const nlohmann::json::exception& e, std::string_view text,
                                     const std::string& file, const std::string& within = "");

/// Parses JSON text; malformed or truncated text throws as throwMalformedJson says.
nlohmann::json parseJsonText(std::string_view text, const std::string& file,
                             const std::string& within = "");

/// Short text of a JSON value for messages (at most ~40 characters).
std::string describeJson(const nlohmann::json& value);

/// Typed, checked access to the values of a parsed document: errors name the file and the JSON
/// pointer of the value ("/" for the root). A module adds what only it reads (the renderer's
/// vectors, the denoiser's parameter blocks) in a class of its own derived from this one.
class JsonReader {
  public:
    explicit JsonReader(std::string file) : m_file(std::move(file)) {}
    const std::string& file() const { return m_file; }

    /// Throws glint::Error(Format) at `where`.
    [[noreturn]] void fail(const std::string& where, const std::string& message) const;
    /// `value` must be an object whose keys are all in `allowed` (an unknown key, such as a
    /// misspelt one, is named with its pointer and the keys expected there).
    void requireObject(const nlohmann::json& value, const std::string& where,
                       std::initializer_list<const char*> allowed) const {
        requireObject(value, where, std::span<const char* const>(allowed.begin(), allowed.size()));
    }
    /// The same, the keys from a table.
    void requireObject(const nlohmann::json& value, const std::string& where,
                       std::span<const char* const> allowed) const;
    /// The same with a list made at run time (a shape's keys, from the asset formats).
    void requireObject(const nlohmann::json& value, const std::string& where,
                       const std::vector<std::string>& allowed) const;
    /// The member `key` of the object `object` (at `where`); an error names it when missing.
    const nlohmann::json& at(const nlohmann::json& object, const std::string& key,
                             const std::string& where) const;
    /// A finite number in [lo, hi].
    double number(const nlohmann::json& value, const std::string& where, double lo,
                  double hi) const;
    /// An integer in [lo, hi] (a number with a fraction, or 1e3 written as a float, is not one;
    /// one beyond 64 bits is reported as written).
    std::int64_t integer(const nlohmann::json& value, const std::string& where, std::int64_t lo,
                         std::int64_t hi) const;
    /// An unsigned integer in [0, hi].
    std::uint64_t unsignedInteger(const nlohmann::json& value, const std::string& where,
                                  std::uint64_t hi) const;
    /// A string.
    std::string string(const nlohmann::json& value, const std::string& where) const;
    /// true or false.
    bool boolean(const nlohmann::json& value, const std::string& where) const;
    /// An array (of any length when `size` is 0, else of exactly `size` elements).
    const nlohmann::json& array(const nlohmann::json& value, const std::string& where,
                                std::size_t size = 0) const;

  private:
    std::string m_file;
};

}  // namespace glint

// Checked access to scene.json values: glint's shared JsonReader (every error names the file and
// the JSON path) with what only the scene reads — numbers as float, vectors of three.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "glint/image/internal/json_reader.h"
#include "vecmath.h"

namespace glint::render::detail {

using glint::throwMalformedJson;

/// glint::JsonReader for a scene file: numbers come as float (the scene's precision), the file
/// as a path, and three-number vectors are read whole.
class JsonReader : public glint::JsonReader {
  public:
    explicit JsonReader(std::filesystem::path file)
        : glint::JsonReader(file.string()), m_path(std::move(file)) {}

    const std::filesystem::path& file() const { return m_path; }

    /// A finite number in [lo, hi], as float.
    float number(const nlohmann::json& value, const std::string& where, double lo,
                 double hi) const {
        return float(glint::JsonReader::number(value, where, lo, hi));
    }
    /// An array of three finite numbers, each in [lo, hi].
    Vec3 vec3(const nlohmann::json& value, const std::string& where, double lo = -1e30,
              double hi = 1e30) const;

  private:
    std::filesystem::path m_path;
};

}  // namespace glint::render::detail

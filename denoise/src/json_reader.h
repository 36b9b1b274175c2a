// Reading the JSON files of the denoise module that people write or edit (paint scripts,
// session files, bank indexes): glint's shared reader (glint/image/internal/json_reader.h: one
// glint::Error(Format) naming the file and the place, a line and column for malformed text or
// the JSON pointer of the offending value) with the denoiser's parameter blocks.
#pragma once

#include <string>

#include "glint/denoise/filter.h"
#include "glint/image/internal/json_reader.h"

namespace glint::denoise::detail {

using glint::describeJson;
using glint::parseJsonText;
using glint::readJsonText;

/// glint::JsonReader with the denoiser's parameter blocks.
class JsonReader : public glint::JsonReader {
  public:
    using glint::JsonReader::JsonReader;

    /// A parameter block ({"name": number or list of strings}); the names and kinds are checked
    /// by resolveParams.
    ParamValues params(const nlohmann::json& value, const std::string& where) const;
};

/// Parameter values as one JSON object: numbers, and lists of strings as arrays.
nlohmann::json paramsJson(const ParamValues& params);

}  // namespace glint::denoise::detail

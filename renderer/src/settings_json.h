// scene.json's "render" block read through the settings codec (glint/render/settings_codec.h).
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "glint/image/internal/json_reader.h"
#include "glint/render/settings.h"

namespace glint::render {

/// Reads the "render" block `block` at JSON place `where` into `settings`: every key a named
/// setting (an unknown one is named), each of its JSON type and range.
void readSettingsJson(const glint::JsonReader& reader, const nlohmann::json& block,
                      const std::string& where, Settings& settings);

}  // namespace glint::render

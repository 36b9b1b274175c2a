// The look of a scene: its materials, lights and environment as typed, described properties
// that a look panel builds its controls from, edits, and saves back to scene.json.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "glint/image/parameters.h"

namespace glint::render {

/// One editable property: its description (a number, or a colour when isColour; a slider moves
/// logarithmically when scale is ParamScale::Log) and its current value. Material properties
/// are described by their kind (renderer/src/materials).
struct LookProperty : ParamSpec {
    std::array<double, 3> value{};  ///< current value; a number uses value[0]
};

/// What a look item is.
enum class LookItemKind { Material, Environment };

/// A material (lights are emissive materials) or the environment, with its properties.
struct LookItem {
    LookItemKind kind = LookItemKind::Material;
    std::string name;    ///< material name, or "environment"
    std::string type;    ///< "diffuse", "mirror", "dielectric", "conductor"; "image", "constant"
    bool light = false;  ///< emits light (an emissive material, or the environment)
    std::vector<LookProperty> properties;
};

}  // namespace glint::render

// The look of a scene: its materials, lights and environment as typed, described properties
// that a look panel builds its controls from, edits, and saves back to scene.json.
#pragma once

#include <array>
#include <string>
#include <vector>

namespace glint::render {

/// The kind of value a look property holds.
enum class PropertyType {
    Color,  ///< three components (RGB), each in [min, max]
    Scalar  ///< one number in [min, max] (value[0])
};

/// One editable property: its description and current value.
struct LookProperty {
    std::string name;   ///< key: "albedo", "emission", "strength", "roughness", "ior", "scale"...
    std::string label;  ///< for a UI, e.g. "emission colour"
    PropertyType type = PropertyType::Scalar;
    double min = 0.0, max = 1.0;    ///< range of the value (of each component for a colour)
    bool logScale = false;          ///< a slider should move logarithmically
    std::string help;               ///< one sentence
    std::array<double, 3> value{};  ///< current value; a scalar uses value[0]
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

// What a material kind's parameters are: each kind describes its own once, in its file under
// materials/, and that description drives scene reading (scene_loader.cpp), look edits
// (look.cpp), scene writing (scene_writer.cpp) and the table in docs/scene-format.md
// (materialParameterTable, checked by a test).
#pragma once

#include <string>
#include <string_view>

#include "glint/image/parameters.h"
#include "scene/scene_data.h"

namespace glint::render {

struct MaterialKind;

/// One parameter of a material kind: its description (spec.name is the scene.json key and the
/// look property's name) and where a Material holds it.
struct MaterialParameter {
    ParamSpec spec;                             ///< a number, or a colour (spec.isColour)
    float detail::Material::*number = nullptr;  ///< a number's field
    Vec3 detail::Material::*colour = nullptr;   ///< a colour's field
    /// A look panel edits it (Scene::setLook), and saveScene writes the edit back.
    bool look = false;
    /// The material's base colour texture multiplies it (glTF): a look panel labels it
    /// "… factor" where the material has one. Otherwise a texture replaces the base colour
    /// (`albedo`), which is then neither shown nor written.
    bool multipliedByTexture = false;
    /// Given only together with this other key (the conductor's `eta` and `k`); reading it sets
    /// Material::*given.
    const char* partner = nullptr;
    bool detail::Material::*given = nullptr;

    /// This parameter, edited in a look panel.
    MaterialParameter inLook() const;
    /// This parameter, multiplied by the base colour texture.
    MaterialParameter timesTexture() const;
    /// This parameter, given only with `other`; reading them sets `flag`.
    MaterialParameter givenWith(const char* other, bool detail::Material::*flag) const;
};

/// A colour parameter held in `field`.
MaterialParameter colourParameter(const char* name, const char* label, double min, double max,
                                  double defaultValue, Vec3 detail::Material::*field,
                                  const char* help);
/// A number parameter held in `field`.
MaterialParameter numberParameter(const char* name, const char* label, double min, double max,
                                  double defaultValue, float detail::Material::*field,
                                  const char* help);

/// The parameter `name` of `kind`, or null.
const MaterialParameter* findParameter(const MaterialKind& kind, std::string_view name);

/// The scene.json types, as an error message lists them: "diffuse, mirror, dielectric or
/// conductor".
std::string sceneJsonTypeList();

/// The material table of docs/scene-format.md: the keys of every kind (`type`, `texture`,
/// `emission`), then each registered kind and its parameters, one Markdown row each.
std::string materialParameterTable();

}  // namespace glint::render

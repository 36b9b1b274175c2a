#include "materials/material_parameters.h"

#include <sstream>
#include <vector>

#include "materials/bsdf.h"

namespace glint::render {

namespace {

/// The keys every kind takes, for the table (the loader reads them itself).
constexpr const char* kTextureHelp =
    "a PNG, JPEG, EXR or any image OpenImageIO reads; **replaces** `albedo`. sRGB images (JPEG; "
    "PNG unless it declares gamma 1.0; 8-bit tagged sRGB or untagged: BMP, TGA) are linearised; "
    "float images are used as they are; a negative "
    "or non-finite texel is an error naming the file and pixel. Lookups repeat (uv wrapped into "
    "[0,1) first).";
constexpr const char* kEmissionHelp =
    "Emitted radiance; any material may emit. Every emissive triangle is an area light.";

MaterialParameter parameterOf(ParamSpec spec) {
    MaterialParameter p;
    p.spec = std::move(spec);
    return p;
}

/// A number as the docs write it: 1.5, 0.001, 1e+18.
std::string formatNumber(double v) {
    std::ostringstream out;
    out << v;
    return out.str();
}

/// The value column: "[r,g,b] in [0, 1]", "number in [0.001, 100]".
std::string valueColumn(const ParamSpec& spec) {
    return std::string(spec.isColour ? "[r,g,b]" : "number") + " in [" + formatNumber(spec.min) +
           ", " + formatNumber(spec.max) + "]";
}

std::string defaultColumn(const ParamSpec& spec) {
    const std::string v = formatNumber(spec.defaultValue);
    return spec.isColour ? "[" + v + "," + v + "," + v + "]" : v;
}

}  // namespace

MaterialParameter MaterialParameter::inLook() const {
    MaterialParameter p = *this;
    p.look = true;
    return p;
}

MaterialParameter MaterialParameter::timesTexture() const {
    MaterialParameter p = *this;
    p.multipliedByTexture = true;
    return p;
}

MaterialParameter MaterialParameter::givenWith(const char* other,
                                               bool detail::Material::*flag) const {
    MaterialParameter p = *this;
    p.partner = other;
    p.given = flag;
    return p;
}

MaterialParameter colourParameter(const char* name, const char* label, double min, double max,
                                  double defaultValue, Vec3 detail::Material::*field,
                                  const char* help) {
    MaterialParameter p = parameterOf(ParamSpec::colour(name, label, min, max, defaultValue, help));
    p.colour = field;
    return p;
}

MaterialParameter numberParameter(const char* name, const char* label, double min, double max,
                                  double defaultValue, float detail::Material::*field,
                                  const char* help) {
    MaterialParameter p = parameterOf(
        ParamSpec(name, label, min, max, defaultValue, ParamScale::Linear, false, help));
    p.number = field;
    return p;
}

const MaterialParameter* findParameter(const MaterialKind& kind, std::string_view name) {
    for (const MaterialParameter& p : kind.parameters)
        if (p.spec.name == name) return &p;
    return nullptr;
}

std::string sceneJsonTypeList() {
    std::vector<std::string> names;
    for (const MaterialKind* kind : kMaterialKinds)
        if (kind->inSceneJson) names.emplace_back(kind->name);
    std::string list;
    for (std::size_t i = 0; i < names.size(); ++i)
        list += (i == 0 ? "" : i + 1 == names.size() ? " or " : ", ") + names[i];
    return list;
}

std::string materialParameterTable() {
    std::ostringstream t;
    std::string types;
    for (const MaterialKind* kind : kMaterialKinds)
        if (kind->inSceneJson)
            types += (types.empty() ? "`\"" : ", `\"") + std::string(kind->name) + "\"`";
    t << "| type | key | value | default | meaning |\n|---|---|---|---|---|\n";
    t << "| all | `type` | " << types << " | **required** | the kind of material, below |\n";
    t << "| all | `texture` | file name | — | " << kTextureHelp << " |\n";
    t << "| all | `emission` | [r,g,b] in [0, 1e18] | [0,0,0] | " << kEmissionHelp << " |\n";
    for (const MaterialKind* kind : kMaterialKinds) {
        const std::string name = "`" + std::string(kind->name) + "`";
        t << "| " << name << " | | | | " << kind->summary
          << (kind->inSceneJson ? "" : " Its keys are a glTF shape's `edits`.") << " |\n";
        for (const MaterialParameter& p : kind->parameters)
            t << "| " << name << " | `" << p.spec.name << "` | " << valueColumn(p.spec) << " | "
              << defaultColumn(p.spec) << " | " << p.spec.help << " |\n";
    }
    return t.str();
}

}  // namespace glint::render

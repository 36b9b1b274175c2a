// Scene::look and Scene::setLook: the editable properties of materials, lights and the
// environment, checked with the same ranges as the JSON reader (scene_loader.cpp).
#include <cmath>
#include <sstream>

#include "glint/image/error.h"
#include "glint/render/scene.h"
#include "materials/bsdf.h"
#include "scene/loader.h"
#include "scene/scene_data.h"

namespace glint::render {

using detail::EnvironmentDesc;
using detail::kMaxRadiance;
using detail::Material;
using detail::materialTypeName;
using detail::SceneData;

namespace {

std::array<double, 3> toArray(const Vec3& v) {
    return {double(v.x), double(v.y), double(v.z)};
}

LookProperty property(ParamSpec spec, const std::array<double, 3>& value) {
    LookProperty p;
    static_cast<ParamSpec&>(p) = std::move(spec);
    p.value = value;
    return p;
}

LookProperty color(const char* name, const char* label, double max, const Vec3& value,
                   const char* help) {
    return property(ParamSpec::colour(name, label, 0.0, max, 0.0, help), toArray(value));
}

LookProperty scalar(const char* name, const char* label, double min, double max, bool logScale,
                    double value, const char* help) {
    return property(ParamSpec(name, label, min, max, value,
                              logScale ? ParamScale::Log : ParamScale::Linear, false, help),
                    {value, 0.0, 0.0});
}

/// True when a look panel shows parameter `p` of `m`: a look parameter, unless it is the base
/// colour and a texture replaces it.
bool shown(const Material& m, const MaterialParameter& p) {
    return p.look && (m.texture < 0 || p.colour != &Material::albedo || p.multipliedByTexture);
}

std::vector<LookProperty> materialProperties(const Material& m) {
    std::vector<LookProperty> props;
    // The kind's own parameters, as it describes them.
    for (const MaterialParameter& p : materialKind(m.type).parameters) {
        if (!shown(m, p)) continue;
        LookProperty prop =
            property(p.spec, p.colour ? toArray(m.*p.colour)
                                      : std::array<double, 3>{double(m.*p.number), 0.0, 0.0});
        // A factor that multiplies a texture says so.
        if (p.multipliedByTexture && m.texture >= 0) prop.label += " factor";
        props.push_back(std::move(prop));
    }
    props.push_back(color("emission", "emission colour", 1.0, m.emissionColor,
                          "Colour of the light the surface emits (times strength)."));
    props.push_back(scalar("strength", "emission strength", 0.0, kMaxRadiance, true,
                           m.emissionStrength,
                           "Emitted radiance scale; 0 makes the surface no light."));
    return props;
}

std::vector<LookProperty> environmentProperties(const EnvironmentDesc& env) {
    std::vector<LookProperty> props;
    if (env.kind == EnvironmentDesc::Kind::Constant)
        props.push_back(color("color", "colour", kMaxRadiance, env.baseColor,
                              "Radiance arriving from every direction (times scale)."));
    props.push_back(scalar("scale", "strength", 0.0, 1e30, true, env.scale,
                           "Multiplies the environment's radiance."));
    props.push_back(scalar("rotate", "rotation (degrees)", -1e6, 1e6, false, env.rotateDeg,
                           "Rotation about the up (+y) axis."));
    return props;
}

// Range check with the JSON reader's message; `where` is the JSON place of the value.
float checked(double v, double lo, double hi, const std::filesystem::path& file,
              const std::string& where) {
    if (!std::isfinite(v) || v < lo || v > hi) {
        std::ostringstream msg;
        msg << "expected a number in [" << lo << ", " << hi << "], got " << v;
        throw Error(ErrorKind::InvalidArgument, msg.str(), file.string(), where);
    }
    return float(v);
}

Vec3 checkedColor(const std::array<double, 3>& v, double lo, double hi,
                  const std::filesystem::path& file, const std::string& where) {
    return {checked(v[0], lo, hi, file, where + "/0"), checked(v[1], lo, hi, file, where + "/1"),
            checked(v[2], lo, hi, file, where + "/2")};
}

// Emission on triangles that cannot emit (moving, or zero total area) is refused as the loader
// refuses it.
void checkCanEmit(const SceneData& d, std::size_t material, const std::string& where) {
    double area = 0.0;
    bool used = false;
    for (std::uint32_t i = 0; i < d.instances.size(); ++i) {
        const std::size_t n = d.meshes[d.instances[i].mesh].triangleCount();
        for (std::uint32_t t = 0; t < n; ++t) {
            if (d.materialOf(i, t) != material) continue;
            used = true;
            if (d.instances[i].motion >= 0)
                throw Error(ErrorKind::InvalidArgument,
                            "a moving shape must not be emissive (area lights are static)",
                            d.path.string(), where);
            const detail::TriangleView tri = d.triangle(i, t);
            area += triangleArea(tri.p[0], tri.p[1], tri.p[2]);
        }
    }
    if (used && !(area > 0.0))
        throw Error(ErrorKind::InvalidArgument,
                    "emissive faces would have zero total area (zero-area light)", d.path.string(),
                    where);
}

void setMaterial(SceneData& d, std::size_t index, const std::string& property,
                 const std::array<double, 3>& value) {
    Material& m = d.materials[index];
    const std::string where = "/materials/" + m.name + "/" + property;
    Material next = m;
    const MaterialParameter* p = findParameter(materialKind(m.type), property);
    if (p && shown(m, *p)) {
        // A parameter of the kind, in the range it describes.
        if (p->colour)
            next.*p->colour = checkedColor(value, p->spec.min, p->spec.max, d.path, where);
        else
            next.*p->number = checked(value[0], p->spec.min, p->spec.max, d.path, where);
    } else if (property == "emission") {
        next.emissionColor = checkedColor(value, 0.0, 1.0, d.path, where);
        next.emission = next.emissionColor * next.emissionStrength;
    } else if (property == "strength") {
        next.emissionStrength = checked(value[0], 0.0, kMaxRadiance, d.path, where);
        next.emission = next.emissionColor * next.emissionStrength;
    } else {
        std::string names;
        for (const LookProperty& p : materialProperties(m))
            names += (names.empty() ? "" : ", ") + p.name;
        throw Error(ErrorKind::InvalidArgument,
                    "material '" + m.name + "' (" + materialTypeName(m.type) +
                        ") has no editable property '" + property + "' (it has " + names + ")",
                    d.path.string(), where);
    }
    if (next.emissive() && !m.emissive()) checkCanEmit(d, index, where);
    next.edited = true;
    m = std::move(next);
}

void setEnvironment(SceneData& d, const std::string& property, const std::array<double, 3>& value) {
    EnvironmentDesc& env = d.environment;
    const std::string where = "/environment/" + property;
    if (property == "scale") {
        const float scale = checked(value[0], 0.0, 1e30, d.path, where);
        // Build the scaled copy first: an overflow leaves the environment as it was.
        if (env.kind == EnvironmentDesc::Kind::Image)
            env.image = detail::scaledRgb(env.source, scale, "environment image", d.path, where);
        if (maxAbsComponent(env.baseColor * scale) > kMaxRadiance)
            throw Error(
                ErrorKind::InvalidArgument,
                "colour × scale would exceed the largest radiance, " + std::to_string(kMaxRadiance),
                d.path.string(), where);
        env.scale = scale;
        env.color = env.baseColor * scale;
    } else if (property == "rotate") {
        env.rotateDeg = checked(value[0], -1e6, 1e6, d.path, where);
    } else if (property == "color" && env.kind == EnvironmentDesc::Kind::Constant) {
        env.baseColor = checkedColor(value, 0.0, kMaxRadiance, d.path, where);
        if (maxAbsComponent(env.baseColor * env.scale) > kMaxRadiance)
            throw Error(
                ErrorKind::InvalidArgument,
                "colour × scale would exceed the largest radiance, " + std::to_string(kMaxRadiance),
                d.path.string(), where);
        env.color = env.baseColor * env.scale;
    } else {
        throw Error(ErrorKind::InvalidArgument,
                    "the environment has no editable property '" + property +
                        "' (it has scale, rotate" +
                        (env.kind == EnvironmentDesc::Kind::Constant ? ", color" : "") + ")",
                    d.path.string(), where);
    }
    env.edited = true;
}

}  // namespace

std::vector<LookItem> Scene::look() const {
    std::vector<LookItem> items;
    for (const Material& m : m_data->materials)
        items.push_back({LookItemKind::Material, m.name, materialTypeName(m.type), m.emissive(),
                         materialProperties(m)});
    const EnvironmentDesc& env = m_data->environment;
    if (env.kind != EnvironmentDesc::Kind::None)
        items.push_back({LookItemKind::Environment, "environment",
                         env.kind == EnvironmentDesc::Kind::Image ? "image" : "constant", true,
                         environmentProperties(env)});
    return items;
}

void Scene::setLook(const std::string& item, const std::string& property,
                    const std::array<double, 3>& value) {
    SceneData& d = *m_data;
    bool found = false;
    for (std::size_t i = 0; i < d.materials.size() && !found; ++i)
        if (d.materials[i].name == item) {
            setMaterial(d, i, property, value);
            found = true;
        }
    if (!found && item == "environment" && d.environment.kind != EnvironmentDesc::Kind::None) {
        setEnvironment(d, property, value);
        found = true;
    }
    if (!found) {
        std::string names;
        for (const LookItem& it : look()) names += (names.empty() ? "" : ", ") + it.name;
        throw Error(ErrorKind::InvalidArgument,
                    "no material or environment called '" + item + "' (the scene has " +
                        (names.empty() ? std::string("none") : names) + ")",
                    d.path.string(), "/materials/" + item);
    }
    ++d.lookRevision;
}

void Scene::setLook(const std::string& item, const std::string& property, double value) {
    setLook(item, property, std::array<double, 3>{value, value, value});
}

std::uint64_t Scene::lookRevision() const {
    return m_data->lookRevision;
}

}  // namespace glint::render

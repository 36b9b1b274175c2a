// Scene::look and Scene::setLook: the editable properties of materials, lights and the
// environment, checked with the same ranges as the JSON reader (scene_loader.cpp).
#include <cmath>
#include <sstream>

#include "glint/image/error.h"
#include "glint/render/scene.h"
#include "scene/loader.h"
#include "scene/scene_data.h"

namespace glint::render {

using detail::EnvironmentDesc;
using detail::kMaxRadiance;
using detail::Material;
using detail::MaterialType;
using detail::materialTypeName;
using detail::SceneData;

namespace {

std::array<double, 3> toArray(const Vec3& v) {
    return {double(v.x), double(v.y), double(v.z)};
}

LookProperty color(const char* name, const char* label, double max, const Vec3& value,
                   const char* help) {
    LookProperty p;
    p.name = name;
    p.label = label;
    p.type = PropertyType::Color;
    p.min = 0.0;
    p.max = max;
    p.help = help;
    p.value = toArray(value);
    return p;
}

LookProperty scalar(const char* name, const char* label, double min, double max, bool logScale,
                    double value, const char* help) {
    LookProperty p;
    p.name = name;
    p.label = label;
    p.type = PropertyType::Scalar;
    p.min = min;
    p.max = max;
    p.logScale = logScale;
    p.help = help;
    p.value = {value, 0.0, 0.0};
    return p;
}

std::vector<LookProperty> materialProperties(const Material& m) {
    std::vector<LookProperty> props;
    if (m.type == MaterialType::MetallicRoughness) {
        // glTF factors: each multiplies its texture where the material has one.
        props.push_back(color("albedo", m.texture >= 0 ? "base colour factor" : "base colour", 1.0,
                              m.albedo,
                              "Base colour: the diffuse colour of a dielectric, the reflectance "
                              "of a metal (multiplies the base colour texture)."));
        props.push_back(scalar("metallic", "metallic", 0.0, 1.0, false, m.metallic,
                               "0 is a dielectric base under a specular coat, 1 a metal "
                               "(multiplies the metallic-roughness texture's B)."));
        props.push_back(scalar("roughness", "roughness", 0.0, 1.0, false, m.roughness,
                               "Perceptual roughness (GGX alpha = roughness²; multiplies the "
                               "metallic-roughness texture's G)."));
        props.push_back(scalar("ior", "index of refraction", 1.0, 10.0, false, m.ior,
                               "The dielectric base's index (its specular f0; 1.5 by default)."));
        props.push_back(scalar("transmission", "transmission", 0.0, 1.0, false, m.transmission,
                               "How much of the dielectric base refracts (rough glass) instead of "
                               "scattering diffusely (KHR_materials_transmission)."));
    } else if (m.texture < 0)
        props.push_back(color(
            "albedo", m.type == MaterialType::Diffuse ? "base colour" : "tint", 1.0, m.albedo,
            m.type == MaterialType::Diffuse ? "Diffuse reflectance."
                                            : "Colour that multiplies what the surface reflects or "
                                              "transmits."));
    props.push_back(color("emission", "emission colour", 1.0, m.emissionColor,
                          "Colour of the light the surface emits (times strength)."));
    props.push_back(scalar("strength", "emission strength", 0.0, kMaxRadiance, true,
                           m.emissionStrength,
                           "Emitted radiance scale; 0 makes the surface no light."));
    if (m.type == MaterialType::Conductor)
        props.push_back(scalar("roughness", "roughness", 0.0, 1.0, false, m.roughness,
                               "GGX roughness (alpha = roughness²); 0 is a perfect mirror."));
    if (m.type == MaterialType::Dielectric) {
        props.push_back(scalar("ior", "index of refraction", 1e-3, 100.0, false, m.ior,
                               "Index of refraction inside the surface (glass about 1.5)."));
        props.push_back(scalar("roughness", "roughness", 0.0, 1.0, false, m.roughness,
                               "GGX roughness (alpha = roughness²); 0 is smooth glass."));
    }
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
    const bool gltf = m.type == MaterialType::MetallicRoughness;
    if (property == "albedo" && (m.texture < 0 || gltf)) {
        next.albedo = checkedColor(value, 0.0, 1.0, d.path, where);
    } else if (property == "metallic" && gltf) {
        next.metallic = checked(value[0], 0.0, 1.0, d.path, where);
    } else if (property == "roughness" && gltf) {
        next.roughness = checked(value[0], 0.0, 1.0, d.path, where);
    } else if (property == "ior" && gltf) {
        next.ior = checked(value[0], 1.0, 10.0, d.path, where);
    } else if (property == "transmission" && gltf) {
        next.transmission = checked(value[0], 0.0, 1.0, d.path, where);
    } else if (property == "emission") {
        next.emissionColor = checkedColor(value, 0.0, 1.0, d.path, where);
        next.emission = next.emissionColor * next.emissionStrength;
    } else if (property == "strength") {
        next.emissionStrength = checked(value[0], 0.0, kMaxRadiance, d.path, where);
        next.emission = next.emissionColor * next.emissionStrength;
    } else if (property == "roughness" &&
               (m.type == MaterialType::Conductor || m.type == MaterialType::Dielectric)) {
        next.roughness = checked(value[0], 0.0, 1.0, d.path, where);
    } else if (property == "ior" && m.type == MaterialType::Dielectric) {
        next.ior = checked(value[0], 1e-3, 100.0, d.path, where);
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

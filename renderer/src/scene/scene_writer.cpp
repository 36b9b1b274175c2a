// saveScene: the scene's own JSON with its look edits written back, paths rebased to the new
// folder. Numbers are written as the double of the float the renderer holds, which reads back
// to the same float, so the saved scene renders bit for bit the same.
#include <fstream>

#include <nlohmann/json.hpp>

#include "glint/image/error.h"
#include "glint/image/io.h"
#include "glint/render/scene.h"
#include "scene/scene_data.h"

namespace glint::render {

namespace fs = std::filesystem;
using ordered_json = nlohmann::ordered_json;
using detail::EnvironmentDesc;
using detail::Material;
using detail::MaterialType;

namespace {

ordered_json toJson(const Vec3& v) {
    return ordered_json::array({double(v.x), double(v.y), double(v.z)});
}

// `file` as a path relative to `toDir` where one exists, else absolute.
std::string relativeTo(const fs::path& file, const fs::path& toDir) {
    const fs::path absolute = fs::absolute(file).lexically_normal();
    const fs::path relative = absolute.lexically_relative(fs::absolute(toDir).lexically_normal());
    return relative.empty() ? absolute.string() : relative.generic_string();
}

// A path of the scene file: absolute ones stay, relative ones (to `fromDir`) are rebased.
std::string rebase(const fs::path& file, const fs::path& fromDir, const fs::path& toDir) {
    return file.is_absolute() ? file.string() : relativeTo(fromDir / file, toDir);
}

// The full JSON definition of a material that came from an MTL file.
ordered_json definition(const Material& m, const detail::SceneData& d, const fs::path& toDir) {
    ordered_json j;
    switch (m.type) {
        case MaterialType::Diffuse:
            j["type"] = "diffuse";
            break;
        case MaterialType::Mirror:
            j["type"] = "mirror";
            break;
        case MaterialType::Dielectric:
            j["type"] = "dielectric";
            break;
        case MaterialType::Conductor:
            j["type"] = "conductor";
            break;
    }
    if (m.texture >= 0)
        j["texture"] = relativeTo(d.textures[std::size_t(m.texture)].path, toDir);
    else
        j["albedo"] = toJson(m.albedo);
    j["emission"] = toJson(m.emission);
    if (m.type == MaterialType::Dielectric) j["ior"] = double(m.ior);
    if (m.type == MaterialType::Conductor) {
        j["roughness"] = double(m.roughness);
        if (m.hasEtaK) {
            j["eta"] = toJson(m.eta);
            j["k"] = toJson(m.k);
        } else {
            j["specular"] = toJson(m.specular);
        }
    }
    return j;
}

}  // namespace

void saveScene(const Scene& scene, const fs::path& path) {
    const detail::SceneData& d = scene.data();
    if (d.sourceJson.empty())
        throw Error(ErrorKind::InvalidArgument, "the scene was not read from JSON: nothing to save",
                    path.string());
    ordered_json root = ordered_json::parse(d.sourceJson, nullptr, true, false);
    const fs::path fromDir = d.path.parent_path();
    const fs::path toDir = path.parent_path();

    // Paths relative to the old file become relative to the new one.
    auto rebaseString = [&](ordered_json& value) {
        if (value.is_string()) value = rebase(value.get<std::string>(), fromDir, toDir);
    };
    if (root.contains("shapes"))
        for (ordered_json& shape : root["shapes"])
            if (shape.contains("obj")) rebaseString(shape["obj"]);
    if (root.contains("environment") && root["environment"].contains("image"))
        rebaseString(root["environment"]["image"]);
    if (root.contains("materials"))
        for (auto& item : root["materials"].items())
            if (item.value().contains("texture")) rebaseString(item.value()["texture"]);

    // Edited materials: JSON ones get their editable keys updated, MTL ones a full definition.
    for (const Material& m : d.materials) {
        if (!m.edited) continue;
        ordered_json& materials = root["materials"];
        if (!m.fromJson) {
            materials[m.name] = definition(m, d, toDir);
            continue;
        }
        ordered_json& j = materials[m.name];
        if (m.texture < 0) j["albedo"] = toJson(m.albedo);
        j["emission"] = toJson(m.emission);
        if (m.type == MaterialType::Dielectric) j["ior"] = double(m.ior);
        if (m.type == MaterialType::Conductor) j["roughness"] = double(m.roughness);
    }
    const EnvironmentDesc& env = d.environment;
    if (env.edited) {
        ordered_json& j = root["environment"];
        j["scale"] = double(env.scale);
        j["rotate"] = double(env.rotateDeg);
        if (env.kind == EnvironmentDesc::Kind::Constant) j["color"] = toJson(env.baseColor);
    }

    writeAtomically(path, [&](const fs::path& tmp) {
        std::ofstream out(tmp, std::ios::binary);
        out << root.dump(2) << "\n";
        out.close();
        if (!out)
            throw Error(ErrorKind::Io, "cannot write the scene file", path.string());
    });
}

}  // namespace glint::render

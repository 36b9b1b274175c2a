// saveScene: the scene's own JSON with its look edits written back, paths rebased to the new
// folder. Numbers are written as the shortest decimal that reads back to the float the renderer
// holds, so the saved scene renders bit for bit the same.
#include <charconv>
#include <cstdlib>
#include <fstream>
#include <ostream>

#include <nlohmann/json.hpp>

#include "glint/image/error.h"
#include "glint/image/io.h"
#include "glint/render/scene.h"
#include "materials/bsdf.h"
#include "scene/asset_format.h"
#include "scene/scene_access.h"
#include "scene/scene_data.h"

namespace glint::render {

namespace fs = std::filesystem;
using ordered_json = nlohmann::ordered_json;
using detail::EnvironmentDesc;
using detail::Material;

namespace {

// The shortest decimal that reads back to the same float (so 0.1f is written 0.1, not
// 0.10000000149011612), as a double.
double shortest(float value) {
    char text[32];
    const auto [end, ec] = std::to_chars(text, text + sizeof text, value);
    if (ec == std::errc()) {
        *end = '\0';
        const double d = std::strtod(text, nullptr);
        if (float(d) == value) return d;
    }
    return double(value);
}

ordered_json toJson(float v) {
    return shortest(v);
}

ordered_json toJson(const Vec3& v) {
    return ordered_json::array({shortest(v.x), shortest(v.y), shortest(v.z)});
}

// JSON text with two-space indentation and arrays of numbers on one line.
void writePretty(std::ostream& out, const ordered_json& j, int indent) {
    const std::string pad(std::size_t(indent), ' ');
    if (j.is_object() && !j.empty()) {
        out << "{\n";
        std::size_t i = 0;
        for (const auto& item : j.items()) {
            out << pad << "  " << ordered_json(item.key()).dump() << ": ";
            writePretty(out, item.value(), indent + 2);
            out << (++i < j.size() ? ",\n" : "\n");
        }
        out << pad << "}";
        return;
    }
    if (j.is_array() && !j.empty()) {
        bool flat = true;
        for (const ordered_json& e : j) flat = flat && !e.is_structured();
        if (flat) {
            out << "[";
            for (std::size_t i = 0; i < j.size(); ++i) out << (i ? ", " : "") << j[i].dump();
            out << "]";
            return;
        }
        out << "[\n";
        for (std::size_t i = 0; i < j.size(); ++i) {
            out << pad << "  ";
            writePretty(out, j[i], indent + 2);
            out << (i + 1 < j.size() ? ",\n" : "\n");
        }
        out << pad << "]";
        return;
    }
    out << j.dump(-1, ' ', false, ordered_json::error_handler_t::replace);
}

// `file` as a path relative to `toDir` when the two share a folder below the root, else
// absolute (a path that climbs to the root says nothing a reader can use).
std::string relativeTo(const fs::path& file, const fs::path& toDir) {
    const fs::path absolute = fs::absolute(file).lexically_normal();
    const fs::path dir = fs::absolute(toDir).lexically_normal();
    auto a = absolute.begin(), d = dir.begin();
    int shared = 0;
    for (; a != absolute.end() && d != dir.end() && *a == *d; ++a, ++d) ++shared;
    if (shared < 2) return absolute.string();  // only the root in common
    const fs::path relative = absolute.lexically_relative(dir);
    return relative.empty() ? absolute.string() : relative.generic_string();
}

// A path of the scene file: absolute ones stay, relative ones (to `fromDir`) are rebased.
std::string rebase(const fs::path& file, const fs::path& fromDir, const fs::path& toDir) {
    return file.is_absolute() ? file.string() : relativeTo(fromDir / file, toDir);
}

// Parameter `p` of `m` as JSON.
ordered_json valueOf(const Material& m, const MaterialParameter& p) {
    return p.colour ? toJson(m.*p.colour) : toJson(m.*p.number);
}

// True when parameter `p` of `m` holds its default (reading it back without the key gives the
// same value).
bool atDefault(const Material& m, const MaterialParameter& p) {
    const float d = float(p.spec.defaultValue);
    if (!p.colour) return m.*p.number == d;
    const Vec3& c = m.*p.colour;
    return c.x == d && c.y == d && c.z == d;
}

// Writes into the material object `j` the parameters of `m`'s kind that `j` already has or
// that differ from their default: those a look panel edits (lookOnly), or all (a definition).
// A base colour that a texture replaces is not written, nor a pair (eta, k) not given; a pair
// given is written whole (one of them alone would not read back).
void writeParameters(ordered_json& j, const Material& m, bool lookOnly) {
    for (const MaterialParameter& p : materialKind(m.type).parameters) {
        if (lookOnly && !p.look) continue;
        if (p.colour == &Material::albedo && m.texture >= 0 && !p.multipliedByTexture) continue;
        if (p.given && !(m.*p.given)) continue;
        if (j.contains(p.spec.name) || !atDefault(m, p) || p.given) j[p.spec.name] = valueOf(m, p);
    }
}

// The full JSON definition of a material that came from an MTL file.
ordered_json definition(const Material& m, const detail::SceneData& d, const fs::path& toDir) {
    ordered_json j;
    j["type"] = detail::materialTypeName(m.type);
    if (m.texture >= 0) j["texture"] = relativeTo(d.textures[std::size_t(m.texture)].path, toDir);
    writeParameters(j, m, false);
    j["emission"] = toJson(m.emission);
    return j;
}

}  // namespace

void saveScene(const Scene& scene, const fs::path& path) {
    const detail::SceneData& d = detail::sceneData(scene);
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
            for (const detail::AssetFormat* format : detail::assetFormatRegistry())
                if (shape.contains(format->key)) rebaseString(shape[format->key]);
    if (root.contains("environment") && root["environment"].contains("image"))
        rebaseString(root["environment"]["image"]);
    if (root.contains("materials"))
        for (auto& item : root["materials"].items())
            if (item.value().contains("texture")) rebaseString(item.value()["texture"]);

    // Edited materials: JSON ones get their editable keys updated, MTL ones a full definition.
    for (const Material& m : d.materials) {
        if (!m.edited) continue;
        if (m.assetShape >= 0 && !m.fromJson) {
            // An asset's material edited in place (a glTF material): its factors go to the
            // placing shape's "edits"; the asset's textures stay as the asset has them.
            ordered_json& j = root["shapes"][std::size_t(m.assetShape)]["edits"][m.assetName];
            for (const MaterialParameter& p : materialKind(m.type).parameters)
                if (p.look) j[p.spec.name] = valueOf(m, p);
            j["emission"] = toJson(m.emission);
            continue;
        }
        ordered_json& materials = root["materials"];
        if (!m.fromJson) {
            materials[m.name] = definition(m, d, toDir);
            continue;
        }
        ordered_json& j = materials[m.name];
        writeParameters(j, m, true);
        j["emission"] = toJson(m.emission);
    }
    const EnvironmentDesc& env = d.environment;
    if (env.edited) {
        ordered_json& j = root["environment"];
        j["scale"] = toJson(env.scale);
        j["rotate"] = toJson(env.rotateDeg);
        if (env.kind == EnvironmentDesc::Kind::Constant) j["color"] = toJson(env.baseColor);
    }

    writeAtomically(path, [&](const fs::path& tmp) {
        std::ofstream out(tmp, std::ios::binary);
        writePretty(out, root, 0);
        out << "\n";
        out.close();
        if (!out) throw Error(ErrorKind::Io, "cannot write the scene file", path.string());
    });
}

}  // namespace glint::render

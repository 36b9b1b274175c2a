// scene.json → SceneData (loader.h): camera, film, render block, materials (JSON overriding an
// asset's materials by name), environment, shapes (an asset of a registered format,
// asset_format.h) with scale-rotate-translate transforms and motion, the scene built around a
// bare asset, and the texture table with the reading of textures and environment images. Each
// format imports its own files through the loader's ImportContext.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <sstream>
#include <string>
#include <tuple>

#include <nlohmann/json.hpp>

#include "glint/image/error.h"
#include "glint/image/io.h"
#include "glint/render/scene.h"
#include "materials/bsdf.h"
#include "scene/asset_format.h"
#include "scene/camera.h"
#include "scene/input_file.h"
#include "scene/json_reader.h"
#include "scene/loader.h"
#include "scene/scene_data.h"
#include "settings_json.h"

namespace glint::render {

namespace fs = std::filesystem;
using nlohmann::json;

namespace detail {

Loader::Loader(const fs::path& file, SceneData& scene, std::uint64_t memoryLimit)
    : m_reader(file), m_scene(scene), m_memoryLimit(memoryLimit) {
    m_dir = file.parent_path();
}

Vec3 Loader::radiance(const json& value, const std::string& where) const {
    try {
        return m_reader.vec3(value, where, 0.0, kMaxRadiance);
    } catch (const Error& e) {
        // Say why the range ends where it does.
        throw Error(e.kind(),
                    e.message() +
                        " (radiance is limited to 1e18 so that its variance, about its "
                        "square, fits a float EXR)",
                    e.file(), e.where());
    }
}

int Loader::addMaterial(Material material) {
    m_materialIndex[material.name] = int(m_scene.materials.size());
    m_scene.materials.push_back(std::move(material));
    return int(m_scene.materials.size()) - 1;
}

void Loader::load(const json& root) {
    m_reader.requireObject(root, "",
                           {"camera", "film", "materials", "shapes", "environment", "render"});
    if (!root.contains("film")) m_reader.fail("/film", "missing required key 'film'");
    readFilm(root["film"], "/film");
    m_hasCamera = root.contains("camera");
    if (m_hasCamera) readCamera(root["camera"], "/camera");
    if (root.contains("render")) readRender(root["render"], "/render");
    // JSON materials are parsed up front; they override MTL materials of the same name.
    if (root.contains("materials")) {
        const json& mats = root["materials"];
        if (!mats.is_object()) m_reader.fail("/materials", "expected an object of materials");
        for (const auto& item : mats.items()) {
            const std::string where = "/materials/" + item.key();
            Material m = readMaterial(item.key(), item.value(), where);
            m.fromJson = true;
            addMaterial(std::move(m));
        }
    }
    if (root.contains("shapes")) {
        const json& shapes = root["shapes"];
        if (!shapes.is_array()) m_reader.fail("/shapes", "expected an array of shapes");
        for (std::size_t i = 0; i < shapes.size(); ++i)
            readShape(shapes[i], "/shapes/" + std::to_string(i), int(i));
    }
    if (root.contains("environment")) readEnvironment(root["environment"], "/environment");
    // Without a camera block, the first camera an asset brings.
    if (!m_hasCamera && !m_scene.assetCameras.empty()) useAssetCamera(0);
    for (Material& m : m_scene.materials) m.deriveEmissionLook();
    m_scene.finishMeshes();
    computeBounds(m_scene);
    if (m_scene.triangleCount() == 0 && m_scene.environment.kind == EnvironmentDesc::Kind::None)
        m_reader.fail("/shapes", "the scene has neither geometry nor an environment");
}

void Loader::readFilm(const json& j, const std::string& where) {
    m_reader.requireObject(j, where, {"width", "height"});
    if (!j.contains("width")) m_reader.fail(where + "/width", "missing required key 'width'");
    if (!j.contains("height")) m_reader.fail(where + "/height", "missing required key 'height'");
    m_scene.width = int(m_reader.integer(j["width"], where + "/width", 1, 16384));
    m_scene.height = int(m_reader.integer(j["height"], where + "/height", 1, 16384));
}

void Loader::readCamera(const json& j, const std::string& where) {
    m_reader.requireObject(
        j, where,
        {"position", "lookAt", "up", "fovY", "lensRadius", "focusDistance", "shutter", "motion"});
    CameraDesc& cam = m_scene.camera;
    if (j.contains("position"))
        cam.position =
            m_reader.vec3(j["position"], where + "/position", -kMaxCoordinate, kMaxCoordinate);
    if (j.contains("lookAt"))
        cam.lookAt = m_reader.vec3(j["lookAt"], where + "/lookAt", -kMaxCoordinate, kMaxCoordinate);
    if (j.contains("up")) cam.up = m_reader.vec3(j["up"], where + "/up");
    if (j.contains("fovY")) cam.fovY = m_reader.number(j["fovY"], where + "/fovY", 1e-3, 179.0);
    if (j.contains("lensRadius"))
        cam.lensRadius = m_reader.number(j["lensRadius"], where + "/lensRadius", 0.0, 1e30);
    if (j.contains("focusDistance"))
        cam.focusDistance =
            m_reader.number(j["focusDistance"], where + "/focusDistance", 1e-9, 1e30);
    if (j.contains("shutter")) {
        const json& s = j["shutter"];
        if (!s.is_array() || s.size() != 2)
            m_reader.fail(where + "/shutter", "expected [open, close]");
        cam.shutterOpen = m_reader.number(s[0], where + "/shutter/0", -1e30, 1e30);
        cam.shutterClose = m_reader.number(s[1], where + "/shutter/1", -1e30, 1e30);
        if (cam.shutterClose < cam.shutterOpen)
            m_reader.fail(where + "/shutter", "shutter close (" + json(s[1]).dump() +
                                                  ") must not be before shutter open (" +
                                                  json(s[0]).dump() + ")");
    }
    if (j.contains("motion")) {
        const json& m = j["motion"];
        m_reader.requireObject(m, where + "/motion", {"position", "lookAt"});
        cam.motionPosition = m.contains("position")
                                 ? m_reader.vec3(m["position"], where + "/motion/position")
                                 : cam.position;
        cam.motionLookAt = m.contains("lookAt")
                               ? m_reader.vec3(m["lookAt"], where + "/motion/lookAt")
                               : cam.lookAt;
        cam.hasMotion = length(cam.motionPosition - cam.position) > 0.0f ||
                        length(cam.motionLookAt - cam.lookAt) > 0.0f;
    }
    // A view basis the camera can compute in float, at shutter open and over the shutter.
    if (const auto fault = cameraFault(cam)) m_reader.fail(where + "/" + fault->key, fault->reason);
}

void Loader::readRender(const json& j, const std::string& where) {
    readSettingsJson(m_reader, j, where, m_scene.settings);
}

namespace {
/// The keys a material of `kind` takes: those of every kind, then its own parameters (all of
/// them, or those a look panel edits).
std::vector<std::string> materialKeys(const MaterialKind& kind, bool lookOnly) {
    std::vector<std::string> keys;
    if (!lookOnly) keys = {"type", "texture"};
    for (const MaterialParameter& p : kind.parameters)
        if (p.look || !lookOnly) keys.push_back(p.spec.name);
    keys.push_back("emission");
    return keys;
}
}  // namespace

void Loader::readParameter(Material& m, const MaterialParameter& p, const json& j,
                           const std::string& where) const {
    const std::string& key = p.spec.name;
    if (!j.contains(key)) return;
    if (p.colour)
        m.*p.colour = m_reader.vec3(j[key], where + "/" + key, p.spec.min, p.spec.max);
    else
        m.*p.number = m_reader.number(j[key], where + "/" + key, p.spec.min, p.spec.max);
    if (p.given) m.*p.given = true;
}

Material Loader::readMaterial(const std::string& name, const json& j, const std::string& where) {
    // Keys no kind takes first (today's message lists them all), then the kind's own.
    std::vector<std::string> anyKind;
    for (const MaterialKind* kind : kMaterialKinds)
        if (kind->inSceneJson)
            for (const std::string& key : materialKeys(*kind, false))
                if (std::find(anyKind.begin(), anyKind.end(), key) == anyKind.end())
                    anyKind.push_back(key);
    m_reader.requireObject(j, where, anyKind);
    Material m;
    m.name = name;
    if (!j.contains("type")) m_reader.fail(where + "/type", "missing required key 'type'");
    const std::string type = m_reader.string(j["type"], where + "/type");
    const MaterialKind* kind = nullptr;
    for (std::size_t i = 0; i < std::size(kMaterialKinds) && !kind; ++i)
        if (kMaterialKinds[i]->inSceneJson && type == kMaterialKinds[i]->name) {
            kind = kMaterialKinds[i];
            m.type = MaterialType(int(i));
        }
    if (!kind)
        m_reader.fail(where + "/type", "unknown material type '" + type + "' (expected " +
                                           sceneJsonTypeList() + ")");
    m_reader.requireObject(j, where, materialKeys(*kind, false));
    // Each parameter of the kind: its default, or the value given.
    for (const MaterialParameter& p : kind->parameters) {
        if (p.colour)
            m.*p.colour = Vec3{1.0f, 1.0f, 1.0f} * float(p.spec.defaultValue);
        else
            m.*p.number = float(p.spec.defaultValue);
        if (p.partner && j.contains(p.spec.name) != j.contains(p.partner))
            m_reader.fail(where, type + " '" + p.spec.name + "' and '" + p.partner +
                                     "' must be given together");
        readParameter(m, p, j, where);
    }
    if (j.contains("texture"))
        m.texture =
            loadTexture(m_reader.string(j["texture"], where + "/texture"), where + "/texture");
    if (j.contains("emission")) m.emission = radiance(j["emission"], where + "/emission");
    return m;
}

void Loader::applyLookEdits(Material& m, const json& j, const std::string& where) const {
    // The look panel's parameters of the material's kind, over the asset's own factors.
    const MaterialKind& kind = materialKind(m.type);
    m_reader.requireObject(j, where, materialKeys(kind, true));
    for (const MaterialParameter& p : kind.parameters)
        if (p.look) readParameter(m, p, j, where);
    if (j.contains("emission")) m.emission = radiance(j["emission"], where + "/emission");
}

void Loader::readEnvironment(const json& j, const std::string& where) {
    m_reader.requireObject(j, where, {"image", "color", "scale", "rotate"});
    EnvironmentDesc& env = m_scene.environment;
    if (j.contains("image") == j.contains("color"))
        m_reader.fail(where, "expected exactly one of 'image' or 'color'");
    if (j.contains("scale")) env.scale = m_reader.number(j["scale"], where + "/scale", 0.0, 1e30);
    if (j.contains("rotate"))
        env.rotateDeg = m_reader.number(j["rotate"], where + "/rotate", -1e6, 1e6);
    if (j.contains("color")) {
        env.kind = EnvironmentDesc::Kind::Constant;
        env.baseColor = radiance(j["color"], where + "/color");
        env.color = env.baseColor * env.scale;
        if (maxAbsComponent(env.color) > kMaxRadiance)
            m_reader.fail(where + "/scale", "colour × scale exceeds the largest radiance, " +
                                                std::to_string(kMaxRadiance));
        // A black environment is no environment: nothing to sample.
        if (isBlack(env.color)) env.kind = EnvironmentDesc::Kind::None;
        return;
    }
    const fs::path rel = m_reader.string(j["image"], where + "/image");
    env.path = rel.is_absolute() ? rel : m_dir / rel;
    m_scene.addInput(env.path);
    env.source =
        readLinearRgb(env.path, 1.0f, "environment image", m_reader.file(), where + "/image");
    env.image = scaledRgb(env.source, env.scale, "environment image", env.path, where + "/image");
    env.kind = EnvironmentDesc::Kind::Image;
}

TransformDesc Loader::readTransform(const json& j, const std::string& where,
                                    const TransformDesc& base) {
    m_reader.requireObject(j, where, {"translate", "rotate", "scale"});
    TransformDesc desc = base;
    if (j.contains("scale")) {
        if (j["scale"].is_number()) {
            const float s = m_reader.number(j["scale"], where + "/scale", -1e15, 1e15);
            desc.scale = {s, s, s};
        } else {
            desc.scale = m_reader.vec3(j["scale"], where + "/scale", -1e15, 1e15);
        }
        for (int c = 0; c < 3; ++c)
            if (!(std::fabs(desc.scale[c]) >= 1e-15f))
                m_reader.fail(where + "/scale",
                              "scale factors must be non-zero with a magnitude in [1e-15, 1e15]");
    }
    if (j.contains("rotate")) {
        const json& rot = j["rotate"];
        if (!rot.is_array() || rot.size() != 2)
            m_reader.fail(where + "/rotate", "expected [degrees, [x, y, z]]");
        desc.degrees = m_reader.number(rot[0], where + "/rotate/0", -1e6, 1e6);
        const Vec3 axis = m_reader.vec3(rot[1], where + "/rotate/1");
        if (length(axis) == 0.0f) m_reader.fail(where + "/rotate/1", "rotation axis is zero");
        desc.axis = normalize(axis);
    }
    if (j.contains("translate"))
        desc.translate =
            m_reader.vec3(j["translate"], where + "/translate", -kMaxCoordinate, kMaxCoordinate);
    return desc;
}

std::vector<std::string> Loader::shapeKeys() {
    std::vector<std::string> keys;
    for (const AssetFormat* format : assetFormatRegistry()) keys.push_back(format->key);
    keys.push_back("material");
    for (const AssetFormat* format : assetFormatRegistry())
        for (const std::string& key : format->shapeKeys)
            if (std::find(keys.begin(), keys.end(), key) == keys.end()) keys.push_back(key);
    keys.push_back("transform");
    keys.push_back("motion");
    return keys;
}

void Loader::checkAsset(const AssetFormat& format, const AssetShape& shape) const {
    const std::string place = shape.where + "/" + format.key;
    requireRegularFile(shape.file, format.fileWord, format.expected, m_reader.file().string(),
                       place);
    // Within the memory limit, predicted before the format's reader allocates anything.
    if (m_memoryLimit > 0 && format.predictLoad)
        checkLoadMemory(format.predictLoad(shape.file), heldBytes(m_scene), m_memoryLimit,
                        shape.file, m_reader.file(), place);
}

int Loader::sceneMaterial(const json& value, const std::string& place) const {
    const std::string name = m_reader.string(value, place);
    const int index = materialIndex(name);
    if (index < 0) m_reader.fail(place, "material '" + name + "' is not defined in /materials");
    return index;
}

void Loader::readShape(const json& j, const std::string& where, int shapeIndex) {
    m_reader.requireObject(j, where, shapeKeys());
    // The shape's format: the one whose key it has.
    const AssetFormat* format = nullptr;
    int formats = 0;
    std::string choices;
    const auto& registry = assetFormatRegistry();
    for (std::size_t i = 0; i < registry.size(); ++i) {
        if (j.contains(registry[i]->key)) format = registry[i], ++formats;
        choices += std::string(i == 0                     ? ""
                               : i + 1 == registry.size() ? " or "
                                                          : ", ") +
                   "'" + registry[i]->key + "' (" + registry[i]->shapeDescription + ")";
    }
    if (formats != 1) m_reader.fail(where, "expected exactly one of " + choices);
    const std::string& key = format->key;
    const fs::path rel = m_reader.string(j[key], where + "/" + key);
    const fs::path filePath = rel.is_absolute() ? rel : m_dir / rel;
    // A key of another format's shapes that this format does not take: refused with its reason,
    // else in general words.
    for (const AssetFormat* other : registry)
        for (const std::string& extra : other->shapeKeys) {
            const auto& own = format->shapeKeys;
            if (!j.contains(extra) || std::find(own.begin(), own.end(), extra) != own.end())
                continue;
            std::string why = "'" + extra + "' does not apply to " + format->shapeDescription;
            for (const auto& [refused, reason] : format->refusedKeys)
                if (refused == extra) why = reason;
            m_reader.fail(where + "/" + extra, why);
        }
    const TransformDesc start = j.contains("transform")
                                    ? readTransform(j["transform"], where + "/transform", {})
                                    : TransformDesc{};
    // "motion" is the transform at shutter close; keys it omits keep their "transform" value.
    bool moving = false;
    TransformDesc end = start;
    if (j.contains("motion")) {
        end = readTransform(j["motion"], where + "/motion", start);
        for (int c = 0; c < 3; ++c)
            if ((start.scale[c] > 0.0f) != (end.scale[c] > 0.0f))
                m_reader.fail(
                    where + "/motion/scale",
                    "scale must keep its sign over the shutter (it would pass through 0)");
        moving = length(end.translate - start.translate) > 0.0f ||
                 length(end.scale - start.scale) > 0.0f || end.degrees != start.degrees ||
                 (start.degrees != 0.0f && length(end.axis - start.axis) > 0.0f);
    }
    AssetShape shape{j, where, shapeIndex, filePath, {toAffine(start)}, moving, -1};
    if (j.contains("material")) shape.material = sceneMaterial(j["material"], where + "/material");
    if (moving) {
        const TransformMotion motion(start, end);
        const int steps = motion.timeSteps();
        shape.poses.clear();
        for (int k = 0; k < steps; ++k)
            shape.poses.push_back(motion.at(float(k) / float(steps - 1)));
    }
    checkAsset(*format, shape);
    format->import(*this, shape);
}

void Loader::placeMesh(std::uint32_t meshIndex, const AssetShape& shape) {
    Instance instance;
    instance.transform = shape.poses.front();
    instance.identity = isIdentity(instance.transform);
    instance.material = shape.material;
    instance.name = shape.where;
    instance.mesh = meshIndex;
    const Mesh& mesh = m_scene.meshes[instance.mesh];
    if (mesh.triangleCount() == 0) return;
    if (shape.moving) {
        for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
            const int m = shape.material >= 0 ? shape.material : int(mesh.materialOf(t));
            if (m_scene.materials[std::size_t(m)].emissive())
                m_reader.fail(shape.where + "/motion",
                              "a moving shape must not be emissive (area lights are static)");
        }
        instance.motion = std::int32_t(m_scene.motions.size());
        instance.identity = false;
        m_scene.motions.push_back({shape.poses});
    }
    m_scene.instances.push_back(std::move(instance));
}

void Loader::useAssetCamera(std::size_t index) {
    m_scene.camera = cameraOf(m_scene.assetCameras.at(index));
}

void Loader::loadAsset(const fs::path& file) {
    // The scene a newcomer's first command gets: the asset, its camera or one that frames it,
    // and light to see it by.
    json doc;
    const AssetFormat* format = findAssetFormat(file);
    GLINT_CHECK(format);
    doc["shapes"] = json::array({json{{format->key, file.filename().string()}}});
    readShape(doc["shapes"][0], "/shapes/0", 0);
    m_scene.finishMeshes();
    computeBounds(m_scene);
    m_scene.width = 640;
    m_scene.height = 480;
    // An asset too small for float (1e-30 across) would render as an empty frame: the camera
    // that frames it, in double, is held to the rule of a scene.json camera, whichever camera is
    // used.
    const Vec3 lo = m_scene.bounds.lo, hi = m_scene.bounds.hi;
    {
        double across = 0.0;
        for (int c = 0; c < 3; ++c) across = std::max(across, double(hi[c]) - double(lo[c]));
        const double framing = 0.5 * across / std::sin(20.0 * kPi / 180.0);
        if (const std::string problem = viewDistanceProblem(framing); !problem.empty()) {
            std::ostringstream msg;
            msg << "the asset is " << across
                << " across, too small to render (the camera framing it: " << problem << ")";
            throw Error(ErrorKind::Format, msg.str(), file.string());
        }
    }
    if (!m_scene.assetCameras.empty()) {
        useAssetCamera(0);
        const float aspect = m_scene.assetCameras.front().aspectRatio;
        if (aspect > 0.0f) m_scene.height = std::clamp(int(std::lround(640.0f / aspect)), 1, 16384);
    } else {
        // A camera on +z of the bounding sphere's centre, looking down −z, at the distance at
        // which the sphere fits the narrower field of view.
        const Vec3 centre = (lo + hi) * 0.5f;
        const float radius =
            std::max(0.5f * length(hi - lo), 1e-6f * std::max(1.0f, maxAbsComponent(centre)));
        const float fovY = 40.0f;
        const float halfY = 0.5f * fovY * kPi / 180.0f;
        const float halfX =
            std::atan(std::tan(halfY) * float(m_scene.width) / float(m_scene.height));
        const float distance = radius / std::sin(std::min(halfX, halfY));
        m_scene.camera = CameraDesc{};
        m_scene.camera.position = centre + Vec3{0.0f, 0.0f, distance};
        m_scene.camera.lookAt = centre;
        m_scene.camera.fovY = fovY;
    }
    // Light to see it by unless it brings lamps: emissive materials alone are mostly details (a
    // helmet's visor lights, a screen), not what lights the asset.
    const bool lit = !m_scene.punctualLights.empty();
    if (!lit) {
        m_scene.environment.kind = EnvironmentDesc::Kind::Constant;
        m_scene.environment.baseColor = m_scene.environment.color = {1.0f, 1.0f, 1.0f};
    }
    for (Material& m : m_scene.materials) m.deriveEmissionLook();

    // The equivalent scene.json, so that the scene can be saved and reloaded as it is.
    auto array = [](const Vec3& v) { return json::array({v.x, v.y, v.z}); };
    const CameraDesc& cam = m_scene.camera;
    doc["film"] = {{"width", m_scene.width}, {"height", m_scene.height}};
    doc["camera"] = {{"position", array(cam.position)},
                     {"lookAt", array(cam.lookAt)},
                     {"up", array(cam.up)},
                     {"fovY", cam.fovY}};
    if (!lit) doc["environment"] = {{"color", json::array({1, 1, 1})}};
    m_scene.sourceJson = doc.dump(2);
}

void computeBounds(SceneData& scene) {
    // One pass over every vertex of every instance: the box at shutter open and the box of
    // every pose, whose largest side is the scene's scale for scale-free ray offsets
    // (vecmath.h, rayEpsilon).
    Box open, swept;
    bool any = false;
    for (const Instance& inst : scene.instances) {
        const Mesh& mesh = scene.meshes[inst.mesh];
        any = any || !mesh.positions.empty();
        if (inst.motion >= 0) {
            for (const Vec3& p : mesh.positions) open.grow(inst.transform.point(p));
            for (const Affine& step : scene.motions[std::size_t(inst.motion)].steps)
                for (const Vec3& p : mesh.positions) swept.grow(step.point(p));
        } else if (inst.identity) {
            for (const Vec3& p : mesh.positions) open.grow(p), swept.grow(p);
        } else {
            for (const Vec3& q : mesh.positions) {
                const Vec3 p = inst.transform.point(q);
                open.grow(p), swept.grow(p);
            }
        }
    }
    scene.bounds = open;
    if (any) {
        const float extent = maxAbsComponent(swept.hi - swept.lo);
        scene.extent = extent > 0.0f ? extent : std::max(maxAbsComponent(swept.hi), 1e-30f);
    }
}

// Textures and environment images: read through glint::readImage, linearised, checked; the
// loader's texture table (Loader::loadTexture): untiled files and embedded images held in
// memory, tiled files opened in the scene's TextureStore.

Image scaledRgb(const Image& source, float scale, const std::string& what,
                const std::filesystem::path& sceneFile, const std::string& where) {
    if (source.width() < 1 || source.height() < 1)
        throw Error(ErrorKind::Format, what + " is empty", sceneFile.string(), where);
    Image out(source.width(), source.height(), 3);
    for (int y = 0; y < source.height(); ++y)
        for (int x = 0; x < source.width(); ++x)
            for (int c = 0; c < 3; ++c) {
                const float v = source(x, y, source.channels() >= 3 ? c : 0) * scale;
                // A NaN/Inf/negative value would poison every path that reaches it.
                if (!std::isfinite(v) || v < 0.0f || v > kMaxRadiance)
                    throw Error(ErrorKind::Format,
                                what + " has a negative, non-finite or too large (above " +
                                    std::to_string(kMaxRadiance) + ") value at pixel (" +
                                    std::to_string(x) + ", " + std::to_string(y) + ")" +
                                    (scale != 1.0f ? " after scaling by " + std::to_string(scale)
                                                   : std::string()),
                                sceneFile.string(), where);
                out(x, y, c) = v;
            }
    return out;
}

Image readLinearRgb(const std::filesystem::path& image, float scale, const std::string& what,
                    const std::filesystem::path& sceneFile, const std::string& where) {
    requireRegularFile(image, what, "an image file", sceneFile.string(), where);
    const Image raw = readImage(image, true);
    try {
        return scaledRgb(raw, scale, what, sceneFile, where);
    } catch (const Error& e) {
        // Name the image itself as the file.
        throw Error(e.kind(), e.message(), image.string(), where);
    }
}

Image textureRgba(const Image& raw, const std::string& what, const std::filesystem::path& file,
                  const std::string& where) {
    if (raw.width() < 1 || raw.height() < 1)
        throw Error(ErrorKind::Format, what + " is empty", file.string(), where);
    const int n = raw.channels();
    // Grey, grey + alpha, RGB or RGBA → RGBA (alpha 1 where there is none).
    const int rgb[3] = {0, n >= 3 ? 1 : 0, n >= 3 ? 2 : 0};
    const int alpha = n == 2 ? 1 : (n >= 4 ? 3 : -1);
    Image out(raw.width(), raw.height(), 4);
    for (int y = 0; y < raw.height(); ++y)
        for (int x = 0; x < raw.width(); ++x) {
            for (int c = 0; c < 4; ++c) {
                const float v = c < 3 ? raw(x, y, rgb[c]) : (alpha >= 0 ? raw(x, y, alpha) : 1.0f);
                // A NaN/Inf/negative value would poison every path that reaches it.
                if (!std::isfinite(v) || v < 0.0f || v > kMaxRadiance)
                    throw Error(ErrorKind::Format,
                                what + " has a negative, non-finite or too large (above " +
                                    std::to_string(kMaxRadiance) + ") value at pixel (" +
                                    std::to_string(x) + ", " + std::to_string(y) + ")",
                                file.string(), where);
                out(x, y, c) = v;
            }
        }
    return out;
}

int Loader::loadTexture(const fs::path& path, const std::string& where) {
    Texture source;
    source.path = path.is_absolute() ? path : m_dir / path;
    return loadTexture(source, where);
}

int Loader::loadTexture(const Texture& source, const std::string& where) {
    const auto key = std::tuple{source.path, int(source.use), int(source.wrapS), int(source.wrapT)};
    const auto it = m_textureIndex.find(key);
    if (it != m_textureIndex.end()) return it->second;
    Texture tex = source;
    const bool linearize = source.use == TextureUse::Color;
    if (source.bytes) {
        try {
            tex.image = textureRgba(readImage(*source.bytes, source.path.string(), linearize),
                                    "texture", source.path, where);
        } catch (const Error& e) {
            throw Error(e.kind(), e.message(), source.path.string(),
                        where + (e.where().empty() ? "" : " (" + e.where() + ")"));
        }
    } else {
        requireRegularFile(source.path, "texture", "an image file", m_reader.file().string(),
                           where);
        // A PNG, a JPEG or a scanline EXR is untiled by its header; of other formats only the
        // store (OpenImageIO, in the module its first file loads) can tell.
        const int file = storedInTiles(source.path) == false
                             ? -1
                             : openTextureFile(source.path, linearize, where);
        m_scene.addInput(source.path);
        if (file < 0 || !m_scene.textureStore->info(file).tiled) {
            // An untiled file has no random access: it is read whole, decoded to linear and
            // looked up in memory, exactly and fast, as an embedded image is (docs/assets.md,
            // "Textures").
            tex.image =
                textureRgba(readImage(source.path, linearize), "texture", source.path, where);
        } else {
            tex.file = file;
            tex.store = m_scene.textureStore;
            tex.decodeSrgb = linearize && m_scene.textureStore->info(tex.file).srgb;
            tex.contentHash = m_scene.textureStore->contentHash(tex.file);
            // Reading the resident levels reads the file's small MIP levels: a file damaged
            // there fails now.
            tex.readLevels();
            // The store's tile cache makes room for the resident levels.
            m_scene.textureStore->addResidentBytes(tex.levels.residentBytes());
            m_scene.textureStore->throwIfFailed();
        }
    }
    m_scene.textures.push_back(std::move(tex));
    m_textureIndex[key] = int(m_scene.textures.size()) - 1;
    return int(m_scene.textures.size()) - 1;
}

int Loader::openTextureFile(const fs::path& path, bool linearize, const std::string& where) {
    if (!m_scene.textureStore) m_scene.textureStore = std::make_shared<TextureStore>();
    TextureStore& store = *m_scene.textureStore;
    checkImageFile(path);  // before OpenImageIO allocates what a damaged header claims
    int file = -1;
    try {
        file = store.open(path, m_reader.file(), where);
    } catch (const Error&) {
        // glint::readImage says what is wrong with the file as every other image reader of
        // Glint does; OIIO's own reason when it reads what the TextureSystem could not.
        (void)readImage(path, linearize);
        throw;
    }
    return file;
}

}  // namespace detail

namespace {

/// Parses scene JSON text as the file `path`; `read` says the text is that file's (an input).
Scene readScene(const std::string& jsonText, const fs::path& path, bool read,
                std::uint64_t memoryLimit) {
    json root;
    try {
        root = json::parse(jsonText, nullptr, true, false);
    } catch (const json::exception& e) {
        detail::throwMalformedJson(e, jsonText, path.string());
    }
    auto data = std::make_unique<detail::SceneData>();
    data->path = path;
    data->sourceJson = jsonText;
    if (read) data->addInput(path);
    detail::Loader loader(path, *data, memoryLimit);
    loader.load(root);
    return Scene(std::move(data));
}

}  // namespace

Scene parseScene(const std::string& jsonText, const fs::path& path, std::uint64_t memoryLimit) {
    return readScene(jsonText, path, false, memoryLimit);
}

Scene loadScene(const fs::path& path, std::uint64_t memoryLimit) {
    std::error_code ec;
    if (detail::findAssetFormat(path) && fs::is_regular_file(path, ec)) {
        auto data = std::make_unique<detail::SceneData>();
        data->path = path;
        detail::Loader loader(path, *data, memoryLimit);
        loader.loadAsset(path);
        return Scene(std::move(data));
    }
    if (fs::is_directory(path, ec))
        throw Error(ErrorKind::Io, "is a folder, expected a scene.json file", path.string());
    if (!fs::exists(path, ec))
        throw Error(ErrorKind::Io, "file does not exist, expected a scene.json file",
                    path.string());
    // A device or a pipe (/dev/zero) would be read without end.
    if (!fs::is_regular_file(path, ec))
        throw Error(ErrorKind::Io,
                    "is not a regular file (a device or a pipe), expected a scene.json file",
                    path.string());
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(ErrorKind::Io, "cannot open scene file", path.string());
    std::ostringstream text;
    text << in.rdbuf();
    return readScene(text.str(), path, true, memoryLimit);
}

}  // namespace glint::render

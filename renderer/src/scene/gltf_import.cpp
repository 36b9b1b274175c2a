// glTF 2.0 import through tinygltf: the extensions an asset requires, the default scene's node
// hierarchy (TRS or matrix transforms), the placing of meshes shared between the nodes that use
// them, perspective cameras and KHR_lights_punctual lights. The file is read by gltf_file.cpp,
// meshes are converted by gltf_mesh.cpp, materials and textures by gltf_material.cpp.
#include "scene/gltf_import.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <optional>
#include <sstream>
#include <string>

#include "glint/image/error.h"
#include "scene/camera.h"
#include "scene/gltf_buffers.h"
#include "scene/gltf_document.h"
#include "scene/gltf_file.h"
#include "scene/input_file.h"
#include "scene/load_memory.h"
#include "scene/tangent_frames.h"

namespace glint::render::detail {

namespace fs = std::filesystem;

namespace {

/// A row-major 3×4 affine matrix in double, for composing the node hierarchy.
struct Matrix34 {
    double r[3][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}};
};

Matrix34 operator*(const Matrix34& a, const Matrix34& b) {
    Matrix34 c;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 4; ++j) {
            double s = j == 3 ? a.r[i][3] : 0.0;
            for (int k = 0; k < 3; ++k) s += a.r[i][k] * b.r[k][j];
            c.r[i][j] = s;
        }
    return c;
}

/// A node's local transform: its matrix (column-major, must be affine) or T · R · S.
Matrix34 localTransform(const tinygltf::Node& n, const std::string& place,
                        const GltfAccessors& acc) {
    Matrix34 out;
    auto finite = [&](const std::vector<double>& v, const char* key) {
        for (double x : v)
            if (!std::isfinite(x)) acc.fail(place + "." + key, "holds a non-finite number");
    };
    if (!n.matrix.empty()) {
        if (n.matrix.size() != 16)
            acc.fail(place + ".matrix",
                     "has " + std::to_string(n.matrix.size()) + " numbers, expected 16");
        finite(n.matrix, "matrix");
        for (int row = 0; row < 3; ++row)
            for (int col = 0; col < 4; ++col)
                out.r[row][col] = n.matrix[std::size_t(col * 4 + row)];
        if (std::abs(n.matrix[3]) > 1e-6 || std::abs(n.matrix[7]) > 1e-6 ||
            std::abs(n.matrix[11]) > 1e-6 || std::abs(n.matrix[15] - 1.0) > 1e-6)
            acc.fail(place + ".matrix", "is not affine (its last row is not 0 0 0 1)");
        return out;
    }
    auto sized = [&](const std::vector<double>& v, std::size_t n3, const char* key) {
        if (!v.empty() && v.size() != n3)
            acc.fail(place + "." + key, "has " + std::to_string(v.size()) + " numbers, expected " +
                                            std::to_string(n3));
        finite(v, key);
    };
    sized(n.translation, 3, "translation");
    sized(n.rotation, 4, "rotation");
    sized(n.scale, 3, "scale");
    double q[4] = {0, 0, 0, 1};  // x, y, z, w
    if (!n.rotation.empty()) {
        const double len = std::sqrt(n.rotation[0] * n.rotation[0] + n.rotation[1] * n.rotation[1] +
                                     n.rotation[2] * n.rotation[2] + n.rotation[3] * n.rotation[3]);
        if (!(len > 0.0)) acc.fail(place + ".rotation", "is the zero quaternion");
        for (int i = 0; i < 4; ++i) q[i] = n.rotation[std::size_t(i)] / len;
    }
    const double x = q[0], y = q[1], z = q[2], w = q[3];
    // The rotation matrix of a unit quaternion (Shoemake 1985).
    const double rot[3][3] = {{1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)},
                              {2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)},
                              {2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)}};
    const double s[3] = {n.scale.empty() ? 1.0 : n.scale[0], n.scale.empty() ? 1.0 : n.scale[1],
                         n.scale.empty() ? 1.0 : n.scale[2]};
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) out.r[i][j] = rot[i][j] * s[j];
        out.r[i][3] = n.translation.empty() ? 0.0 : n.translation[std::size_t(i)];
    }
    return out;
}

/// The extension object `name` of an extension map, or null.
const tinygltf::Value* extension(const tinygltf::ExtensionMap& map, const char* name) {
    const auto it = map.find(name);
    return it == map.end() || !it->second.IsObject() ? nullptr : &it->second;
}

}  // namespace

std::string decodeUri(const std::string& uri) {
    std::string out;
    for (std::size_t i = 0; i < uri.size(); ++i) {
        if (uri[i] == '%' && i + 2 < uri.size() &&
            std::isxdigit(static_cast<unsigned char>(uri[i + 1])) &&
            std::isxdigit(static_cast<unsigned char>(uri[i + 2]))) {
            out += char(std::stoi(uri.substr(i + 1, 2), nullptr, 16));
            i += 2;
        } else {
            out += uri[i];
        }
    }
    return out;
}

GltfImport::GltfImport(ImportContext& loader, const tinygltf::Model& model,
                       const GltfBuffers& buffers, fs::path file, const GltfOverrides& overrides,
                       std::string where)
    : m_loader(loader),
      m_scene(loader.scene()),
      m_model(model),
      m_buffers(buffers),
      m_file(std::move(file)),
      m_overrides(overrides),
      m_where(std::move(where)),
      m_accessors(model, buffers, m_file),
      m_meshes(model.meshes.size(), -1),
      m_materials(model.materials.size(), -1) {}

void GltfImport::warn(const std::string& text) {
    const std::string line = m_file.filename().string() + ": " + text;
    if (std::find(m_scene.warnings.begin(), m_scene.warnings.end(), line) == m_scene.warnings.end())
        m_scene.warnings.push_back(line);
}

void GltfImport::warnOnce(const std::string& key, const std::string& text) {
    if (m_warnedOnce.insert(key).second) warn(text);
}

void GltfImport::fail(const std::string& place, const std::string& what) const {
    m_accessors.fail(place, what);
}

std::string GltfImport::nodeName(int node) const {
    const std::string& name = m_model.nodes[std::size_t(node)].name;
    return name.empty() ? "nodes[" + std::to_string(node) + "]" : name;
}

void GltfImport::checkExtensions() {
    if (const auto unread = unreadRequiredExtension(m_model.extensionsRequired))
        fail("extensionsRequired[" + std::to_string(unread->first) + "]", unread->second);
    for (const std::string& name : m_model.extensionsUsed) {
        bool read = false;
        for (const char* e : kReadGltfExtensions) read = read || name == e;
        if (!read)
            warn("extension " + name + " is not read by Glint; the asset may look different");
    }
}

void GltfImport::importScene(const std::vector<Affine>& poses) {
    checkExtensions();
    // The shape's "materials" must name materials the asset has: a misspelt name would
    // otherwise be ignored without a word.
    for (const tinygltf::Material& m : m_model.materials) m_usedMaterialNames.insert(m.name);
    for (const auto& [name, index] : m_overrides.byName)
        if (!m_usedMaterialNames.count(name)) {
            std::string names;
            for (const std::string& n : m_usedMaterialNames)
                if (!n.empty()) names += (names.empty() ? "" : ", ") + n;
            m_loader.reader().fail(m_overrides.byNamePlace + "/" + name,
                                   m_file.filename().string() + " has no material '" + name +
                                       "' (it has: " + (names.empty() ? "none named" : names) +
                                       ")");
        }
    // "edits" likewise, by the names editName gives.
    std::set<std::string> editable{editName(-1)};
    for (std::size_t i = 0; i < m_model.materials.size(); ++i) editable.insert(editName(int(i)));
    for (const auto& [name, edit] : m_overrides.edits)
        if (!editable.count(name)) {
            std::string names;
            for (const std::string& n : editable) names += (names.empty() ? "" : ", ") + n;
            m_loader.reader().fail(m_overrides.editsPlace + "/" + name,
                                   m_file.filename().string() + " has no material '" + name +
                                       "' to edit (it has: " + names + ")");
        }
    if (!m_model.animations.empty())
        warn("animations are ignored (the nodes' rest pose is rendered)");
    // The default scene, else the first, else every root node.
    std::vector<int> roots;
    std::string scenePlace = "nodes";
    const int sceneIndex = m_model.defaultScene >= 0 ? m_model.defaultScene
                           : m_model.scenes.empty()  ? -1
                                                     : 0;
    if (sceneIndex >= int(m_model.scenes.size()))
        fail("scene", "names scenes[" + std::to_string(sceneIndex) + "], but the asset has " +
                          std::to_string(m_model.scenes.size()));
    if (sceneIndex >= 0) {
        roots = m_model.scenes[std::size_t(sceneIndex)].nodes;
        scenePlace = "scenes[" + std::to_string(sceneIndex) + "]";
    } else {
        std::vector<bool> child(m_model.nodes.size(), false);
        for (const tinygltf::Node& n : m_model.nodes)
            for (int c : n.children)
                if (c >= 0 && std::size_t(c) < child.size()) child[std::size_t(c)] = true;
        for (std::size_t i = 0; i < child.size(); ++i)
            if (!child[i]) roots.push_back(int(i));
    }

    // Walk the hierarchy depth first; a node reached twice (a cycle, or two parents) is invalid.
    std::vector<bool> visited(m_model.nodes.size(), false);
    struct Item {
        int node;
        Matrix34 parent;
        std::string place;
    };
    std::vector<Item> stack;
    for (std::size_t i = roots.size(); i-- > 0;)
        stack.push_back({roots[i], Matrix34{}, scenePlace + ".nodes[" + std::to_string(i) + "]"});
    const std::size_t trianglesBefore = m_scene.triangleCount();
    while (!stack.empty()) {
        const Item item = std::move(stack.back());
        stack.pop_back();
        if (item.node < 0 || std::size_t(item.node) >= m_model.nodes.size())
            fail(item.place, "names nodes[" + std::to_string(item.node) + "], but the asset has " +
                                 std::to_string(m_model.nodes.size()));
        const std::string place = "nodes[" + std::to_string(item.node) + "]";
        if (visited[std::size_t(item.node)])
            fail(place, "is reached twice from the scene (a cycle, or a node with two parents)");
        visited[std::size_t(item.node)] = true;
        const tinygltf::Node& node = m_model.nodes[std::size_t(item.node)];
        const Matrix34 world = item.parent * localTransform(node, place, m_accessors);
        for (std::size_t c = node.children.size(); c-- > 0;)
            stack.push_back(
                {node.children[c], world, place + ".children[" + std::to_string(c) + "]"});

        Affine nodeAffine;
        if (!affineFromMatrix(world.r, nodeAffine)) {
            if (node.mesh >= 0 || node.camera >= 0 || !node.extensions.empty())
                warn(place + " (" + nodeName(item.node) +
                     ") has a singular transform (a zero scale): what it holds is not rendered");
            continue;
        }
        if (node.skin >= 0) warn("skins are ignored (skinned meshes are rendered unposed)");
        if (node.mesh >= 0) {
            if (std::size_t(node.mesh) >= m_model.meshes.size())
                fail(place + ".mesh", "names meshes[" + std::to_string(node.mesh) +
                                          "], but the asset has " +
                                          std::to_string(m_model.meshes.size()));
            const int glintMesh = mesh(node.mesh);
            if (glintMesh >= 0) {
                std::vector<Affine> placed;
                for (const Affine& pose : poses) placed.push_back(compose(pose, nodeAffine));
                placeMesh(item.node, glintMesh, placed);
            }
        }
        const Affine atOpen = compose(poses.front(), nodeAffine);
        if (node.camera >= 0) addCamera(item.node, atOpen);
        if (extension(node.extensions, "KHR_lights_punctual")) addLight(item.node, atOpen);
    }
    if (m_scene.triangleCount() == trianglesBefore)
        fail(m_model.meshes.empty() ? "meshes" : scenePlace,
             m_model.meshes.empty() ? "the asset has no mesh"
             : m_skippedPrimitives > 0
                 ? "no node of the scene places a triangle mesh (the primitives it places are "
                   "points or lines, which Glint does not render)"
                 : "no node of the scene places a triangle mesh");
}

void GltfImport::placeMesh(int node, int glintMesh, const std::vector<Affine>& poses) {
    const Mesh& mesh = m_scene.meshes[std::size_t(glintMesh)];
    // Every vertex in every pose within the coordinate range: the mesh's bounding box corners
    // first (|affine| is convex, so the box's extremes are at its corners), vertex by vertex
    // only when a corner is out, to name the vertex.
    Vec3 lo = mesh.positions.front(), hi = lo;
    for (const Vec3& p : mesh.positions)
        for (int c = 0; c < 3; ++c) lo[c] = std::min(lo[c], p[c]), hi[c] = std::max(hi[c], p[c]);
    for (const Affine& pose : poses) {
        bool inside = true;
        for (int k = 0; k < 8 && inside; ++k) {
            const Vec3 corner{(k & 1) ? hi.x : lo.x, (k & 2) ? hi.y : lo.y, (k & 4) ? hi.z : lo.z};
            const Vec3 w = pose.point(corner);
            inside = isFinite(w) && maxAbsComponent(w) <= kMaxCoordinate;
        }
        if (inside) continue;
        for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
            const Vec3 w = pose.point(mesh.positions[v]);
            if (isFinite(w) && maxAbsComponent(w) <= kMaxCoordinate) continue;
            const Vec3& p = mesh.positions[v];
            std::ostringstream msg;
            msg << "vertex " << v << " (" << p.x << ", " << p.y << ", " << p.z << ") of "
                << mesh.name << " lies beyond " << kMaxCoordinate
                << " (the largest coordinate) after the node's transform and that of " << m_where;
            if (poses.size() > 1) msg << " during its motion";
            fail("nodes[" + std::to_string(node) + "]", msg.str());
        }
    }

    Instance instance;
    instance.mesh = std::uint32_t(glintMesh);
    instance.transform = poses.front();
    instance.identity = isIdentity(instance.transform);
    instance.material = m_overrides.material;
    instance.name = m_where + " " + m_file.filename().string() + " " + nodeName(node);
    // Emissive triangles are area lights: static, with some area.
    double emissiveArea = 0.0;
    bool anyEmissive = false;
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
        const int m = m_overrides.material >= 0 ? m_overrides.material : int(mesh.materialOf(t));
        if (!m_scene.materials[std::size_t(m)].emissive()) continue;
        anyEmissive = true;
        const std::uint32_t* idx = &mesh.indices[3 * t];
        emissiveArea += triangleArea(instance.transform.point(mesh.positions[idx[0]]),
                                     instance.transform.point(mesh.positions[idx[1]]),
                                     instance.transform.point(mesh.positions[idx[2]]));
    }
    const std::string place = "nodes[" + std::to_string(node) + "]";
    if (anyEmissive && poses.size() > 1)
        m_loader.reader().fail(m_where + "/motion",
                               "a moving shape must not be emissive (area lights are static): " +
                                   place + " of " + m_file.filename().string() + " emits");
    if (anyEmissive && !(emissiveArea > 0.0))
        fail(place, "its emissive triangles have zero total area (zero-area light)");
    if (poses.size() > 1) {
        instance.motion = std::int32_t(m_scene.motions.size());
        instance.identity = false;
        m_scene.motions.push_back({poses});
    }
    m_scene.instances.push_back(std::move(instance));
    ++m_instances;
}

void GltfImport::addCamera(int node, const Affine& world) {
    const int index = m_model.nodes[std::size_t(node)].camera;
    const std::string place = "cameras[" + std::to_string(index) + "]";
    if (std::size_t(index) >= m_model.cameras.size())
        fail("nodes[" + std::to_string(node) + "].camera",
             "names " + place + ", but the asset has " + std::to_string(m_model.cameras.size()));
    const tinygltf::Camera& cam = m_model.cameras[std::size_t(index)];
    if (cam.type != "perspective") {
        warn(place + " is " + (cam.type.empty() ? "untyped" : cam.type) +
             "; Glint reads perspective cameras only: skipped");
        return;
    }
    const double yfov = cam.perspective.yfov;
    if (!(yfov > 0.0 && yfov < kPi))
        fail(place + ".perspective.yfov",
             "is " + std::to_string(yfov) + ", expected (0, pi) radians");
    // 0: none given (gltf_document.cpp refuses a 0, or any ratio out of range, that is written).
    const double aspect = cam.perspective.aspectRatio;
    GLINT_CHECK(aspect == 0.0 || (aspect >= kMinGltfAspectRatio && aspect <= kMaxGltfAspectRatio));
    AssetCamera c;
    const std::string& nodeLabel = m_model.nodes[std::size_t(node)].name;
    c.name = !nodeLabel.empty() ? nodeLabel : !cam.name.empty() ? cam.name : place;
    c.position = world.point({0.0f, 0.0f, 0.0f});
    const Vec3 forward = world.vector({0.0f, 0.0f, -1.0f});
    const Vec3 up = world.vector({0.0f, 1.0f, 0.0f});
    if (!isFinite(c.position) || maxAbsComponent(c.position) > kMaxCoordinate)
        fail("nodes[" + std::to_string(node) + "]", "places " + place + " out of range");
    // The node's transform gives the view direction (its −z) and up (its +y) the camera needs.
    if (const auto fault = viewBasisFault({0.0f, 0.0f, 0.0f}, forward, up))
        fail("nodes[" + std::to_string(node) + "]",
             "places " + place + " with a degenerate orientation (" +
                 (fault->key == "up" ? "its +y" : "its -z") +
                 " from the node's transform: " + fault->reason + ")");
    // The look-at point at a distance that float keeps apart from the position.
    const float distance = std::max(1.0f, maxAbsComponent(c.position));
    c.lookAt = c.position + normalize(forward) * distance;
    c.up = normalize(up);
    c.fovY = float(yfov * 180.0 / kPi);
    c.aspectRatio = float(aspect);
    m_scene.assetCameras.push_back(std::move(c));
}

void GltfImport::addLight(int node, const Affine& world) {
    const tinygltf::Value& ext =
        *extension(m_model.nodes[std::size_t(node)].extensions, "KHR_lights_punctual");
    const std::string nodePlace =
        "nodes[" + std::to_string(node) + "].extensions.KHR_lights_punctual";
    if (!ext.Has("light") || !ext.Get("light").IsNumber()) fail(nodePlace, "has no light index");
    const int index = ext.Get("light").GetNumberAsInt();
    const std::string place =
        "extensions.KHR_lights_punctual.lights[" + std::to_string(index) + "]";
    if (index < 0 || std::size_t(index) >= m_model.lights.size())
        fail(nodePlace + ".light", "names " + place + ", but the asset has " +
                                       std::to_string(m_model.lights.size()) + " lights");
    const tinygltf::Light& gl = m_model.lights[std::size_t(index)];
    PunctualLight light;
    light.name = gl.name.empty() ? nodeName(node) : gl.name;
    if (gl.type == "point")
        light.kind = PunctualLight::Kind::Point;
    else if (gl.type == "spot")
        light.kind = PunctualLight::Kind::Spot;
    else if (gl.type == "directional")
        light.kind = PunctualLight::Kind::Directional;
    else
        fail(place + ".type", "is '" + gl.type + "', expected point, spot or directional");
    Vec3 color{1.0f, 1.0f, 1.0f};
    if (!gl.color.empty()) {
        if (gl.color.size() != 3) fail(place + ".color", "expected 3 numbers");
        for (int c = 0; c < 3; ++c) {
            const double v = gl.color[std::size_t(c)];
            if (!(v >= 0.0 && v <= 1.0)) fail(place + ".color", "expected numbers in [0, 1]");
            color[c] = float(v);
        }
    }
    // Photometric (candela, lux) to radiometric (W/sr, W/m²) as Blender's importer does.
    const double intensity = gl.intensity / kLumensPerWatt;
    if (!(gl.intensity >= 0.0) || !(intensity <= kMaxRadiance))
        fail(place + ".intensity", "is " + std::to_string(gl.intensity) + ", expected [0, " +
                                       std::to_string(kMaxRadiance * kLumensPerWatt) + "]");
    light.intensity = color * float(intensity);
    if (gl.range > 0.0) warn("the range of punctual lights is ignored (they fall off with 1/d²)");
    if (light.kind == PunctualLight::Kind::Spot) {
        const double inner = gl.spot.innerConeAngle, outer = gl.spot.outerConeAngle;
        if (!(inner >= 0.0 && inner < outer && outer <= kPi / 2 + 1e-6))
            fail(place + ".spot", "expected 0 <= innerConeAngle < outerConeAngle <= pi/2");
        light.cosInner = float(std::cos(inner));
        light.cosOuter = float(std::cos(outer));
    }
    light.position = world.point({0.0f, 0.0f, 0.0f});
    const Vec3 dir = world.vector({0.0f, 0.0f, -1.0f});
    if (!isFinite(light.position) || maxAbsComponent(light.position) > kMaxCoordinate ||
        !(length(dir) > 0.0f) || !isFinite(dir))
        fail("nodes[" + std::to_string(node) + "]",
             "places " + place + " out of range or with a degenerate direction");
    light.direction = normalize(dir);
    m_scene.punctualLights.push_back(std::move(light));
}

namespace {

/// Adds the glTF asset's default scene (its node hierarchy) as meshes placed by instances, each
/// glTF mesh one Glint mesh however many nodes use it; its materials (unless overridden),
/// cameras (SceneData::assetCameras) and KHR_lights_punctual lights. `poses` is the shape's
/// transform (or every time step of its motion); every vertex must stay within the coordinate
/// range in each. Errors name the asset and the glTF place.
void importGltf(ImportContext& loader, const fs::path& path, const std::vector<Affine>& poses,
                const GltfOverrides& overrides, const std::string& where) {
    // The buffers' mappings end with this function: after the asset is converted.
    tinygltf::Model model;
    GltfBuffers buffers;
    readGltfFile(path, model, buffers);
    SceneData& scene = loader.scene();
    scene.addInput(path);
    for (const fs::path& file : buffers.files()) scene.addInput(file);
    // Buffer files tinygltf read itself (beyond those Glint keeps open).
    for (std::size_t i = 0; i < model.buffers.size(); ++i) {
        const std::string& uri = model.buffers[i].uri;
        if (!buffers.fromFile(i) && !uri.empty() && uri.rfind("data:", 0) != 0)
            scene.addInput(path.parent_path() / uri);
    }
    GltfImport(loader, model, buffers, path, overrides, where).importScene(poses);
}

/// A glTF shape of scene.json: its "edits" and "materials" as overrides, then the asset.
void importGltfShape(ImportContext& loader, const AssetShape& shape) {
    const nlohmann::json& j = shape.object;
    const std::string& where = shape.where;
    GltfOverrides overrides;
    overrides.material = shape.material;
    overrides.byNamePlace = where + "/materials";
    overrides.editsPlace = where + "/edits";
    overrides.shape = shape.index;
    if (j.contains("edits")) {
        if (!j["edits"].is_object())
            loader.reader().fail(where + "/edits",
                                 "expected an object mapping glTF material names to their edits");
        for (const auto& item : j["edits"].items()) overrides.edits[item.key()] = item.value();
    }
    if (j.contains("materials")) {
        const nlohmann::json& map = j["materials"];
        if (!map.is_object())
            loader.reader().fail(
                where + "/materials",
                "expected an object mapping glTF material names to JSON materials");
        for (const auto& item : map.items())
            overrides.byName[item.key()] =
                loader.sceneMaterial(item.value(), where + "/materials/" + item.key());
    }
    importGltf(loader, shape.file, shape.poses, overrides, where);
}

}  // namespace

const AssetFormat& gltfAssetFormat() {
    static const AssetFormat format{
        .name = "glTF 2.0",
        .key = "gltf",
        .shapeDescription = "a glTF 2.0 .gltf or .glb asset",
        .fileWord = "glTF",
        .expected = "a .gltf or .glb file",
        .extensions = {".gltf", ".glb"},
        .shapeKeys = {"materials", "edits"},
        .refusedKeys = {},
        // Predicted from the JSON before anything is parsed.
        .predictLoad = predictGltfLoad,
        .import = importGltfShape,
    };
    return format;
}

}  // namespace glint::render::detail

#include "glint/render/scene.h"

#include "glint/image/error.h"
#include "materials/bsdf.h"
#include "scene/scene_data.h"

#include <algorithm>
#include <cmath>

namespace glint::render {

namespace detail {

const char* materialTypeName(MaterialType type) {
    return materialKind(type).name;
}

std::size_t Mesh::bytes() const {
    return positions.size() * sizeof(Vec3) + normals.size() * sizeof(Vec3) +
           tangents.size() * sizeof(Vec4) + uvs.size() * sizeof(Vec2) + uvs1.size() * sizeof(Vec2) +
           colors.size() * sizeof(Vec4) + indices.size() * sizeof(std::uint32_t) +
           materials.size() * sizeof(std::uint32_t) + faceNormals.size() * sizeof(Vec3);
}

std::size_t SceneData::triangleCount() const {
    std::size_t count = 0;
    for (const Instance& inst : instances) count += meshes[inst.mesh].triangleCount();
    return count;
}

TriangleView SceneData::posedTriangle(const Instance& inst, std::uint32_t prim, float time) const {
    const Mesh& mesh = meshes[inst.mesh];
    const std::uint32_t* idx = &mesh.indices[3 * std::size_t(prim)];
    TriangleView tri;
    tri.hasNormals = !mesh.normals.empty();
    if (inst.motion >= 0) {
        // Step k and fraction within it, as Embree interpolates between time steps.
        const InstanceMotion& motion = motions[std::size_t(inst.motion)];
        const int segments = int(motion.steps.size()) - 1;
        const float f = std::clamp(time, 0.0f, 1.0f) * float(segments);
        const int k = std::min(int(f), segments - 1);
        const float frac = f - float(k);
        const Affine& a = motion.steps[std::size_t(k)];
        const Affine& b = motion.steps[std::size_t(k) + 1];
        for (int v = 0; v < 3; ++v) {
            const Vec3& x = mesh.positions[idx[v]];
            tri.p[v] = lerp(frac, a.point(x), b.point(x));
            if (tri.hasNormals) {
                const Vec3& n = mesh.normals[idx[v]];
                tri.n[v] = lerp(frac, a.normal(n), b.normal(n));
            }
        }
    } else if (inst.identity) {
        return worldTriangle(mesh, prim);
    } else {
        for (int v = 0; v < 3; ++v) {
            tri.p[v] = inst.transform.point(mesh.positions[idx[v]]);
            if (tri.hasNormals) {
                const Vec3 n = inst.transform.normal(mesh.normals[idx[v]]);
                tri.n[v] = length(n) > 0.0f ? normalize(n) : Vec3{};
            }
        }
    }
    tri.ng = triangleNormal(tri.p[0], tri.p[1], tri.p[2]);
    return tri;
}

void SceneData::finishMeshes() {
    std::vector<int> uses(meshes.size(), 0);
    std::vector<bool> moving(meshes.size(), false);
    for (const Instance& inst : instances) {
        ++uses[inst.mesh];
        if (inst.motion >= 0) moving[inst.mesh] = true;
    }
    std::vector<bool> baked(meshes.size(), false);
    for (Instance& inst : instances) {
        if (inst.identity || inst.motion >= 0 || uses[inst.mesh] != 1 || moving[inst.mesh])
            continue;
        baked[inst.mesh] = true;
        Mesh& mesh = meshes[inst.mesh];
        const Affine& xf = inst.transform;
        for (Vec3& p : mesh.positions) p = xf.point(p);
        for (Vec3& n : mesh.normals) {
            const Vec3 w = xf.normal(n);
            n = length(w) > 0.0f ? normalize(w) : Vec3{};
        }
        for (Vec4& t : mesh.tangents) {
            const Vec3 w = xf.vector({t.x, t.y, t.z});
            const float len = length(w);
            const Vec3 u = len > 0.0f ? w / len : Vec3{};
            t = {u.x, u.y, u.z, t.w};
        }
        inst.transform = Affine{};
        inst.identity = true;
    }
    // Meshes only identity instances use are in world space as they are: their normals are made
    // unit here, as baking makes those it transforms. Shared and moving meshes keep the file's
    // normals; triangle() maps and normalises them.
    std::vector<bool> worldOnly(meshes.size(), true);
    for (const Instance& inst : instances)
        if (!inst.identity || inst.motion >= 0) worldOnly[inst.mesh] = false;
    for (std::size_t m = 0; m < meshes.size(); ++m) {
        Mesh& mesh = meshes[m];
        if (worldOnly[m] && !baked[m])
            for (Vec3& n : mesh.normals) n = length(n) > 0.0f ? normalize(n) : Vec3{};
        if (mesh.positions.capacity() == mesh.positions.size())
            mesh.positions.reserve(mesh.positions.size() + 1);
    }
    // Face normals of the world-space meshes, when the scene is small enough to hold them.
    std::size_t triangles = 0;
    for (const Mesh& mesh : meshes) triangles += mesh.triangleCount();
    for (std::size_t m = 0; m < meshes.size(); ++m) {
        Mesh& mesh = meshes[m];
        mesh.faceNormals.clear();
        if (!worldOnly[m] || triangles > kFaceNormalTriangles) continue;
        mesh.faceNormals.resize(mesh.triangleCount());
        for (std::uint32_t t = 0; t < mesh.triangleCount(); ++t) {
            const std::uint32_t* idx = &mesh.indices[3 * std::size_t(t)];
            mesh.faceNormals[t] = triangleNormal(mesh.positions[idx[0]], mesh.positions[idx[1]],
                                                 mesh.positions[idx[2]]);
        }
    }
}

}  // namespace detail

Scene::Scene() : m_data(std::make_unique<detail::SceneData>()) {}
Scene::Scene(std::unique_ptr<detail::SceneData> data) : m_data(std::move(data)) {}
Scene::~Scene() = default;
Scene::Scene(Scene&&) noexcept = default;
Scene& Scene::operator=(Scene&&) noexcept = default;

int Scene::width() const {
    return m_data->width;
}
int Scene::height() const {
    return m_data->height;
}
const Settings& Scene::settings() const {
    return m_data->settings;
}
const std::filesystem::path& Scene::path() const {
    return m_data->path;
}
std::size_t Scene::triangleCount() const {
    return m_data->triangleCount();
}

std::size_t Scene::areaLightCount() const {
    std::size_t count = 0;
    const detail::SceneData& d = *m_data;
    for (std::uint32_t i = 0; i < d.instances.size(); ++i) {
        const std::size_t n = d.meshes[d.instances[i].mesh].triangleCount();
        for (std::uint32_t t = 0; t < n; ++t)
            if (d.materials[d.materialOf(i, t)].emissive()) ++count;
    }
    return count;
}

bool Scene::hasEnvironment() const {
    return m_data->environment.kind != detail::EnvironmentDesc::Kind::None;
}

const std::vector<std::string>& Scene::warnings() const {
    return m_data->warnings;
}

std::vector<std::string> Scene::assetCameraNames() const {
    std::vector<std::string> names;
    for (const detail::AssetCamera& c : m_data->assetCameras) names.push_back(c.name);
    return names;
}

void Scene::useAssetCamera(const std::string& name) {
    for (const detail::AssetCamera& a : m_data->assetCameras) {
        if (a.name != name) continue;
        m_data->camera = detail::cameraOf(a);
        return;
    }
    std::string names;
    for (const detail::AssetCamera& a : m_data->assetCameras)
        names += (names.empty() ? "" : ", ") + a.name;
    throw Error(
        ErrorKind::InvalidArgument,
        "no glTF camera named '" + name + "' (" +
            (names.empty() ? "the scene's assets bring no camera" : "the cameras are: " + names) +
            ")",
        m_data->path.string());
}

const std::vector<std::filesystem::path>& Scene::inputs() const {
    return m_data->inputs;
}

}  // namespace glint::render

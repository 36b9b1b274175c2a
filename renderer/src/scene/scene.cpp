#include "glint/render/scene.h"

#include "scene/scene_data.h"

#include <algorithm>
#include <cmath>

namespace glint::render {

namespace detail {

const char* materialTypeName(MaterialType type) {
    switch (type) {
        case MaterialType::Diffuse:
            return "diffuse";
        case MaterialType::Mirror:
            return "mirror";
        case MaterialType::Dielectric:
            return "dielectric";
        case MaterialType::Conductor:
            return "conductor";
    }
    return "?";
}

TriangleView SceneData::poseMoving(std::size_t t, float time, PosedTriangle& scratch) const {
    const ShapeMotion& motion = motions[std::size_t(triangleMotion[t])];
    // Step k and fraction within it, as Embree interpolates between time steps.
    const int segments = int(motion.steps.size()) - 1;
    const float f = std::clamp(time, 0.0f, 1.0f) * float(segments);
    const int k = std::min(int(f), segments - 1);
    const float frac = f - float(k);
    const Affine& a = motion.steps[std::size_t(k)];
    const Affine& b = motion.steps[std::size_t(k) + 1];
    const std::size_t local = 3 * (t - motion.firstTriangle);
    for (int v = 0; v < 3; ++v) {
        const Vec3& x = motion.objectPositions[local + std::size_t(v)];
        scratch.p[v] = lerp(frac, a.point(x), b.point(x));
        const Vec3& n = motion.objectNormals[local + std::size_t(v)];
        scratch.n[v] = lerp(frac, a.normal(n), b.normal(n));
    }
    return {scratch.p, normals.empty() ? nullptr : scratch.n,
            triangleNormal(scratch.p[0], scratch.p[1], scratch.p[2])};
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
    for (std::size_t t = 0; t < m_data->triangleCount(); ++t)
        if (m_data->materials[m_data->triangleMaterial[t]].emissive()) ++count;
    return count;
}

bool Scene::hasEnvironment() const {
    return m_data->environment.kind != detail::EnvironmentDesc::Kind::None;
}

}  // namespace glint::render

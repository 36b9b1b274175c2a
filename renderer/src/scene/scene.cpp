#include "glint/render/scene.h"

#include "scene/scene_data.h"

namespace glint::render {

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

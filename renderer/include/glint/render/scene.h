// glint::render::Scene — a loaded scene.json with its meshes, materials, textures, lights.
#pragma once

#include <cstddef>
#include <filesystem>
#include <memory>
#include <string>

#include "glint/render/settings.h"

namespace glint::render {

namespace detail {
struct SceneData;
}

/// A scene ready to be rendered. Move-only; the contents are private to the renderer.
class Scene {
  public:
    Scene();
    explicit Scene(std::unique_ptr<detail::SceneData> data);
    ~Scene();
    Scene(Scene&&) noexcept;
    Scene& operator=(Scene&&) noexcept;

    /// Film width in pixels.
    int width() const;
    /// Film height in pixels.
    int height() const;
    /// The settings of the file's "render" block (defaults where absent).
    const Settings& settings() const;
    /// Path of the scene file (empty for a scene parsed from a string).
    const std::filesystem::path& path() const;
    /// Number of triangles after loading every shape.
    std::size_t triangleCount() const;
    /// Number of emissive triangles (area lights).
    std::size_t areaLightCount() const;
    /// True when the scene has an environment (image or constant colour).
    bool hasEnvironment() const;

    /// The private contents (for the renderer's own code).
    const detail::SceneData& data() const { return *m_data; }

  private:
    std::unique_ptr<detail::SceneData> m_data;
};

/// Loads scene.json and everything it references (paths relative to the file). Throws
/// glint::Error naming the file and the JSON path or line of every problem.
Scene loadScene(const std::filesystem::path& path);

/// Parses scene JSON text as if it were the file `path` (relative paths resolve against
/// path's directory; `path` is used in error messages and need not exist).
Scene parseScene(const std::string& jsonText, const std::filesystem::path& path);

}  // namespace glint::render

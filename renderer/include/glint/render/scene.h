// glint::render::Scene — a loaded scene.json with its meshes, materials, textures, lights.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "glint/render/look.h"
#include "glint/render/settings.h"

namespace glint::render {

namespace detail {
struct SceneData;
struct SceneAccess;
}  // namespace detail

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
    /// Every file the scene was read from: the scene file, OBJ and MTL files, glTF files and
    /// their buffer files, texture and environment images; so that a tool can refuse to write
    /// over one of them.
    const std::vector<std::filesystem::path>& inputs() const;

    /// What loading ignored and the user should know (an unread glTF extension, a skipped
    /// orthographic camera...), one line each.
    const std::vector<std::string>& warnings() const;
    /// Names of the cameras the scene's glTF assets bring (the node's name, else the camera's,
    /// else `cameras[i]`), in the order the assets' scenes list them.
    std::vector<std::string> assetCameraNames() const;
    /// Renders through the glTF camera `name` (see assetCameraNames); the film stays as it is.
    /// Throws glint::Error(InvalidArgument) listing the names when there is none of that name.
    void useAssetCamera(const std::string& name);

    /// Every material (in file order: JSON materials, then those the OBJ files added) and the
    /// environment, each with its editable properties and their current values. A material has
    /// albedo (unless textured), emission colour and strength, and roughness (conductor) or ior
    /// and roughness (dielectric); the environment has scale and rotate, and colour if constant.
    std::vector<LookItem> look() const;

    /// Sets one property of a look item (see look()). Throws glint::Error(InvalidArgument) naming
    /// the scene file and the JSON place (e.g. /materials/light/emission/0) for an unknown item
    /// or property, a value outside its range, or an edit the scene cannot take (emission on a
    /// moving or zero-area shape). The next render picks the change up without rebuilding the
    /// ray-tracing structures.
    void setLook(const std::string& item, const std::string& property,
                 const std::array<double, 3>& value);
    /// Scalar form of setLook.
    void setLook(const std::string& item, const std::string& property, double value);

    /// Counts look edits; a renderer compares it to rebuild its lights.
    std::uint64_t lookRevision() const;

  private:
    // The renderer's own code reads the contents (renderer/src/scene/scene_access.h).
    friend struct detail::SceneAccess;
    std::unique_ptr<detail::SceneData> m_data;
};

/// Loads scene.json and everything it references (paths relative to the file), or a bare glTF
/// or OBJ asset. Throws glint::Error naming the file and the JSON path or line of every problem.
/// With `memoryLimit` > 0 (Settings::memoryLimit), the load is held to it: before an OBJ or glTF
/// reader parses an asset, its load's peak is predicted from a scan of the file (its statement
/// counts; its JSON and image headers), and an asset that would take the scene past the limit
/// is refused with Error(OutOfMemory) naming the prediction, the limit and what would help,
/// before its reader allocates (docs/renderer.md, "Memory").
Scene loadScene(const std::filesystem::path& path, std::uint64_t memoryLimit = 0);

/// Parses scene JSON text as if it were the file `path` (relative paths resolve against
/// path's directory; `path` is used in error messages and need not exist); `memoryLimit` as in
/// loadScene.
Scene parseScene(const std::string& jsonText, const std::filesystem::path& path,
                 std::uint64_t memoryLimit = 0);

/// Writes the scene, with its look edits, as scene.json at `path` (atomically): the original
/// file with the edited materials and environment updated (a material that came from an MTL
/// file gets a full JSON definition) and relative paths rewritten for the new folder. Loading
/// it gives the same image bit for bit. Throws glint::Error(Io) when it cannot be written.
void saveScene(const Scene& scene, const std::filesystem::path& path);

}  // namespace glint::render

// The private contents of a Scene, for the renderer's own code and its tests. Not part of the
// public API (docs/architecture.md, "Public headers").
#pragma once

#include "glint/render/scene.h"
#include "scene/scene_data.h"

namespace glint::render::detail {

/// Reads a Scene's private contents (Scene befriends it).
struct SceneAccess {
    static const SceneData& data(const Scene& scene) { return *scene.m_data; }
};

/// The private contents of `scene`.
inline const SceneData& sceneData(const Scene& scene) {
    return SceneAccess::data(scene);
}

}  // namespace glint::render::detail

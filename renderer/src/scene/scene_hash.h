// A content hash of a loaded scene: what two machines compare to know they render the same
// scene (glint:sceneHash of a shard, docs/distributed.md).
#pragma once

#include <cstdint>

#include "scene/scene_data.h"

namespace glint::render {

/// Hash of everything a render of `data` depends on besides Settings: film size, camera,
/// geometry, materials (with look edits), textures, environment and motion. The file's path is
/// left out, so the same scene in another folder or on another machine hashes the same.
std::uint64_t sceneContentHash(const detail::SceneData& data);

}  // namespace glint::render

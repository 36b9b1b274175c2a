// The Embree BVH of a scene behind a small interface: the rest of the renderer never sees
// <embree3/rtcore.h>.
#pragma once

#include <cstdint>

#include "scene/camera.h"
#include "scene/scene_data.h"
#include "vecmath.h"

struct RTCDeviceTy;
struct RTCSceneTy;

namespace glint::render {

/// The closest hit of a ray: distance, triangle and barycentrics (p = (1-u-v) p0 + u p1 + v p2).
struct Hit {
    float t = 0.0f;
    std::uint32_t triangle = 0;
    float u = 0.0f, v = 0.0f;
};

/// Embree device + committed scene of one SceneData (one triangle mesh of all shapes).
class EmbreeScene {
  public:
    /// Converts the scene (see convertScene in embree_scene.cpp). Throws glint::Error on failure.
    explicit EmbreeScene(const detail::SceneData& scene);
    ~EmbreeScene();
    EmbreeScene(const EmbreeScene&) = delete;
    EmbreeScene& operator=(const EmbreeScene&) = delete;

    /// Closest hit along the ray within (0, tMax); `coherent` hints primary rays.
    bool intersect(const Ray& ray, float tMax, Hit& hit, bool coherent = false) const;
    /// True when anything blocks the segment from origin along dir within (0, tMax).
    bool occluded(const Vec3& origin, const Vec3& dir, float tMax) const;

  private:
    RTCDeviceTy* m_device = nullptr;
    RTCSceneTy* m_scene = nullptr;
};

}  // namespace glint::render

// Pinhole and thin-lens camera: raster position + lens sample → world ray.
#pragma once

#include "scene/scene_data.h"
#include "vecmath.h"

namespace glint::render {

/// A ray with origin and (unit) direction.
struct Ray {
    Vec3 origin;
    Vec3 dir;
};

/// The camera of a scene at film resolution width × height.
class Camera {
  public:
    Camera(const detail::CameraDesc& desc, int width, int height);

    /// Ray through raster point (px, py) (pixels, y down) and lens sample u in [0,1)^2.
    Ray generateRay(float px, float py, Vec2 lensU) const;
    /// Camera-space depth (distance along the view axis) of a world point.
    float depth(const Vec3& p) const { return dot(p - m_position, m_forward); }
    const Vec3& position() const { return m_position; }

  private:
    Vec3 m_position, m_forward, m_right, m_up;
    float m_tanHalfY = 0.0f, m_aspect = 1.0f;
    float m_lensRadius = 0.0f, m_focusDistance = 1.0f;
    float m_invWidth = 1.0f, m_invHeight = 1.0f;
};

}  // namespace glint::render

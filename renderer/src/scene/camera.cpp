#include "scene/camera.h"

#include <cmath>

#include "sampling/warp.h"

namespace glint::render {

Camera::Camera(const detail::CameraDesc& desc, int width, int height)
    : m_position(desc.position),
      m_tanHalfY(std::tan(0.5f * desc.fovY * kPi / 180.0f)),
      m_aspect(float(width) / float(height)),
      m_lensRadius(desc.lensRadius),
      m_focusDistance(desc.focusDistance),
      m_invWidth(1.0f / float(width)),
      m_invHeight(1.0f / float(height)) {
    // Right-handed view basis: right = forward × up, so +x of the image is to the viewer's right.
    m_forward = normalize(desc.lookAt - desc.position);
    m_right = normalize(cross(m_forward, desc.up));
    m_up = cross(m_right, m_forward);
}

Ray Camera::generateRay(float px, float py, Vec2 lensU) const {
    const float sx = (2.0f * px * m_invWidth - 1.0f) * m_tanHalfY * m_aspect;
    const float sy = (1.0f - 2.0f * py * m_invHeight) * m_tanHalfY;
    const Vec3 d = m_forward + m_right * sx + m_up * sy;  // camera-space z of d is 1
    if (m_lensRadius <= 0.0f) return {m_position, normalize(d)};
    // Thin lens: aim at the point where the pinhole ray meets the plane of focus (PBR 6.2.3).
    const Vec3 focus = m_position + d * m_focusDistance;
    const Vec2 disk = sampleConcentricDisk(lensU);
    const Vec3 origin = m_position + (m_right * disk.x + m_up * disk.y) * m_lensRadius;
    return {origin, normalize(focus - origin)};
}

}  // namespace glint::render

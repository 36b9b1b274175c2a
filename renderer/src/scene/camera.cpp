#include "scene/camera.h"

#include <cmath>
#include <sstream>
#include <string>
#include <utility>

#include "glint/image/error.h"
#include "sampling/warp.h"

namespace glint::render {

namespace {

using detail::kMinViewDistance;

struct Vec3d {
    double x, y, z;
};

Vec3d toDouble(const Vec3& v) {
    return {double(v.x), double(v.y), double(v.z)};
}

double lengthOf(const Vec3d& v) {
    return std::sqrt(v.x * v.x + v.y * v.y + v.z * v.z);
}

Vec3d crossOf(const Vec3d& a, const Vec3d& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

// The largest up accepted: the camera's float cross products and their squares stay finite.
constexpr double kMaxUpLength = 1e18;

}  // namespace

std::string viewDistanceProblem(double distance) {
    if (distance >= kMinViewDistance) return {};
    std::ostringstream msg;
    msg << "lookAt is " << distance << " from position, too close to give a view direction "
        << "in float; expected a distance of at least " << kMinViewDistance;
    return msg.str();
}

std::optional<ViewBasisFault> viewBasisFault(const Vec3& position, const Vec3& lookAt,
                                             const Vec3& up) {
    // In double: a float length of a tiny difference underflows to 0 although the points differ.
    const Vec3d p = toDouble(position), l = toDouble(lookAt), u = toDouble(up);
    const Vec3d view{l.x - p.x, l.y - p.y, l.z - p.z};
    const double distance = lengthOf(view);
    std::ostringstream msg;
    if (distance == 0.0) return ViewBasisFault{"lookAt", "lookAt must differ from position"};
    if (std::string problem = viewDistanceProblem(distance); !problem.empty())
        return ViewBasisFault{"lookAt", std::move(problem)};
    const double upLength = lengthOf(u);
    if (!std::isfinite(upLength) || upLength == 0.0) {
        msg << "up is [" << up.x << ", " << up.y << ", " << up.z
            << "]; expected a non-zero vector (the image's up direction)";
        return ViewBasisFault{"up", msg.str()};
    }
    if (upLength > kMaxUpLength) {
        msg << "up is " << upLength << " long; expected a length of at most " << kMaxUpLength;
        return ViewBasisFault{"up", msg.str()};
    }
    // The right axis is the view direction × up, normalised in float.
    const Vec3d dir{view.x / distance, view.y / distance, view.z / distance};
    const double across = lengthOf(crossOf(dir, u));
    if (across < 1e-6 * upLength)
        return ViewBasisFault{"up", "up must not be parallel to the viewing direction"};
    if (across < kMinViewDistance) {
        msg << "up is " << upLength << " long (" << across << " across the view direction), "
            << "too short to give a direction in float; expected at least " << kMinViewDistance;
        return ViewBasisFault{"up", msg.str()};
    }
    return std::nullopt;
}

std::optional<ViewBasisFault> cameraFault(const detail::CameraDesc& cam) {
    if (auto fault = viewBasisFault(cam.position, cam.lookAt, cam.up)) return fault;
    for (int i = 1; i <= 64 && cam.hasMotion; ++i) {
        const float tau = float(i) / 64.0f;
        if (const auto fault = viewBasisFault(lerp(tau, cam.position, cam.motionPosition),
                                              lerp(tau, cam.lookAt, cam.motionLookAt), cam.up))
            return ViewBasisFault{
                "motion",
                "the camera's view direction degenerates (zero or parallel to up) during "
                "the shutter: " +
                    fault->reason};
    }
    return std::nullopt;
}

void checkCamera(const detail::SceneData& scene) {
    if (const auto fault = cameraFault(scene.camera))
        throw Error(ErrorKind::InvalidArgument, fault->reason, scene.path.string(),
                    "/camera/" + fault->key);
}

Camera::Camera(const detail::CameraDesc& desc, int width, int height)
    : m_position(desc.position),
      m_moving(desc.hasMotion),
      m_upHint(desc.up),
      m_lookAt(desc.lookAt),
      m_endPosition(desc.motionPosition),
      m_endLookAt(desc.motionLookAt),
      m_tanHalfY(std::tan(0.5f * desc.fovY * kPi / 180.0f)),
      m_aspect(float(width) / float(height)),
      m_lensRadius(desc.lensRadius),
      m_focusDistance(desc.focusDistance),
      m_invWidth(1.0f / float(width)),
      m_invHeight(1.0f / float(height)) {
    const Basis b = makeBasis(desc.position, desc.lookAt, desc.up);
    m_forward = b.forward, m_right = b.right, m_up = b.up;
}

Camera::Basis Camera::makeBasis(const Vec3& position, const Vec3& lookAt, const Vec3& up) {
    // Right-handed view basis: right = forward × up, so +x of the image is to the viewer's right.
    Basis b;
    b.position = position;
    b.forward = normalize(lookAt - position);
    b.right = normalize(cross(b.forward, up));
    b.up = cross(b.right, b.forward);
    return b;
}

Camera::Basis Camera::basisAt(float time) const {
    // Position and look-at point move linearly over the shutter; up stays fixed.
    return makeBasis(lerp(time, m_position, m_endPosition), lerp(time, m_lookAt, m_endLookAt),
                     m_upHint);
}

Ray Camera::generateRay(float px, float py, Vec2 lensU, float timeU) const {
    Basis b{m_position, m_forward, m_right, m_up};
    if (m_moving) b = basisAt(timeU);
    const float sx = (2.0f * px * m_invWidth - 1.0f) * m_tanHalfY * m_aspect;
    const float sy = (1.0f - 2.0f * py * m_invHeight) * m_tanHalfY;
    const Vec3 d = b.forward + b.right * sx + b.up * sy;  // camera-space z of d is 1
    if (m_lensRadius <= 0.0f) return {b.position, normalize(d), timeU};
    // Thin lens: aim at the point where the pinhole ray meets the plane of focus (PBR 6.2.3).
    const Vec3 focus = b.position + d * m_focusDistance;
    const Vec2 disk = sampleConcentricDisk(lensU);
    const Vec3 origin = b.position + (b.right * disk.x + b.up * disk.y) * m_lensRadius;
    return {origin, normalize(focus - origin), timeU};
}

void Camera::footprintAxes(const Vec3& p, const Vec3& n, float time, Vec3& dpdx, Vec3& dpdy) const {
    dpdx = dpdy = {};
    Basis b{m_position, m_forward, m_right, m_up};
    if (m_moving) b = basisAt(time);
    const Vec3 w = p - b.position;
    const float dist2 = dot(w, w);
    if (!(dist2 > 0.0f) || !std::isfinite(dist2)) return;
    // Two unit axes across the line of sight, as near the image's right and up as it allows:
    // the right (the up where the line of sight is within 0.6° of the right) less its part along
    // w, a − w (w·a) / |w|², of squared length q / |w|² with q = |w|² − (w·a)². Written so, the
    // square roots and divisions do not wait for one another (the footprint's time is their
    // latency).
    Vec3 across = b.right;
    float wa = dot(w, across), q = dist2 - wa * wa;
    if (!(q > 1e-4f * dist2)) {
        across = b.up;
        wa = dot(w, across), q = dist2 - wa * wa;
    }
    const float invDist2 = 1.0f / dist2, dist = std::sqrt(dist2), invQ = 1.0f / std::sqrt(q);
    const Vec3 d = w * (dist * invDist2);
    const Vec3 ax = (across - w * (wa * invDist2)) * (dist * invQ);
    const Vec3 ay = cross(ax, d);
    // One pixel's angle at the image centre (the smallest of the film).
    const float spread = 2.0f * m_tanHalfY * m_invHeight;
    // Where the ray one pixel over meets the plane through p: o + dir t with n · (o + dir t − p)
    // = 0, so t = n · w / n · dir (PBR 10.1.1). A plane seen edge-on (or the ray missing it)
    // gives the longest axis OIIO's filter takes anyway.
    const float nw = dot(n, w);
    auto offset = [&](const Vec3& axis) {
        const Vec3 dir = d + axis * spread;
        const float t = nw / dot(n, dir);
        const Vec3 o = dir * t - w;
        // (o · o finite: its length is.)
        if (!(t > 0.0f) || !std::isfinite(dot(o, o))) return axis * (dist * spread * 1e3f);
        return o;
    };
    dpdx = offset(ax);
    dpdy = offset(ay);
}

}  // namespace glint::render

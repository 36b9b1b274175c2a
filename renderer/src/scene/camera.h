// Pinhole and thin-lens camera, optionally moving over the shutter: raster position + lens
// sample + time sample → world ray.
#pragma once

#include <optional>
#include <string>

#include "scene/scene_data.h"
#include "vecmath.h"

namespace glint::render {

/// Why a camera's position, lookAt and up give no view basis in float: the key at fault
/// ("lookAt" or "up") and the reason, one sentence.
struct ViewBasisFault {
    std::string key;
    std::string reason;
};

/// Why a camera `distance` from its lookAt point cannot render, or "" when it can: the camera
/// normalises the view direction in float, whose squares end near 1e-38. The one rule for a
/// scene.json camera and for the camera that frames a bare asset.
std::string viewDistanceProblem(double distance);

/// Checks that position, lookAt and up give a view basis the camera can compute in float:
/// lookAt at least kMinViewDistance from position; up non-zero, at most 1e18 long, its part across
/// the view direction at least 1e-6 of its length (not parallel) and at least kMinViewDistance
/// (normalisable in float, whose squares end near 1e-38). Computed in double. Returns the first
/// fault, or nullopt.
std::optional<ViewBasisFault> viewBasisFault(const Vec3& position, const Vec3& lookAt,
                                             const Vec3& up);

/// The first fault of a scene camera's view basis: at shutter open, or (key "motion") at any of
/// 64 times over the shutter of a moving camera.
std::optional<ViewBasisFault> cameraFault(const detail::CameraDesc& camera);

/// Throws glint::Error(InvalidArgument) naming the scene file and /camera/KEY when the scene's
/// camera has a fault (cameraFault): the check every scene passes before a Renderer builds
/// anything, whichever way its camera was set (scene.json, a glTF camera, useAssetCamera).
void checkCamera(const detail::SceneData& scene);

/// A ray with origin, (unit) direction and normalised shutter time (0 = open, 1 = close).
struct Ray {
    Vec3 origin;
    Vec3 dir;
    float time = 0.0f;
};

/// The camera of a scene at film resolution width × height.
class Camera {
  public:
    Camera(const detail::CameraDesc& desc, int width, int height);

    /// The camera ray of one sample: raster point (px, py) (pixels, y down), lens sample
    /// lensU in [0,1)^2 (ignored by a pinhole) and time sample timeU in [0,1) (the normalised
    /// shutter time, ray.time = timeU). Deterministic in its arguments, so any sampler (the
    /// stratified pass sampler, MLT's primary sample space) can drive it.
    Ray generateRay(float px, float py, Vec2 lensU, float timeU = 0.0f) const;
    /// Camera-space depth (distance along the view axis) of a world point at shutter time `time`.
    float depth(const Vec3& p, float time = 0.0f) const {
        if (!m_moving) return dot(p - m_position, m_forward);
        const Basis b = basisAt(time);
        return dot(p - b.position, b.forward);
    }
    /// How a surface point `p` (plane normal `n`) moves for a step of one pixel in x and in y, as
    /// if seen straight from the camera with the angular spread of the image centre's pixels
    /// (pbrt-v4's Camera::Approximate_dp_dxy, without its spp scale): the footprint of texture
    /// filtering, for camera rays and, as an approximation, for the hits of later bounces. A
    /// grazing plane gives long axes; a point at the camera gives zero ones.
    void footprintAxes(const Vec3& p, const Vec3& n, float time, Vec3& dpdx, Vec3& dpdy) const;
    /// Position at shutter open.
    const Vec3& position() const { return m_position; }
    /// True when the camera moves during the shutter.
    bool moving() const { return m_moving; }

  private:
    struct Basis {
        Vec3 position, forward, right, up;
    };
    static Basis makeBasis(const Vec3& position, const Vec3& lookAt, const Vec3& up);
    Basis basisAt(float time) const;

    Vec3 m_position, m_forward, m_right, m_up;
    bool m_moving = false;
    Vec3 m_upHint, m_lookAt, m_endPosition, m_endLookAt;
    float m_tanHalfY = 0.0f, m_aspect = 1.0f;
    float m_lensRadius = 0.0f, m_focusDistance = 1.0f;
    float m_invWidth = 1.0f, m_invHeight = 1.0f;
};

}  // namespace glint::render

// Shape transforms of scene.json (scale, then rotate, then translate) and their interpolation
// over the shutter for motion blur.
#pragma once

#include <algorithm>
#include <cmath>

#include "vecmath.h"

namespace glint::render::detail {

/// An affine map: linear part m (row-major 3×3) plus translation; normals use nm = (m^-1)^T.
struct Affine {
    float m[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    float nm[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    Vec3 t{};

    /// Maps a point.
    Vec3 point(const Vec3& p) const { return linear(m, p) + t; }
    /// Maps a normal (not normalised).
    Vec3 normal(const Vec3& n) const { return linear(nm, n); }
    /// Maps a direction (a tangent; not normalised).
    Vec3 vector(const Vec3& v) const { return linear(m, v); }
    /// Applies a row-major 3×3 matrix.
    static Vec3 linear(const float a[3][3], const Vec3& v) {
        return {a[0][0] * v.x + a[0][1] * v.y + a[0][2] * v.z,
                a[1][0] * v.x + a[1][1] * v.y + a[1][2] * v.z,
                a[2][0] * v.x + a[2][1] * v.y + a[2][2] * v.z};
    }
};

/// The affine map of a row-major 3×4 matrix [M | t]; the normal matrix is (M^-1)^T, computed in
/// double. Returns false when M is singular (determinant 0 or not finite).
bool affineFromMatrix(const double rows[3][4], Affine& out);

/// a ∘ b: first b, then a (normal matrices compose the same way).
Affine compose(const Affine& a, const Affine& b);

/// True when `a` is exactly the identity.
bool isIdentity(const Affine& a);

/// A unit quaternion (w, x, y, z) for rotation interpolation.
struct Quat {
    float w = 1.0f, x = 0.0f, y = 0.0f, z = 0.0f;
};

/// The parameters of one "transform" block: M = T(translate) · R(axis, degrees) · S(scale).
struct TransformDesc {
    Vec3 scale{1.0f, 1.0f, 1.0f};
    float degrees = 0.0f;
    Vec3 axis{0.0f, 1.0f, 0.0f};  ///< unit length
    Vec3 translate{};
};

/// Quaternion of a rotation by `degrees` about the unit `axis`.
Quat quatFromAxisAngle(const Vec3& axis, float degrees);

/// The affine map of rotation quaternion q combined with scale and translation (M = T R S).
Affine composeAffine(const Vec3& scale, const Quat& q, const Vec3& translate);

/// The affine map of a transform block.
Affine toAffine(const TransformDesc& desc);

/// Linear motion from `start` (shutter open) to `end` (shutter close): scale and translation
/// are interpolated linearly; the rotation turns about the shared axis by the linearly
/// interpolated angle when both rotations share an axis (so several turns are kept), otherwise
/// it is slerped along the shortest arc (Shoemake 1985).
class TransformMotion {
  public:
    TransformMotion(const TransformDesc& start, const TransformDesc& end);

    /// The transform at normalised shutter time tau in [0, 1].
    Affine at(float tau) const;
    /// Angle in degrees the rotation sweeps over the shutter.
    float sweptDegrees() const { return m_sweptDegrees; }
    /// Embree time steps needed: 2 without rotation (vertex interpolation is then exact),
    /// otherwise one step per kMaxStepDegrees of swept angle (+1), at most kMaxTimeSteps.
    int timeSteps() const;

    /// Largest rotation between consecutive time steps: the chord of a 5° arc deviates from
    /// the arc by r (1 - cos 2.5°) < 0.001 r.
    static constexpr float kMaxStepDegrees = 5.0f;
    /// Embree's limit on time steps (RTC_MAX_TIME_STEP_COUNT).
    static constexpr int kMaxTimeSteps = 129;

  private:
    TransformDesc m_start, m_end;
    bool m_sharedAxis = true;
    Vec3 m_axis{0.0f, 1.0f, 0.0f};
    float m_degrees0 = 0.0f, m_degrees1 = 0.0f;  // about m_axis (shared-axis case)
    Quat m_q0, m_q1;                             // slerp case
    float m_sweptDegrees = 0.0f;
};

}  // namespace glint::render::detail

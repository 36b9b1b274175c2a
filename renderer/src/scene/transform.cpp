#include "scene/transform.h"

namespace glint::render::detail {

Quat quatFromAxisAngle(const Vec3& axis, float degrees) {
    const float half = 0.5f * degrees * kPi / 180.0f;
    const float s = std::sin(half);
    return {std::cos(half), axis.x * s, axis.y * s, axis.z * s};
}

Affine composeAffine(const Vec3& scale, const Quat& q, const Vec3& translate) {
    // Rotation matrix of a unit quaternion (Shoemake 1985).
    const float w = q.w, x = q.x, y = q.y, z = q.z;
    const float r[3][3] = {{1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)},
                           {2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)},
                           {2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)}};
    Affine a;
    // M = R S; normals transform by (M^-1)^T = R S^-1.
    for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k) {
            a.m[i][k] = r[i][k] * scale[k];
            a.nm[i][k] = r[i][k] / scale[k];
        }
    a.t = translate;
    return a;
}

bool affineFromMatrix(const double rows[3][4], Affine& out) {
    const auto& a = rows;
    // Cofactors of M: (M^-1)^T = cof(M) / det(M).
    const double c[3][3] = {
        {a[1][1] * a[2][2] - a[1][2] * a[2][1], a[1][2] * a[2][0] - a[1][0] * a[2][2],
         a[1][0] * a[2][1] - a[1][1] * a[2][0]},
        {a[0][2] * a[2][1] - a[0][1] * a[2][2], a[0][0] * a[2][2] - a[0][2] * a[2][0],
         a[0][1] * a[2][0] - a[0][0] * a[2][1]},
        {a[0][1] * a[1][2] - a[0][2] * a[1][1], a[0][2] * a[1][0] - a[0][0] * a[1][2],
         a[0][0] * a[1][1] - a[0][1] * a[1][0]}};
    const double det = a[0][0] * c[0][0] + a[0][1] * c[0][1] + a[0][2] * c[0][2];
    if (!(det != 0.0) || !std::isfinite(det)) return false;
    for (int i = 0; i < 3; ++i) {
        for (int k = 0; k < 3; ++k) {
            out.m[i][k] = float(a[i][k]);
            out.nm[i][k] = float(c[i][k] / det);
        }
        out.t[i] = float(a[i][3]);
    }
    return true;
}

Affine compose(const Affine& a, const Affine& b) {
    Affine r;
    for (int i = 0; i < 3; ++i) {
        for (int k = 0; k < 3; ++k) {
            double m = 0.0, n = 0.0;
            for (int j = 0; j < 3; ++j) {
                m += double(a.m[i][j]) * double(b.m[j][k]);
                n += double(a.nm[i][j]) * double(b.nm[j][k]);
            }
            r.m[i][k] = float(m);
            r.nm[i][k] = float(n);
        }
        double t = a.t[i];
        for (int j = 0; j < 3; ++j) t += double(a.m[i][j]) * double(b.t[j]);
        r.t[i] = float(t);
    }
    return r;
}

bool isIdentity(const Affine& a) {
    for (int i = 0; i < 3; ++i) {
        if (a.t[i] != 0.0f) return false;
        for (int k = 0; k < 3; ++k)
            if (a.m[i][k] != (i == k ? 1.0f : 0.0f) || a.nm[i][k] != (i == k ? 1.0f : 0.0f))
                return false;
    }
    return true;
}

Affine toAffine(const TransformDesc& desc) {
    return composeAffine(desc.scale, quatFromAxisAngle(desc.axis, desc.degrees), desc.translate);
}

TransformMotion::TransformMotion(const TransformDesc& start, const TransformDesc& end)
    : m_start(start), m_end(end) {
    // Both rotations about one axis (a zero rotation has any axis): interpolate the angle.
    const float alignment = dot(start.axis, end.axis);
    if (start.degrees == 0.0f) {
        m_axis = end.axis, m_degrees0 = 0.0f, m_degrees1 = end.degrees;
    } else if (end.degrees == 0.0f) {
        m_axis = start.axis, m_degrees0 = start.degrees, m_degrees1 = 0.0f;
    } else if (alignment > 0.99999f) {
        m_axis = start.axis, m_degrees0 = start.degrees, m_degrees1 = end.degrees;
    } else if (alignment < -0.99999f) {
        m_axis = start.axis, m_degrees0 = start.degrees, m_degrees1 = -end.degrees;
    } else {
        m_sharedAxis = false;
    }
    if (m_sharedAxis) {
        m_sweptDegrees = std::abs(m_degrees1 - m_degrees0);
        return;
    }
    m_q0 = quatFromAxisAngle(start.axis, start.degrees);
    m_q1 = quatFromAxisAngle(end.axis, end.degrees);
    // Shortest arc: flip q1 into q0's hemisphere.
    float d = m_q0.w * m_q1.w + m_q0.x * m_q1.x + m_q0.y * m_q1.y + m_q0.z * m_q1.z;
    if (d < 0.0f) {
        m_q1 = {-m_q1.w, -m_q1.x, -m_q1.y, -m_q1.z};
        d = -d;
    }
    m_sweptDegrees = 2.0f * std::acos(std::min(d, 1.0f)) * 180.0f / kPi;
}

Affine TransformMotion::at(float tau) const {
    const Vec3 scale = lerp(tau, m_start.scale, m_end.scale);
    const Vec3 translate = lerp(tau, m_start.translate, m_end.translate);
    if (m_sharedAxis)
        return composeAffine(
            scale, quatFromAxisAngle(m_axis, m_degrees0 + tau * (m_degrees1 - m_degrees0)),
            translate);
    // Spherical linear interpolation (Shoemake 1985): sin((1-t)θ)/sinθ q0 + sin(tθ)/sinθ q1.
    const float d = m_q0.w * m_q1.w + m_q0.x * m_q1.x + m_q0.y * m_q1.y + m_q0.z * m_q1.z;
    const float theta = std::acos(std::min(d, 1.0f));
    float a = 1.0f - tau, b = tau;
    if (theta > 1e-5f) {
        const float s = std::sin(theta);
        a = std::sin((1.0f - tau) * theta) / s;
        b = std::sin(tau * theta) / s;
    }
    Quat q{a * m_q0.w + b * m_q1.w, a * m_q0.x + b * m_q1.x, a * m_q0.y + b * m_q1.y,
           a * m_q0.z + b * m_q1.z};
    const float len = std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
    q = {q.w / len, q.x / len, q.y / len, q.z / len};
    return composeAffine(scale, q, translate);
}

int TransformMotion::timeSteps() const {
    if (m_sweptDegrees <= 0.0f) return 2;
    const int steps = 1 + int(std::ceil(m_sweptDegrees / kMaxStepDegrees));
    return std::clamp(steps, 2, kMaxTimeSteps);
}

}  // namespace glint::render::detail

// Small vector math for the renderer: Vec2, Vec3 (float), orthonormal frames.
#pragma once

#include <algorithm>
#include <cmath>
#include <numbers>

namespace glint::render {

inline constexpr float kPi = std::numbers::pi_v<float>;
inline constexpr float kInvPi = 1.0f / kPi;

struct Vec2 {
    float x = 0.0f, y = 0.0f;
};

struct Vec3 {
    float x = 0.0f, y = 0.0f, z = 0.0f;

    float operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
    float& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
    Vec3 operator-() const { return {-x, -y, -z}; }
    Vec3& operator+=(const Vec3& b) {
        x += b.x, y += b.y, z += b.z;
        return *this;
    }
    Vec3& operator*=(const Vec3& b) {
        x *= b.x, y *= b.y, z *= b.z;
        return *this;
    }
    Vec3& operator*=(float s) {
        x *= s, y *= s, z *= s;
        return *this;
    }
};

/// A tangent with its bitangent sign (glTF's TANGENT: xyz, w = ±1).
struct Vec4 {
    float x = 0.0f, y = 0.0f, z = 0.0f, w = 0.0f;
};

inline Vec3 operator+(const Vec3& a, const Vec3& b) {
    return {a.x + b.x, a.y + b.y, a.z + b.z};
}
inline Vec3 operator-(const Vec3& a, const Vec3& b) {
    return {a.x - b.x, a.y - b.y, a.z - b.z};
}
inline Vec3 operator*(const Vec3& a, const Vec3& b) {
    return {a.x * b.x, a.y * b.y, a.z * b.z};
}
inline Vec3 operator*(const Vec3& a, float s) {
    return {a.x * s, a.y * s, a.z * s};
}
inline Vec3 operator*(float s, const Vec3& a) {
    return {a.x * s, a.y * s, a.z * s};
}
inline Vec3 operator/(const Vec3& a, float s) {
    return a * (1.0f / s);
}
inline float dot(const Vec3& a, const Vec3& b) {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}
inline Vec3 cross(const Vec3& a, const Vec3& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline float length(const Vec3& a) {
    return std::sqrt(dot(a, a));
}
inline Vec3 normalize(const Vec3& a) {
    return a / length(a);
}
/// A vector already unit up to a few float roundings (a unit vector carried through an
/// orthonormal frame), made unit again without a square root or a division: one Newton step of
/// 1/√(a·a) from 1, a (3 − a·a) / 2, whose error is the square of the input's.
inline Vec3 renormalize(const Vec3& a) {
    return a * (0.5f * (3.0f - dot(a, a)));
}
inline float maxComponent(const Vec3& a) {
    return std::max(a.x, std::max(a.y, a.z));
}
inline float maxAbsComponent(const Vec3& a) {
    return std::max(std::abs(a.x), std::max(std::abs(a.y), std::abs(a.z)));
}
inline bool isBlack(const Vec3& a) {
    return a.x == 0.0f && a.y == 0.0f && a.z == 0.0f;
}
inline bool isFinite(const Vec3& a) {
    return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z);
}
/// cross(b − a, c − a) in double: neither tiny nor huge coordinates underflow or overflow.
inline void triangleCross(const Vec3& a, const Vec3& b, const Vec3& c, double n[3]) {
    const double ux = double(b.x) - a.x, uy = double(b.y) - a.y, uz = double(b.z) - a.z;
    const double vx = double(c.x) - a.x, vy = double(c.y) - a.y, vz = double(c.z) - a.z;
    n[0] = uy * vz - uz * vy;
    n[1] = uz * vx - ux * vz;
    n[2] = ux * vy - uy * vx;
}
/// Area of triangle (a, b, c).
inline double triangleArea(const Vec3& a, const Vec3& b, const Vec3& c) {
    double n[3];
    triangleCross(a, b, c, n);
    return 0.5 * std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
}
/// Unit geometric normal of (a, b, c), cross(b − a, c − a) normalised; +z for a degenerate one.
inline Vec3 triangleNormal(const Vec3& a, const Vec3& b, const Vec3& c) {
    double n[3];
    triangleCross(a, b, c, n);
    const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (!(len > 0.0) || !std::isfinite(len)) return {0.0f, 0.0f, 1.0f};
    return {float(n[0] / len), float(n[1] / len), float(n[2] / len)};
}
/// Rec. 709 luminance.
inline float luminance(const Vec3& a) {
    return 0.2126f * a.x + 0.7152f * a.y + 0.0722f * a.z;
}
inline Vec3 lerp(float t, const Vec3& a, const Vec3& b) {
    return a * (1.0f - t) + b * t;
}

/// Orthonormal basis around a unit normal n (Duff et al. 2017, "Building an Orthonormal Basis,
/// Revisited").
struct Frame {
    Vec3 s, t, n;

    static Frame fromNormal(const Vec3& n) {
        const float sign = std::copysign(1.0f, n.z);
        const float a = -1.0f / (sign + n.z);
        const float b = n.x * n.y * a;
        return {{1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x},
                {b, sign + n.y * n.y * a, -n.y},
                n};
    }
    Vec3 toLocal(const Vec3& v) const { return {dot(v, s), dot(v, t), dot(v, n)}; }
    Vec3 toWorld(const Vec3& v) const { return s * v.x + t * v.y + n * v.z; }
};

/// How far a ray starts off a surface at p: relative to the point's magnitude (the float error
/// of a hit point grows with it) plus a small share of the scene's extent (the error of a hit
/// far along a ray, even near the origin), so the same scene at any scale gives the same image:
/// there is no absolute epsilon.
inline float rayEpsilon(const Vec3& p, float sceneExtent) {
    return 1e-4f * maxAbsComponent(p) + 1e-5f * sceneExtent;
}

/// Offset of a ray origin off a surface at p along the geometric normal (towards `side`).
inline Vec3 offsetRayOrigin(const Vec3& p, const Vec3& ng, const Vec3& side, float sceneExtent) {
    const float eps = rayEpsilon(p, sceneExtent);
    return dot(ng, side) >= 0.0f ? p + ng * eps : p - ng * eps;
}

}  // namespace glint::render

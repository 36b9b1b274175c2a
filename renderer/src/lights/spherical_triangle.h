// Sampling a triangle light by the solid angle it subtends (Arvo 1995, "Stratified Sampling of
// Spherical Triangles"): directions uniform over the spherical triangle, pdf 1 / Ω, so a point
// close to a large light no longer pays for the 1/r² and cos θ of area sampling. In double: the
// solid angle loses precision for tiny triangles, which is why callers keep area sampling outside
// [kMinSphericalSolidAngle, kMaxSphericalSolidAngle].
#pragma once

#include <algorithm>
#include <cmath>

#include "vecmath.h"

namespace glint::render {

/// Solid angles (sr) between which a triangle is sampled by solid angle: below, the excess loses
/// its precision (and area sampling is as good: the light is small or far); above, the shading
/// point lies almost on the light's plane (pbrt-v4 uses the same bounds).
inline constexpr double kMinSphericalSolidAngle = 3e-4, kMaxSphericalSolidAngle = 6.22;

/// A vector in double for tests and references (the renderer works in float: above
/// kMinSphericalSolidAngle float keeps about 1e-4 relative accuracy of Ω).
struct DVec3 {
    double x = 0.0, y = 0.0, z = 0.0;
};
inline DVec3 operator+(const DVec3& a, const DVec3& b) {
    return {a.x + b.x, a.y + b.y, a.z + b.z};
}
inline DVec3 operator-(const DVec3& a, const DVec3& b) {
    return {a.x - b.x, a.y - b.y, a.z - b.z};
}
inline DVec3 operator*(double s, const DVec3& a) {
    return {s * a.x, s * a.y, s * a.z};
}
inline double dot(const DVec3& a, const DVec3& b) {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}
inline DVec3 cross(const DVec3& a, const DVec3& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline DVec3 toDouble(const Vec3& v) {
    return {v.x, v.y, v.z};
}

/// a / |a|, or the zero vector for a zero vector (Vec3 or DVec3).
template <class V>
[[gnu::always_inline]] inline V normalizeOrZero(const V& a) {
    using T = decltype(a.x);
    const T l2 = dot(a, a);
    return l2 > T(0) ? (T(1) / std::sqrt(l2)) * a : V{};
}

/// Solid angle of the spherical triangle of unit vectors a, b, c (Van Oosterom and Strackee
/// 1983): accurate for tiny triangles, and atan2 keeps it right past a hemisphere.
template <class V>
auto sphericalTriangleSolidAngle(const V& a, const V& b, const V& c) {
    using T = decltype(a.x);
    const T numerator = std::abs(dot(a, cross(b, c)));
    const T denominator = T(1) + dot(a, b) + dot(b, c) + dot(c, a);
    return T(2) * std::atan2(numerator, denominator);
}

/// The solid angle of triangle (v0, v1, v2) seen from p, in double (for tests and references).
inline double triangleSolidAngle(const Vec3& p, const Vec3& v0, const Vec3& v1, const Vec3& v2) {
    const DVec3 o = toDouble(p);
    return sphericalTriangleSolidAngle(normalizeOrZero(toDouble(v0) - o),
                                       normalizeOrZero(toDouble(v1) - o),
                                       normalizeOrZero(toDouble(v2) - o));
}

/// A direction uniform over the spherical triangle of unit vectors a, b, c of solid angle `area`
/// (sphericalTriangleSolidAngle) (Arvo 1995, sec. 3): u.x picks the sub-triangle A B Ĉ of area
/// u.x Ω, which fixes Ĉ on the arc AC; u.y picks the point on the arc from B to Ĉ whose cosine
/// to B interpolates linearly. False for a degenerate triangle.
template <class V, class T>
bool sampleSphericalTriangle(const V& a, const V& b, const V& c, T area, Vec2 u, V& direction) {
    // The angle α at A is the angle between the great circles AB and AC: between the normals
    // a × b and a × c of their planes. Only its sine and cosine are needed.
    const V nab = cross(a, b), nac = cross(a, c);
    const T lengths2 = dot(nab, nab) * dot(nac, nac);
    if (!(lengths2 > T(0)) || !(area > T(0))) return false;
    const T cosAlpha = std::clamp(dot(nab, nac) / std::sqrt(lengths2), T(-1), T(1));
    const T sinAlpha = std::sqrt(std::max(T(0), T(1) - cosAlpha * cosAlpha));
    if (!(sinAlpha > T(0))) return false;

    // The sub-triangle of area u.x Ω: the cosine q of the arc from A to its third vertex Ĉ
    // (Arvo 1995, eq. 7 onwards), with s, t = sin, cos(u.x Ω − α) by the angle difference.
    const T areaHat = T(u.x) * area;
    const T sinHat = std::sin(areaHat), cosHat = std::cos(areaHat);
    const T s = sinHat * cosAlpha - cosHat * sinAlpha;
    const T t = cosHat * cosAlpha + sinHat * sinAlpha;
    const T du = t - cosAlpha;
    const T dv = s + sinAlpha * dot(a, b);  // dot(a, b) = cos c, the arc AB
    const T denominator = (dv * s + du * t) * sinAlpha;
    if (!(std::abs(denominator) > T(0))) return false;
    const T q = std::clamp(((dv * t - du * s) * cosAlpha - dv) / denominator, T(-1), T(1));
    const V cHat =
        q * a + std::sqrt(std::max(T(0), T(1) - q * q)) * normalizeOrZero(c - dot(c, a) * a);

    // On the arc from B to Ĉ, the cosine to B uniform in [cos |BĈ|, 1].
    const T z = std::clamp(T(1) - T(u.y) * (T(1) - dot(cHat, b)), T(-1), T(1));
    direction =
        z * b + std::sqrt(std::max(T(0), T(1) - z * z)) * normalizeOrZero(cHat - dot(cHat, b) * b);
    return dot(direction, direction) > T(0.5);
}

}  // namespace glint::render

// Warps of uniform samples to disks, hemispheres, spheres and triangles, with their pdfs.
#pragma once

#include <cmath>

#include "vecmath.h"

namespace glint::render {

/// Concentric square→disk map (Shirley & Chiu 1997).
inline Vec2 sampleConcentricDisk(Vec2 u) {
    const float ox = 2.0f * u.x - 1.0f, oy = 2.0f * u.y - 1.0f;
    if (ox == 0.0f && oy == 0.0f) return {0.0f, 0.0f};
    float r, theta;
    if (std::abs(ox) > std::abs(oy)) {
        r = ox;
        theta = 0.25f * kPi * (oy / ox);
    } else {
        r = oy;
        theta = 0.5f * kPi - 0.25f * kPi * (ox / oy);
    }
    return {r * std::cos(theta), r * std::sin(theta)};
}

/// Cosine-weighted direction on the +z hemisphere (Malley's method); pdf cosθ/π.
inline Vec3 sampleCosineHemisphere(Vec2 u) {
    const Vec2 d = sampleConcentricDisk(u);
    const float z = std::sqrt(std::max(0.0f, 1.0f - d.x * d.x - d.y * d.y));
    return {d.x, d.y, z};
}
inline float cosineHemispherePdf(float cosTheta) {
    return std::max(cosTheta, 0.0f) * kInvPi;
}

/// Uniform direction on the unit sphere; pdf 1/(4π).
inline Vec3 sampleUniformSphere(Vec2 u) {
    const float z = 1.0f - 2.0f * u.x;
    const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
    const float phi = 2.0f * kPi * u.y;
    return {r * std::cos(phi), r * std::sin(phi), z};
}
inline constexpr float kUniformSpherePdf = 1.0f / (4.0f * kPi);

/// Uniform barycentrics (b1, b2) on a triangle (the square-root parameterisation, Osada et al.
/// 2002); the point is (1-b1-b2) p0 + b1 p1 + b2 p2.
inline Vec2 sampleUniformTriangle(Vec2 u) {
    const float su = std::sqrt(u.x);
    return {1.0f - su, u.y * su};
}

}  // namespace glint::render

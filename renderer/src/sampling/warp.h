// Warps of uniform samples to disks, hemispheres, spheres and triangles, with their pdfs.
#pragma once

#include <cmath>

#include "vecmath.h"

namespace glint::render {

/// (cos x, sin x) for |x| ≤ π/4 by their Taylor polynomials to x¹⁰ and x⁹: the truncation
/// error is below 2e-9, under float rounding, and there is no range reduction to pay for
/// (a library sincosf was 3-4 % of a Cornell render in cosine sampling alone).
inline Vec2 cosSinQuarterPi(float x) {
    const float x2 = x * x;
    const float c =
        1.0f +
        x2 * (-1.0f / 2 +
              x2 * (1.0f / 24 + x2 * (-1.0f / 720 + x2 * (1.0f / 40320 + x2 * (-1.0f / 3628800)))));
    const float s =
        x *
        (1.0f + x2 * (-1.0f / 6 + x2 * (1.0f / 120 + x2 * (-1.0f / 5040 + x2 * (1.0f / 362880)))));
    return {c, s};
}

/// Concentric square→disk map (Shirley & Chiu 1997).
inline Vec2 sampleConcentricDisk(Vec2 u) {
    const float ox = 2.0f * u.x - 1.0f, oy = 2.0f * u.y - 1.0f;
    if (ox == 0.0f && oy == 0.0f) return {0.0f, 0.0f};
    if (std::abs(ox) > std::abs(oy)) {
        // θ = π/4 · oy/ox.
        const Vec2 cs = cosSinQuarterPi(0.25f * kPi * (oy / ox));
        return {ox * cs.x, ox * cs.y};
    }
    // θ = π/2 − φ with φ = π/4 · ox/oy: cos θ = sin φ, sin θ = cos φ.
    const Vec2 cs = cosSinQuarterPi(0.25f * kPi * (ox / oy));
    return {oy * cs.y, oy * cs.x};
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

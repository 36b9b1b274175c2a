// The watertight ray–triangle test of Woop, Benthin and Wald 2013 ("Watertight Ray/Triangle
// Intersection", JCGT 2(1)), for one triangle and for a batch of up to 16 in SIMD lanes: what the
// clustered geometry (embree/cluster_geometry.cpp) tests a cluster's triangles with. Hits follow
// Embree's conventions: t within (tnear, tfar], u the weight of p1 and v that of p2.
#pragma once

#include <cstdint>

#include "vecmath.h"

namespace glint::render {

/// A ray sheared so that it runs along +z from its origin (Woop et al. 2013, section 3):
/// computed once a ray, used for every triangle.
struct ShearedRay {
    float org[3] = {0.0f, 0.0f, 0.0f};
    int kx = 0, ky = 1, kz = 2;  ///< the axes that become x, y and z
    float sx = 0.0f, sy = 0.0f, sz = 0.0f;
};

/// The shear of the ray from `org` along `dir`.
ShearedRay shearRay(const float org[3], const float dir[3]);

/// A hit: distance and barycentrics (p = (1-u-v) p0 + u p1 + v p2).
struct TriangleHit {
    float t = 0.0f, u = 0.0f, v = 0.0f;
};

/// The test of triangle (p0, p1, p2) within (tnear, tfar]; on an edge in float it decides again
/// in double (the paper's fallback), so that a ray through an edge meets one of its triangles.
bool hitTriangle(const ShearedRay& r, const Vec3& p0, const Vec3& p1, const Vec3& p2, float tnear,
                 float tfar, TriangleHit& hit);

/// Up to W triangles in SIMD layout: p[vertex][axis][triangle]; lanes past the batch's triangles
/// hold NaN, which no test hits.
template <int W>
struct TriangleBatch {
    alignas(64) float p[3][3][W];
};

/// What testBatch found for each lane: `hit` where the float test found a hit within
/// (tnear, tfar] (t, u, v set); `edge` where the float test met an edge exactly and hitTriangle
/// must decide.
template <int W>
struct BatchResult {
    alignas(64) float t[W], u[W], v[W];
    alignas(64) std::int32_t hit[W], edge[W];
};

/// The float part of hitTriangle for W triangles at once (W = 4, 8 or 16), with the same
/// results lane by lane where no edge is met.
void testBatch(const TriangleBatch<4>& batch, const ShearedRay& r, float tnear, float tfar,
               BatchResult<4>& out);
void testBatch(const TriangleBatch<8>& batch, const ShearedRay& r, float tnear, float tfar,
               BatchResult<8>& out);
void testBatch(const TriangleBatch<16>& batch, const ShearedRay& r, float tnear, float tfar,
               BatchResult<16>& out);

}  // namespace glint::render

#include "embree/ray_triangle.h"

#include <cmath>
#include <cstring>
#include <utility>

namespace glint::render {

ShearedRay shearRay(const float org[3], const float dir[3]) {
    ShearedRay r;
    for (int a = 0; a < 3; ++a) r.org[a] = org[a];
    // The axis where the direction is largest becomes z; x and y swap when it points down z,
    // which keeps the triangles' winding.
    r.kz = std::fabs(dir[0]) >= std::fabs(dir[1])
               ? (std::fabs(dir[0]) >= std::fabs(dir[2]) ? 0 : 2)
               : (std::fabs(dir[1]) >= std::fabs(dir[2]) ? 1 : 2);
    r.kx = (r.kz + 1) % 3;
    r.ky = (r.kx + 1) % 3;
    if (dir[r.kz] < 0.0f) std::swap(r.kx, r.ky);
    // Shear constants (Woop et al. 2013, section 3), by one reciprocal: every triangle of the
    // ray is tested with the same constants, which is what keeps the test watertight.
    r.sz = 1.0f / dir[r.kz];
    r.sx = dir[r.kx] * r.sz;
    r.sy = dir[r.ky] * r.sz;
    return r;
}

bool hitTriangle(const ShearedRay& r, const Vec3& p0, const Vec3& p1, const Vec3& p2, float tnear,
                 float tfar, TriangleHit& hit) {
    // Translate the vertices to the ray's origin.
    const float a[3] = {p0.x - r.org[0], p0.y - r.org[1], p0.z - r.org[2]};
    const float b[3] = {p1.x - r.org[0], p1.y - r.org[1], p1.z - r.org[2]};
    const float c[3] = {p2.x - r.org[0], p2.y - r.org[1], p2.z - r.org[2]};
    // Shear and scale them into the ray's space (the ray is +z there).
    const float ax = a[r.kx] - r.sx * a[r.kz], ay = a[r.ky] - r.sy * a[r.kz];
    const float bx = b[r.kx] - r.sx * b[r.kz], by = b[r.ky] - r.sy * b[r.kz];
    const float cx = c[r.kx] - r.sx * c[r.kz], cy = c[r.ky] - r.sy * c[r.kz];
    // Scaled barycentrics: the 2D edge functions.
    float u = cx * by - cy * bx, v = ax * cy - ay * cx, w = bx * ay - by * ax;
    // Exactly on an edge in float: decide again in double.
    if (u == 0.0f || v == 0.0f || w == 0.0f) {
        u = float(double(cx) * double(by) - double(cy) * double(bx));
        v = float(double(ax) * double(cy) - double(ay) * double(cx));
        w = float(double(bx) * double(ay) - double(by) * double(ax));
    }
    if ((u < 0.0f || v < 0.0f || w < 0.0f) && (u > 0.0f || v > 0.0f || w > 0.0f)) return false;
    const float det = u + v + w;
    if (det == 0.0f) return false;
    // The distance; written so that NaN fails the test.
    const float rcp = 1.0f / det;
    const float t = (u * (r.sz * a[r.kz]) + v * (r.sz * b[r.kz]) + w * (r.sz * c[r.kz])) * rcp;
    if (!(t > tnear && t <= tfar)) return false;
    hit = {t, v * rcp, w * rcp};
    return true;
}

namespace {

/// GCC/Clang vector types of W lanes.
template <int W>
struct BatchLanes;
template <>
struct BatchLanes<4> {
    typedef float F __attribute__((vector_size(16)));
    typedef std::int32_t I __attribute__((vector_size(16)));
};
template <>
struct BatchLanes<8> {
    typedef float F __attribute__((vector_size(32)));
    typedef std::int32_t I __attribute__((vector_size(32)));
};
template <>
struct BatchLanes<16> {
    typedef float F __attribute__((vector_size(64)));
    typedef std::int32_t I __attribute__((vector_size(64)));
};

/// hitTriangle's float steps (the same operations in the same order) on the V lanes from
/// `first` of a batch of W.
template <int V, int W>
inline __attribute__((always_inline)) void batchKernel(const TriangleBatch<W>& batch, int first,
                                                       const ShearedRay& r, float tnear, float tfar,
                                                       BatchResult<W>& out) {
    using F = typename BatchLanes<V>::F;
    using I = typename BatchLanes<V>::I;
    // The vertices relative to the origin, in the ray's axes (x, y, z); loaded one vector each
    // into named values (an array of them went through the stack).
    const int kx = r.kx, ky = r.ky, kz = r.kz;
    F p0x, p0y, p0z, p1x, p1y, p1z, p2x, p2y, p2z;
    std::memcpy(&p0x, &batch.p[0][kx][first], sizeof(F));
    std::memcpy(&p0y, &batch.p[0][ky][first], sizeof(F));
    std::memcpy(&p0z, &batch.p[0][kz][first], sizeof(F));
    std::memcpy(&p1x, &batch.p[1][kx][first], sizeof(F));
    std::memcpy(&p1y, &batch.p[1][ky][first], sizeof(F));
    std::memcpy(&p1z, &batch.p[1][kz][first], sizeof(F));
    std::memcpy(&p2x, &batch.p[2][kx][first], sizeof(F));
    std::memcpy(&p2y, &batch.p[2][ky][first], sizeof(F));
    std::memcpy(&p2z, &batch.p[2][kz][first], sizeof(F));
    const float ox = r.org[kx], oy = r.org[ky], oz = r.org[kz];
    p0x -= ox, p0y -= oy, p0z -= oz, p1x -= ox, p1y -= oy, p1z -= oz;
    p2x -= ox, p2y -= oy, p2z -= oz;
    // Shear and scale.
    const F ax = p0x - r.sx * p0z, ay = p0y - r.sy * p0z;
    const F bx = p1x - r.sx * p1z, by = p1y - r.sy * p1z;
    const F cx = p2x - r.sx * p2z, cy = p2y - r.sy * p2z;
    // Scaled barycentrics.
    const F u = cx * by - cy * bx, v = ax * cy - ay * cx, w = bx * ay - by * ax;
    const I edge = (u == 0.0f) | (v == 0.0f) | (w == 0.0f);
    const I outside =
        ((u < 0.0f) | (v < 0.0f) | (w < 0.0f)) & ((u > 0.0f) | (v > 0.0f) | (w > 0.0f));
    const F det = u + v + w;
    const F rcp = 1.0f / det;
    const F t = (u * (r.sz * p0z) + v * (r.sz * p1z) + w * (r.sz * p2z)) * rcp;
    const I hit = ~edge & ~outside & (det != 0.0f) & (t > tnear) & (t <= tfar);
    const F bu = v * rcp, bv = w * rcp;
    std::memcpy(&out.t[first], &t, sizeof(F));
    std::memcpy(&out.u[first], &bu, sizeof(F));
    std::memcpy(&out.v[first], &bv, sizeof(F));
    std::memcpy(&out.hit[first], &hit, sizeof(I));
    std::memcpy(&out.edge[first], &edge, sizeof(I));
}

/// The batch in chunks of 8 lanes with AVX2 (ymm registers).
template <int W>
__attribute__((target("avx2"))) void batchAvx2(const TriangleBatch<W>& batch, const ShearedRay& r,
                                               float tnear, float tfar, BatchResult<W>& out) {
    for (int first = 0; first < W; first += 8) batchKernel<8>(batch, first, r, tnear, tfar, out);
}

/// The batch in chunks of 4 lanes with the baseline's SSE2 (xmm registers).
template <int W>
void batchSse2(const TriangleBatch<W>& batch, const ShearedRay& r, float tnear, float tfar,
               BatchResult<W>& out) {
    for (int first = 0; first < W; first += 4) batchKernel<4>(batch, first, r, tnear, tfar, out);
}

/// Whether the CPU runs AVX2. Both paths compute the same IEEE operations lane by lane (no
/// FMA: the AVX2 path does not enable it), so results do not depend on the CPU.
bool cpuHasAvx2() {
#if defined(__x86_64__) && defined(__GNUC__)
    static const bool avx2 = [] {
        __builtin_cpu_init();
        return __builtin_cpu_supports("avx2") != 0;
    }();
    return avx2;
#else
    return false;
#endif
}

/// Batches of 8 and 16 lanes: AVX2 where the CPU has it.
template <int W>
void testWideBatch(const TriangleBatch<W>& batch, const ShearedRay& r, float tnear, float tfar,
                   BatchResult<W>& out) {
    if (cpuHasAvx2())
        batchAvx2(batch, r, tnear, tfar, out);
    else
        batchSse2(batch, r, tnear, tfar, out);
}

}  // namespace

void testBatch(const TriangleBatch<4>& batch, const ShearedRay& r, float tnear, float tfar,
               BatchResult<4>& out) {
    batchSse2(batch, r, tnear, tfar, out);
}

void testBatch(const TriangleBatch<8>& batch, const ShearedRay& r, float tnear, float tfar,
               BatchResult<8>& out) {
    testWideBatch(batch, r, tnear, tfar, out);
}

void testBatch(const TriangleBatch<16>& batch, const ShearedRay& r, float tnear, float tfar,
               BatchResult<16>& out) {
    testWideBatch(batch, r, tnear, tfar, out);
}

}  // namespace glint::render

#include "embree/cluster_geometry.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include <embree3/rtcore.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "embree/alpha_filter.h"
#include "embree/ray_triangle.h"
#include "glint/image/error.h"

namespace glint::render {

namespace {

constexpr int kBucketBits = 16;  // the codes' top bits that pick a bucket
constexpr std::uint32_t kBuckets = 1u << kBucketBits;

/// Spreads the low 21 bits of x to every third bit (bit i to bit 3i).
std::uint64_t spreadBits(std::uint64_t x) {
    x &= 0x1fffffULL;
    x = (x | x << 32) & 0x1f00000000ffffULL;
    x = (x | x << 16) & 0x1f0000ff0000ffULL;
    x = (x | x << 8) & 0x100f00f00f00f00fULL;
    x = (x | x << 4) & 0x10c30c30c30c30c3ULL;
    x = (x | x << 2) & 0x1249249249249249ULL;
    return x;
}

/// The 48-bit Hilbert index of a point of 16-bit coordinates: Skilling's transform of the axes
/// into the "transpose" of the index (J. Skilling, "Programming the Hilbert curve", AIP Conf.
/// Proc. 707, 2004), whose bits interleaved (x's first) are the index. Consecutive cells of the
/// curve are neighbours, unlike Morton order's jumps; on the 4M-triangle grid its clusters of
/// 16 have a third less box area than Morton order's (docs/lab/mesh-memory.md).
std::uint64_t hilbertIndex(std::uint32_t x, std::uint32_t y, std::uint32_t z) {
    constexpr std::uint32_t top = 1u << 15;
    // Where bit q of a coordinate c is set, invert the low bits of x; else exchange the low
    // bits of x and c (without branches: the bits are random).
    auto step = [](std::uint32_t& x, std::uint32_t& c, std::uint32_t q, std::uint32_t p) {
        const std::uint32_t set = 0u - ((c & q) != 0 ? 1u : 0u);
        const std::uint32_t t = (x ^ c) & p & ~set;
        x ^= (p & set) | t;
        c ^= t;
    };
    // Undo the excess work of the curve's rotations, from the top bit down.
    for (std::uint32_t q = top; q > 1; q >>= 1) {
        const std::uint32_t p = q - 1;
        x ^= p & (0u - ((x & q) != 0 ? 1u : 0u));  // x against itself: invert or nothing
        step(x, y, q, p);
        step(x, z, q, p);
    }
    // Gray encode.
    y ^= x;
    z ^= y;
    std::uint32_t t = 0;
    for (std::uint32_t q = top; q > 1; q >>= 1)
        if (z & q) t ^= q - 1;
    x ^= t, y ^= t, z ^= t;
    return spreadBits(x) << 2 | spreadBits(y) << 1 | spreadBits(z);
}

/// 48-bit Hilbert indices of triangle centroids, quantised to 16 bits an axis over a cube.
struct CentroidCoder {
    const detail::Mesh& mesh;
    float lo[3] = {0.0f, 0.0f, 0.0f};
    float scale = 0.0f;

    static constexpr std::uint64_t kNonFinite = (std::uint64_t(1) << 48) - 1;

    /// Three times the centroid of triangle t (the sum of its vertices).
    void centroidSum(std::size_t t, float s[3]) const {
        const std::uint32_t* idx = &mesh.indices[3 * t];
        const Vec3 &a = mesh.positions[idx[0]], &b = mesh.positions[idx[1]],
                   &c = mesh.positions[idx[2]];
        s[0] = a.x + b.x + c.x, s[1] = a.y + b.y + c.y, s[2] = a.z + b.z + c.z;
    }

    explicit CentroidCoder(const detail::Mesh& m) : mesh(m) {
        float hi[3] = {-std::numeric_limits<float>::infinity(),
                       -std::numeric_limits<float>::infinity(),
                       -std::numeric_limits<float>::infinity()};
        for (float& l : lo) l = std::numeric_limits<float>::infinity();
        for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
            float s[3];
            centroidSum(t, s);
            if (!(std::isfinite(s[0]) && std::isfinite(s[1]) && std::isfinite(s[2]))) continue;
            for (int a = 0; a < 3; ++a)
                lo[a] = std::min(lo[a], s[a]), hi[a] = std::max(hi[a], s[a]);
        }
        // A cube, so that a cluster is about as wide as it is deep (per-axis scales gave
        // clusters of twice the box area on the grid).
        float extent = 0.0f;
        for (int a = 0; a < 3; ++a)
            if (hi[a] >= lo[a]) extent = std::max(extent, hi[a] - lo[a]);
        scale = extent > 0.0f && std::isfinite(extent) ? 65536.0f / extent : 0.0f;
    }

    std::uint64_t code(std::size_t t) const {
        float s[3];
        centroidSum(t, s);
        if (!(std::isfinite(s[0]) && std::isfinite(s[1]) && std::isfinite(s[2]))) return kNonFinite;
        std::uint32_t q[3];
        for (int a = 0; a < 3; ++a)
            q[a] = std::uint32_t(std::clamp((s[a] - lo[a]) * scale, 0.0f, 65535.0f));
        return hilbertIndex(q[0], q[1], q[2]);
    }
};

/// The hit record of triangle `prim` as Embree's triangles report it.
RTCHit hitRecord(const detail::Mesh& mesh, std::uint32_t prim, const TriangleHit& h,
                 unsigned geomID, const RTCIntersectContext* context) {
    const std::uint32_t* idx = &mesh.indices[3 * std::size_t(prim)];
    const Vec3 &p0 = mesh.positions[idx[0]], &p1 = mesh.positions[idx[1]],
               &p2 = mesh.positions[idx[2]];
    // Embree's geometric normal: (p0 - p1) × (p2 - p0), not normalised.
    const Vec3 e1 = p0 - p1, e2 = p2 - p0;
    RTCHit hit;
    hit.Ng_x = e1.y * e2.z - e1.z * e2.y;
    hit.Ng_y = e1.z * e2.x - e1.x * e2.z;
    hit.Ng_z = e1.x * e2.y - e1.y * e2.x;
    hit.u = h.u;
    hit.v = h.v;
    hit.primID = prim;
    hit.geomID = geomID;
    for (int l = 0; l < RTC_MAX_INSTANCE_LEVEL_COUNT; ++l) hit.instID[l] = context->instID[l];
    return hit;
}

/// Lane i of a ray packet as a single ray.
RTCRay laneRay(RTCRayN* ray, unsigned N, unsigned i) {
    RTCRay r;
    r.org_x = RTCRayN_org_x(ray, N, i), r.org_y = RTCRayN_org_y(ray, N, i);
    r.org_z = RTCRayN_org_z(ray, N, i), r.tnear = RTCRayN_tnear(ray, N, i);
    r.dir_x = RTCRayN_dir_x(ray, N, i), r.dir_y = RTCRayN_dir_y(ray, N, i);
    r.dir_z = RTCRayN_dir_z(ray, N, i), r.time = RTCRayN_time(ray, N, i);
    r.tfar = RTCRayN_tfar(ray, N, i), r.mask = RTCRayN_mask(ray, N, i);
    r.id = RTCRayN_id(ray, N, i), r.flags = RTCRayN_flags(ray, N, i);
    return r;
}

/// Runs the geometry's filter on one candidate hit of lane i at distance t, as a single ray
/// (N = 1: the filters read the ray's origin, direction and id and the hit); true when the
/// filter accepts it. `report` is rtcFilterIntersection or rtcFilterOcclusion.
template <class Args, class Report>
bool filterAccepts(const Args* args, const ClusterGeometry& g, RTCRayN* ray, unsigned i, float t,
                   RTCHit& hit, Report report) {
    RTCRayHit single;
    single.ray = laneRay(ray, args->N, i);
    single.ray.tfar = t;  // Embree's filters see the ray ending at the hit
    single.hit = hit;
    int valid = -1;
    RTCFilterFunctionNArguments filter;
    filter.valid = &valid;
    filter.geometryUserPtr = const_cast<AlphaTest*>(g.alpha());
    filter.context = args->context;
    filter.ray = reinterpret_cast<RTCRayN*>(&single.ray);
    filter.hit = reinterpret_cast<RTCHitN*>(&single.hit);
    filter.N = 1;
    report(args, &filter);
    if (valid != -1) return false;
    hit = single.hit;
    return true;
}

ShearedRay shearLane(RTCRayN* ray, unsigned N, unsigned i) {
    const float org[3] = {RTCRayN_org_x(ray, N, i), RTCRayN_org_y(ray, N, i),
                          RTCRayN_org_z(ray, N, i)};
    const float dir[3] = {RTCRayN_dir_x(ray, N, i), RTCRayN_dir_y(ray, N, i),
                          RTCRayN_dir_z(ray, N, i)};
    return shearRay(org, dir);
}

void clusterBounds(const RTCBoundsFunctionArguments* args) {
    const auto& g = *static_cast<const ClusterGeometry*>(args->geometryUserPtr);
    const detail::Mesh& mesh = g.mesh();
    const std::size_t first = std::size_t(args->primID) * g.clusterSize();
    const std::size_t last = std::min(first + g.clusterSize(), g.order().size());
    constexpr float inf = std::numeric_limits<float>::infinity();
    float lo[3] = {inf, inf, inf}, hi[3] = {-inf, -inf, -inf};
    for (std::size_t j = first; j < last; ++j) {
        const std::uint32_t* idx = &mesh.indices[3 * std::size_t(g.order()[j])];
        for (int k = 0; k < 3; ++k) {
            const Vec3& p = mesh.positions[idx[k]];
            // A triangle with a non-finite vertex is never hit; it does not widen the box.
            if (!(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z))) continue;
            lo[0] = std::min(lo[0], p.x), lo[1] = std::min(lo[1], p.y);
            lo[2] = std::min(lo[2], p.z), hi[0] = std::max(hi[0], p.x);
            hi[1] = std::max(hi[1], p.y), hi[2] = std::max(hi[2], p.z);
        }
    }
    RTCBounds& b = *args->bounds_o;
    if (!(lo[0] <= hi[0])) {
        // Nothing finite: NaN bounds, which Embree's build leaves out.
        const float nan = std::numeric_limits<float>::quiet_NaN();
        b.lower_x = b.lower_y = b.lower_z = b.upper_x = b.upper_y = b.upper_z = nan;
        return;
    }
    b.lower_x = lo[0], b.lower_y = lo[1], b.lower_z = lo[2];
    b.upper_x = hi[0], b.upper_y = hi[1], b.upper_z = hi[2];
}

/// Cluster `cluster`'s triangles in SIMD layout (NaN past its last), and which they are.
template <int W>
struct ClusterBatch {
    TriangleBatch<W> batch;
    std::uint32_t prim[W];
    int count = 0;

    ClusterBatch(const ClusterGeometry& g, unsigned cluster) {
        const detail::Mesh& mesh = g.mesh();
        const std::size_t first = std::size_t(cluster) * g.clusterSize();
        count = int(std::min<std::size_t>(g.clusterSize(), g.order().size() - first));
        // In three passes, each load of one independent of the others in flight (the cache
        // misses overlap): the triangles, their vertex numbers, the vertices.
        std::uint32_t vertex[3][W];
        for (int j = 0; j < count; ++j) prim[j] = g.order()[first + std::size_t(j)];
        for (int j = 0; j < count; ++j)
            for (int k = 0; k < 3; ++k) vertex[k][j] = mesh.indices[3 * std::size_t(prim[j]) + k];
        for (int k = 0; k < 3; ++k)
            for (int j = 0; j < count; ++j) {
                const Vec3& p = mesh.positions[vertex[k][j]];
                batch.p[k][0][j] = p.x, batch.p[k][1][j] = p.y, batch.p[k][2][j] = p.z;
            }
        for (auto& v : batch.p)
            for (auto& axis : v)
                for (int j = count; j < W; ++j) axis[j] = std::numeric_limits<float>::quiet_NaN();
    }

    /// Lane j's test: the batch's float result, or hitTriangle where it met an edge.
    bool hit(const BatchResult<W>& r, int j, const ShearedRay& ray, float tnear, float tfar,
             TriangleHit& h) const {
        if (r.edge[j]) {
            const Vec3 p0{batch.p[0][0][j], batch.p[0][1][j], batch.p[0][2][j]};
            const Vec3 p1{batch.p[1][0][j], batch.p[1][1][j], batch.p[1][2][j]};
            const Vec3 p2{batch.p[2][0][j], batch.p[2][1][j], batch.p[2][2][j]};
            return hitTriangle(ray, p0, p1, p2, tnear, tfar, h);
        }
        if (!r.hit[j] || !(r.t[j] <= tfar)) return false;
        h = {r.t[j], r.u[j], r.v[j]};
        return true;
    }
};

template <int W>
void intersectCluster(const RTCIntersectFunctionNArguments* args) {
    const auto& g = *static_cast<const ClusterGeometry*>(args->geometryUserPtr);
    const unsigned N = args->N;
    RTCRayN* ray = RTCRayHitN_RayN(args->rayhit, N);
    RTCHitN* hits = RTCRayHitN_HitN(args->rayhit, N);
    const ClusterBatch<W> cluster(g, args->primID);
    for (unsigned i = 0; i < N; ++i) {
        if (args->valid[i] != -1) continue;
        const ShearedRay r = shearLane(ray, N, i);
        const float tnear = RTCRayN_tnear(ray, N, i);
        float tfar = RTCRayN_tfar(ray, N, i);
        BatchResult<W> result;
        testBatch(cluster.batch, r, tnear, tfar, result);
        // The closest accepted hit: candidates in order, each nearer than the last accepted.
        bool found = false;
        RTCHit best;
        for (int j = 0; j < cluster.count; ++j) {
            TriangleHit h;
            if (!cluster.hit(result, j, r, tnear, tfar, h)) continue;
            RTCHit hit = hitRecord(g.mesh(), cluster.prim[j], h, args->geomID, args->context);
            if (g.alpha() && !filterAccepts(args, g, ray, i, h.t, hit, rtcFilterIntersection))
                continue;
            tfar = h.t;
            best = hit;
            found = true;
        }
        if (!found) continue;
        RTCRayN_tfar(ray, N, i) = tfar;
        RTCHitN_Ng_x(hits, N, i) = best.Ng_x;
        RTCHitN_Ng_y(hits, N, i) = best.Ng_y;
        RTCHitN_Ng_z(hits, N, i) = best.Ng_z;
        RTCHitN_u(hits, N, i) = best.u;
        RTCHitN_v(hits, N, i) = best.v;
        RTCHitN_primID(hits, N, i) = best.primID;
        RTCHitN_geomID(hits, N, i) = best.geomID;
        for (unsigned l = 0; l < RTC_MAX_INSTANCE_LEVEL_COUNT; ++l)
            RTCHitN_instID(hits, N, i, l) = best.instID[l];
    }
}

template <int W>
void occludedCluster(const RTCOccludedFunctionNArguments* args) {
    const auto& g = *static_cast<const ClusterGeometry*>(args->geometryUserPtr);
    const unsigned N = args->N;
    RTCRayN* ray = args->ray;
    const ClusterBatch<W> cluster(g, args->primID);
    for (unsigned i = 0; i < N; ++i) {
        if (args->valid[i] != -1) continue;
        const ShearedRay r = shearLane(ray, N, i);
        const float tnear = RTCRayN_tnear(ray, N, i), tfar = RTCRayN_tfar(ray, N, i);
        BatchResult<W> result;
        testBatch(cluster.batch, r, tnear, tfar, result);
        // Any accepted hit blocks the segment; a filter's rejection (a MASK hole, a BLEND
        // surface counted into the transmittance) goes on with the next triangle, and the
        // filter sees every candidate within the whole segment.
        for (int j = 0; j < cluster.count; ++j) {
            TriangleHit h;
            if (!cluster.hit(result, j, r, tnear, tfar, h)) continue;
            if (g.alpha()) {
                RTCHit hit = hitRecord(g.mesh(), cluster.prim[j], h, args->geomID, args->context);
                if (!filterAccepts(args, g, ray, i, h.t, hit, rtcFilterOcclusion)) continue;
            }
            RTCRayN_tfar(ray, N, i) = -std::numeric_limits<float>::infinity();
            break;
        }
    }
}

}  // namespace

ClusterOrder spatialOrder(const detail::Mesh& mesh) {
    const std::size_t n = mesh.triangleCount();
    GLINT_CHECK(n <= std::numeric_limits<std::uint32_t>::max(),
                "a clustered mesh holds at most 2^32 - 1 triangles");
    const CentroidCoder coder(mesh);
    auto bucketOf = [](std::uint64_t code) { return std::uint16_t(code >> (48 - kBucketBits)); };
    // Step 1: each triangle's bucket (the codes' top bits; 2 bytes a triangle), in parallel,
    // and the buckets' sizes.
    std::vector<std::uint16_t> bucket(n);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                          for (std::size_t t = r.begin(); t < r.end(); ++t)
                              bucket[t] = bucketOf(coder.code(t));
                      });
    std::vector<std::uint32_t> start(kBuckets + 1, 0);
    for (std::size_t t = 0; t < n; ++t) ++start[bucket[t] + 1u];
    for (std::uint32_t b = 0; b < kBuckets; ++b) start[b + 1] += start[b];
    // Step 2: place each triangle in its bucket, in index order.
    ClusterOrder order(n);
    {
        std::vector<std::uint32_t> next(start.begin(), start.end() - 1);
        for (std::size_t t = 0; t < n; ++t) order[next[bucket[t]]++] = std::uint32_t(t);
    }
    std::vector<std::uint16_t>().swap(bucket);
    // Step 3: sort each bucket by the rest of its code, ties by index; buckets in parallel (each
    // on its own, so the order does not depend on the threads).
    constexpr std::uint64_t lowMask = (std::uint64_t(1) << (48 - kBucketBits)) - 1;
    tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, kBuckets, 256),
                      [&](const tbb::blocked_range<std::uint32_t>& r) {
                          std::vector<std::uint64_t> keys;
                          for (std::uint32_t b = r.begin(); b < r.end(); ++b) {
                              const std::uint32_t begin = start[b], end = start[b + 1];
                              if (end - begin < 2) continue;
                              keys.resize(end - begin);
                              for (std::uint32_t j = begin; j < end; ++j)
                                  keys[j - begin] =
                                      (coder.code(order[j]) & lowMask) << 32 | order[j];
                              std::sort(keys.begin(), keys.end());
                              for (std::uint32_t j = begin; j < end; ++j)
                                  order[j] = std::uint32_t(keys[j - begin] & 0xffffffffu);
                          }
                      });
    return order;
}

ClusterGeometry::ClusterGeometry(const detail::Mesh& mesh, std::uint32_t clusterSize)
    : m_mesh(&mesh), m_order(spatialOrder(mesh)), m_size(clusterSize) {
    GLINT_CHECK(clusterSize >= 1 && clusterSize <= kMaxClusterSize,
                "a cluster holds 1 to 16 triangles");
}

RTCGeometryTy* ClusterGeometry::newGeometry(RTCDeviceTy* device, const AlphaTest* alpha) {
    m_alpha = alpha;
    RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_USER);
    if (!geom) return nullptr;
    rtcSetGeometryUserPrimitiveCount(geom, clusterCount());
    rtcSetGeometryUserData(geom, this);
    rtcSetGeometryBoundsFunction(geom, clusterBounds, this);
    // The narrowest SIMD batch that holds a cluster.
    if (m_size <= 4) {
        rtcSetGeometryIntersectFunction(geom, intersectCluster<4>);
        rtcSetGeometryOccludedFunction(geom, occludedCluster<4>);
    } else if (m_size <= 8) {
        rtcSetGeometryIntersectFunction(geom, intersectCluster<8>);
        rtcSetGeometryOccludedFunction(geom, occludedCluster<8>);
    } else {
        rtcSetGeometryIntersectFunction(geom, intersectCluster<16>);
        rtcSetGeometryOccludedFunction(geom, occludedCluster<16>);
    }
    if (alpha) attachAlphaFilterFunctions(geom);
    return geom;
}

}  // namespace glint::render

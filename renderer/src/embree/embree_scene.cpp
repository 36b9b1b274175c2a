// The only file that includes Embree: scene conversion (ending in rtcCommitScene) and queries.
#include "embree/embree_scene.h"

#include <algorithm>
#include <atomic>
#include <limits>
#include <memory>
#include <string>
#include <utility>

#include <embree3/rtcore.h>

#include "embree/alpha_filter.h"
#include "embree/shadow_context.h"
#include "glint/image/error.h"
#include "glint/image/memory.h"

namespace glint::render {

namespace {

void throwDeviceError(RTCDevice device, const char* what) {
    const RTCError code = rtcGetDeviceError(device);
    throw Error(ErrorKind::Internal, std::string("Embree: ") + what + " failed (error " +
                                         std::to_string(int(code)) + ")");
}

/// Meshes above this many triangles are built at Embree's medium quality: the high-quality
/// build (spatial splits) pays for itself on small scenes rendered many times, but on a
/// multi-million-triangle asset it takes seconds and more memory than the mesh.
constexpr std::size_t kHighQualityBuildLimit = 1u << 20;

/// A mesh's positions as they are (object or world space), its index buffer the mesh's own.
RTCGeometry newStaticMesh(RTCDevice device, const detail::Mesh& mesh) {
    RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    const std::size_t vertices = mesh.vertexCount(), triangles = mesh.triangleCount();
    // Embree reads 16 bytes for the last float3: share the mesh's storage only when its
    // allocation reaches that far (SceneData::finish pads it), else copy into Embree's padded
    // buffer.
    if (mesh.positions.capacity() > mesh.positions.size()) {
        rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                   mesh.positions.data(), 0, sizeof(Vec3), vertices);
    } else {
        auto* buffer = static_cast<float*>(rtcSetNewGeometryBuffer(
            geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), vertices));
        if (!buffer) {
            rtcReleaseGeometry(geom);
            throwDeviceError(device, "buffer allocation");
        }
        for (std::size_t v = 0; v < vertices; ++v) {
            buffer[3 * v + 0] = mesh.positions[v].x;
            buffer[3 * v + 1] = mesh.positions[v].y;
            buffer[3 * v + 2] = mesh.positions[v].z;
        }
    }
    rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                               mesh.indices.data(), 0, 3 * sizeof(std::uint32_t), triangles);
    return geom;
}

void attach(RTCScene scene, RTCGeometry geom, unsigned id) {
    rtcCommitGeometry(geom);
    rtcAttachGeometryByID(scene, geom, id);
    rtcReleaseGeometry(geom);
}

}  // namespace

detail::SurfaceId EmbreeScene::surfaceOf(unsigned instID, unsigned geomID, unsigned primID) {
    // Shared meshes are one geometry of their own scene: the top-level instance names it.
    return {instID != RTC_INVALID_GEOMETRY_ID ? instID : geomID, primID};
}

/// A scene of more than kHighQualityBuildLimit triangles gets Embree's medium-quality builder
/// and its compact layout. On a 4M-triangle asset compact took the peak memory from 636 to
/// 378 MB and the build from 1.8 to 1.4 s at the same samples/s
/// (docs/lab/gltf-assets.md, "Speed and memory"); smaller scenes keep the high-quality build, which
/// traces faster. Clusters (Accel) are built at medium quality too: on that asset, 18.3 instead
/// of 21.0 MB at the same rays/s (docs/lab/mesh-memory.md).
void setBuildOptions(RTCScene scene, std::size_t triangles, bool clusters) {
    const bool large = clusters || triangles > kHighQualityBuildLimit;
    rtcSetSceneBuildQuality(scene, large ? RTC_BUILD_QUALITY_MEDIUM : RTC_BUILD_QUALITY_HIGH);
    if (large) rtcSetSceneFlags(scene, RTC_SCENE_FLAG_COMPACT);
}

namespace {

/// The triangles the BVHs hold: a mesh once however many instances, still or moving, share it.
std::size_t bvhTriangles(const detail::SceneData& data) {
    std::vector<bool> counted(data.meshes.size(), false);
    std::size_t triangles = 0;
    for (const detail::Instance& inst : data.instances) {
        if (counted[inst.mesh]) continue;
        counted[inst.mesh] = true;
        triangles += data.meshes[inst.mesh].triangleCount();
    }
    return triangles;
}

// Bytes a triangle costs at the build's peak (Embree's BVH and build arrays; with clusters also
// Glint's order, 4 bytes), and a geometry, from Embree's memory monitor in bench_asset_load on
// generated meshes (docs/renderer.md, "Memory"): the high-quality build 126 over 1M triangles,
// compact triangles 59.4 over 2.4M (34.6 over 4M), clusters 10.6 over 1M and 12.1 over 2.4M; a
// glb of 100k one-triangle meshes 115 bytes a geometry with its triangle. Rounded up.
constexpr std::uint64_t kHighQualityTriangleBytes = 128;
constexpr std::uint64_t kCompactTriangleBytes = 60;
constexpr std::uint64_t kClusterTriangleBytes = 13;
constexpr std::uint64_t kGeometryBytes = 128;

}  // namespace

bool EmbreeScene::buildsClusters(const detail::SceneData& data, Accel accel) {
    return accel == Accel::Clusters ||
           (accel == Accel::Auto && bvhTriangles(data) > kClusterTriangles);
}

std::uint64_t EmbreeScene::estimateBytes(const detail::SceneData& data, bool clusters) {
    const bool compact = data.triangleCount() > kHighQualityBuildLimit;
    std::uint64_t bytes = 0;
    std::vector<bool> counted(data.meshes.size(), false);
    for (const detail::Instance& inst : data.instances) {
        const detail::Mesh& mesh = data.meshes[inst.mesh];
        bytes = saturatingAdd(bytes, kGeometryBytes);
        if (counted[inst.mesh]) continue;  // a shared mesh is built once, moving or not
        counted[inst.mesh] = true;
        const std::uint64_t perTriangle = clusters  ? kClusterTriangleBytes
                                          : compact ? kCompactTriangleBytes
                                                    : kHighQualityTriangleBytes;
        bytes = saturatingAdd(bytes, saturatingMul(mesh.triangleCount(), perTriangle));
    }
    return bytes;
}

std::size_t EmbreeScene::clusterOrderBytes() const {
    std::size_t bytes = 0;
    for (const auto& c : m_clusters) bytes += c->bytes();
    return bytes;
}

/// Converts the scene: geometry i of the top-level scene is instance i — its mesh in world
/// space, or an Embree instance of the mesh's own scene (built once per mesh), whose transform
/// at time step k of a moving instance is its pose at normalised time k / (steps - 1). With
/// clusters every mesh is a clustered geometry. Ends in rtcCommitScene.
RTCScene EmbreeScene::convertScene(RTCDevice device, const detail::SceneData& data, Accel accel) {
    const bool clusters = buildsClusters(data, accel);
    // Held in m_scene at once so that the constructor releases it if the conversion throws.
    RTCScene scene = m_scene = rtcNewScene(device);
    setBuildOptions(scene, data.triangleCount(), clusters);
    // Default (non-robust) traversal: RTC_SCENE_FLAG_ROBUST made cornell ~40 % slower and the
    // closed-sphere furnace test shows no leaks without it.
    std::vector<int> meshScene(data.meshes.size(), -1);
    // Cut-outs and see-through surfaces: a filter on every geometry that may hold one (a
    // shared mesh's when any of its instances may).
    std::vector<bool> instanceAlpha(data.instances.size()), meshAlpha(data.meshes.size());
    for (std::uint32_t i = 0; i < data.instances.size(); ++i) {
        instanceAlpha[i] = needsAlphaTest(data, i);
        if (instanceAlpha[i]) meshAlpha[data.instances[i].mesh] = true;
    }
    // The filter's data of an instance, or of a shared mesh (its instance comes with the hit).
    auto alphaTest = [&](std::uint32_t instance, bool shared) {
        m_alphaTests.push_back(std::make_unique<AlphaTest>(AlphaTest{&data, instance, shared}));
        return m_alphaTests.back().get();
    };
    // A static mesh's geometry, with the filter when `alpha` is set: Embree's triangles, or
    // clusters of them whose callbacks run the same filter.
    auto staticMesh = [&](const detail::Mesh& mesh, const AlphaTest* alpha) {
        if (!clusters) {
            RTCGeometry geom = newStaticMesh(device, mesh);
            if (alpha) attachAlphaFilter(geom, alpha);
            return geom;
        }
        m_clusters.push_back(std::make_unique<ClusterGeometry>(mesh));
        RTCGeometry geom = m_clusters.back()->newGeometry(device, alpha);
        if (!geom) throwDeviceError(device, "user geometry creation");
        return geom;
    };
    for (std::size_t i = 0; i < data.instances.size(); ++i) {
        const detail::Instance& inst = data.instances[i];
        const detail::Mesh& mesh = data.meshes[inst.mesh];
        if (mesh.triangleCount() == 0) continue;
        if (inst.identity && inst.motion < 0) {
            RTCGeometry geom =
                staticMesh(mesh, instanceAlpha[i] ? alphaTest(std::uint32_t(i), false) : nullptr);
            attach(scene, geom, unsigned(i));
            continue;
        }
        // An instance of a mesh in object space: the mesh's scene is built once. A moving
        // instance places it by its pose at each time step, which Embree interpolates linearly
        // between steps: the vertices then move exactly as posed vertices interpolated linearly
        // would (SceneData::posedTriangle), and the mesh's BVH is built once, not once a step.
        int& child = meshScene[inst.mesh];
        if (child < 0) {
            RTCScene meshScene = rtcNewScene(device);
            m_meshScenes.push_back(meshScene);
            setBuildOptions(meshScene, mesh.triangleCount(), clusters);
            RTCGeometry geom =
                staticMesh(mesh, meshAlpha[inst.mesh] ? alphaTest(0, true) : nullptr);
            attach(meshScene, geom, 0);
            rtcCommitScene(meshScene);
            child = int(m_meshScenes.size()) - 1;
        }
        RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_INSTANCE);
        rtcSetGeometryInstancedScene(geom, m_meshScenes[std::size_t(child)]);
        auto setPose = [&](unsigned step, const detail::Affine& pose) {
            float xfm[12];
            for (int r = 0; r < 3; ++r) {
                for (int c = 0; c < 3; ++c) xfm[4 * r + c] = pose.m[r][c];
                xfm[4 * r + 3] = pose.t[r];
            }
            rtcSetGeometryTransform(geom, step, RTC_FORMAT_FLOAT3X4_ROW_MAJOR, xfm);
        };
        if (inst.motion >= 0) {
            const detail::InstanceMotion& motion = data.motions[std::size_t(inst.motion)];
            const int steps = int(motion.steps.size());
            rtcSetGeometryTimeStepCount(geom, unsigned(steps));
            for (int k = 0; k < steps; ++k) setPose(unsigned(k), motion.steps[std::size_t(k)]);
            m_timeSteps.push_back(steps);
        } else {
            setPose(0, inst.transform);
        }
        attach(scene, geom, unsigned(i));
    }
    rtcCommitScene(scene);
    return scene;
}

/// The bytes the device holds, counted by its memory monitor (Embree calls it from its build
/// threads: +bytes before or after an allocation, -bytes after a free).
struct EmbreeScene::MemoryCount {
    std::atomic<std::int64_t> current{0}, peak{0};

    static bool monitor(void* self, ssize_t bytes, bool /*post*/) {
        auto* count = static_cast<MemoryCount*>(self);
        const std::int64_t now = count->current.fetch_add(bytes) + bytes;
        std::int64_t peak = count->peak.load();
        while (now > peak && !count->peak.compare_exchange_weak(peak, now)) {
        }
        return true;
    }
};

EmbreeMemory EmbreeScene::memory() const {
    return {m_memory->current.load(), m_memory->peak.load()};
}

EmbreeScene::EmbreeScene(const detail::SceneData& scene, Accel accel)
    : m_memory(std::make_unique<MemoryCount>()) {
    m_device = rtcNewDevice("verbose=0");
    if (!m_device) throwDeviceError(nullptr, "device creation");
    rtcSetDeviceMemoryMonitorFunction(m_device, &MemoryCount::monitor, m_memory.get());
    // The destructor does not run when the constructor throws: release what exists here.
    try {
        m_scene = convertScene(m_device, scene, accel);
        if (rtcGetDeviceError(m_device) != RTC_ERROR_NONE)
            throwDeviceError(m_device, "scene build");
        // The widest packet the device traces natively.
        for (const auto& [property, width] :
             {std::pair{RTC_DEVICE_PROPERTY_NATIVE_RAY16_SUPPORTED, 16},
              std::pair{RTC_DEVICE_PROPERTY_NATIVE_RAY8_SUPPORTED, 8},
              std::pair{RTC_DEVICE_PROPERTY_NATIVE_RAY4_SUPPORTED, 4}})
            if (rtcGetDeviceProperty(m_device, property) != 0) {
                m_packetWidth = width;
                break;
            }
    } catch (...) {
        if (m_scene) rtcReleaseScene(m_scene);
        for (RTCScene s : m_meshScenes) rtcReleaseScene(s);
        rtcReleaseDevice(m_device);
        throw;
    }
}

EmbreeScene::~EmbreeScene() {
    if (m_scene) rtcReleaseScene(m_scene);
    for (RTCScene s : m_meshScenes) rtcReleaseScene(s);
    if (m_device) rtcReleaseDevice(m_device);
}

bool EmbreeScene::intersect(const Ray& ray, float tMax, Hit& hit, bool coherent) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    if (coherent) context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    RTCRayHit rh;
    rh.ray.org_x = ray.origin.x, rh.ray.org_y = ray.origin.y, rh.ray.org_z = ray.origin.z;
    rh.ray.dir_x = ray.dir.x, rh.ray.dir_y = ray.dir.y, rh.ray.dir_z = ray.dir.z;
    rh.ray.tnear = 0.0f;
    rh.ray.tfar = tMax;
    rh.ray.time = ray.time;
    rh.ray.mask = 0xffffffffu;
    rh.ray.id = 0;
    rh.ray.flags = 0;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(m_scene, &context, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
    hit.t = rh.ray.tfar;
    hit.surface = surfaceOf(rh.hit.instID[0], rh.hit.geomID, rh.hit.primID);
    hit.u = rh.hit.u;
    hit.v = rh.hit.v;
    return true;
}

float EmbreeScene::visibility(const Vec3& origin, const Vec3& dir, float tMax, float time) const {
    // The occluded filter multiplies context.transmittance[id] at each BLEND surface.
    ShadowContext context;
    context.reset(1);
    RTCRay r;
    r.org_x = origin.x, r.org_y = origin.y, r.org_z = origin.z;
    r.dir_x = dir.x, r.dir_y = dir.y, r.dir_z = dir.z;
    r.tnear = 0.0f;
    r.tfar = tMax;
    r.time = time;
    r.mask = 0xffffffffu;
    r.id = 0;
    r.flags = 0;
    rtcOccluded1(m_scene, &context.base, &r);
    // Embree sets tfar to -inf when the ray is blocked.
    return r.tfar < 0.0f ? 0.0f : context.transmittance[0];
}

namespace {

/// Ray and hit packets of each native width, and the functions that trace them.
template <int N>
struct Packet;
template <>
struct Packet<16> {
    using RayHit = RTCRayHit16;
    using Ray = RTCRay16;
    // One declaration each: the two have different types (clang refuses one `auto` for both).
    static constexpr auto intersect = &rtcIntersect16;
    static constexpr auto occluded = &rtcOccluded16;
};
template <>
struct Packet<8> {
    using RayHit = RTCRayHit8;
    using Ray = RTCRay8;
    static constexpr auto intersect = &rtcIntersect8;
    static constexpr auto occluded = &rtcOccluded8;
};
template <>
struct Packet<4> {
    using RayHit = RTCRayHit4;
    using Ray = RTCRay4;
    static constexpr auto intersect = &rtcIntersect4;
    static constexpr auto occluded = &rtcOccluded4;
};

/// Lane k of an SoA packet ray.
template <class R>
void setLane(R& r, int k, const Vec3& origin, const Vec3& dir, float tMax, float time) {
    r.org_x[k] = origin.x, r.org_y[k] = origin.y, r.org_z[k] = origin.z;
    r.dir_x[k] = dir.x, r.dir_y[k] = dir.y, r.dir_z[k] = dir.z;
    r.tnear[k] = 0.0f;
    r.tfar[k] = tMax;
    r.time[k] = time;
    r.mask[k] = 0xffffffffu;
    r.id[k] = 0;
    r.flags[k] = 0;
}

}  // namespace

template <int N>
void EmbreeScene::intersectPackets(std::size_t count, const Ray* const* rays, Hit* hits,
                                   bool* found, bool coherent) const {
    using P = Packet<N>;
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    if (coherent) context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    for (std::size_t first = 0; first < count; first += N) {
        const int lanes = int(std::min<std::size_t>(N, count - first));
        alignas(64) int valid[N];
        alignas(64) typename P::RayHit rh;
        for (int k = 0; k < N; ++k) {
            valid[k] = k < lanes ? -1 : 0;
            const Ray& ray = *rays[first + std::size_t(k < lanes ? k : 0)];
            setLane(rh.ray, k, ray.origin, ray.dir, std::numeric_limits<float>::infinity(),
                    ray.time);
            rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
            rh.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
        }
        P::intersect(valid, m_scene, &context, &rh);
        for (int k = 0; k < lanes; ++k) {
            const std::size_t i = first + std::size_t(k);
            found[i] = rh.hit.geomID[k] != RTC_INVALID_GEOMETRY_ID;
            if (!found[i]) continue;
            hits[i].t = rh.ray.tfar[k];
            hits[i].surface = surfaceOf(rh.hit.instID[0][k], rh.hit.geomID[k], rh.hit.primID[k]);
            hits[i].u = rh.hit.u[k];
            hits[i].v = rh.hit.v[k];
        }
    }
}

template <int N>
void EmbreeScene::visibilityPackets(std::size_t count, const ShadowRay* const* rays,
                                    float* visible) const {
    static_assert(N <= ShadowContext::kLanes);
    using P = Packet<N>;
    ShadowContext context;
    for (std::size_t first = 0; first < count; first += N) {
        const int lanes = int(std::min<std::size_t>(N, count - first));
        context.reset(N);
        alignas(64) int valid[N];
        alignas(64) typename P::Ray r;
        for (int k = 0; k < N; ++k) {
            valid[k] = k < lanes ? -1 : 0;
            const ShadowRay& s = *rays[first + std::size_t(k < lanes ? k : 0)];
            setLane(r, k, s.origin, s.dir, s.tMax, s.time);
            r.id[k] = unsigned(k);  // the filter's index into the context's lanes
        }
        P::occluded(valid, m_scene, &context.base, &r);
        // Embree sets tfar to -inf where the segment is blocked.
        for (int k = 0; k < lanes; ++k)
            visible[first + std::size_t(k)] = r.tfar[k] < 0.0f ? 0.0f : context.transmittance[k];
    }
}

void EmbreeScene::intersectMany(std::size_t count, const Ray* const* rays, Hit* hits, bool* found,
                                bool coherent) const {
    switch (m_packetWidth) {
        case 16:
            return intersectPackets<16>(count, rays, hits, found, coherent);
        case 8:
            return intersectPackets<8>(count, rays, hits, found, coherent);
        case 4:
            return intersectPackets<4>(count, rays, hits, found, coherent);
        default:
            for (std::size_t i = 0; i < count; ++i)
                found[i] =
                    intersect(*rays[i], std::numeric_limits<float>::infinity(), hits[i], coherent);
    }
}

void EmbreeScene::visibilityMany(std::size_t count, const ShadowRay* const* rays,
                                 float* visible) const {
    switch (m_packetWidth) {
        case 16:
            return visibilityPackets<16>(count, rays, visible);
        case 8:
            return visibilityPackets<8>(count, rays, visible);
        case 4:
            return visibilityPackets<4>(count, rays, visible);
        default:
            for (std::size_t i = 0; i < count; ++i)
                visible[i] =
                    visibility(rays[i]->origin, rays[i]->dir, rays[i]->tMax, rays[i]->time);
    }
}

}  // namespace glint::render

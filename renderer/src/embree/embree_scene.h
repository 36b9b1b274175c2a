// The Embree BVH of a scene behind a small interface: the rest of the renderer never sees
// <embree3/rtcore.h>.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "embree/alpha_filter.h"
#include "embree/cluster_geometry.h"
#include "glint/render/settings.h"
#include "scene/camera.h"
#include "scene/scene_data.h"
#include "vecmath.h"

struct RTCDeviceTy;
struct RTCSceneTy;

namespace glint::render {

/// The closest hit of a ray: distance, the instance and its mesh's triangle, and barycentrics
/// (p = (1-u-v) p0 + u p1 + v p2).
struct Hit {
    float t = 0.0f;
    detail::SurfaceId surface;
    float u = 0.0f, v = 0.0f;
};

/// A segment for an occlusion query: from origin along dir within (0, tMax) at shutter time.
struct ShadowRay {
    Vec3 origin, dir;
    float tMax = 0.0f, time = 0.0f;
};

/// Bytes an Embree device holds (its memory monitor): the BVH and, while building, the build's
/// temporary arrays — not the mesh arrays Embree reads in place.
struct EmbreeMemory {
    std::int64_t current = 0;  ///< now
    std::int64_t peak = 0;     ///< at most since the device was made (the build's peak)
};

/// Embree device + committed scene of one SceneData. Geometry i of the top-level scene is
/// instance i: a triangle mesh in world space (a mesh only it uses), an Embree instance of the
/// mesh's own scene (a mesh several instances share, which is built once), or a motion-blur
/// triangle mesh (a moving instance). With clusters (Accel), a static mesh is a clustered
/// geometry instead of Embree's triangles (embree/cluster_geometry.h); hits are the same.
class EmbreeScene {
  public:
    /// Converts the scene (see convertScene in embree_scene.cpp) over the primitives `accel`
    /// names. Throws glint::Error on failure.
    explicit EmbreeScene(const detail::SceneData& scene, Accel accel = Accel::Auto);
    ~EmbreeScene();
    EmbreeScene(const EmbreeScene&) = delete;
    EmbreeScene& operator=(const EmbreeScene&) = delete;

    /// Closest hit along the ray within (0, tMax) at the ray's shutter time; `coherent` hints
    /// primary rays. hit.surface names the instance and its triangle.
    bool intersect(const Ray& ray, float tMax, Hit& hit, bool coherent = false) const;
    /// The fraction of light that passes the segment from origin along dir within (0, tMax) at
    /// normalised shutter time `time`: 0 when something opaque (or a MASK surface where it is
    /// there) blocks it, else the product of 1 − alpha over the BLEND surfaces it crosses (1
    /// for a clear segment).
    float visibility(const Vec3& origin, const Vec3& dir, float tMax, float time = 0.0f) const;

    /// Number of meshes built once and shared by several instances.
    int sharedMeshCount() const { return int(m_meshScenes.size()); }

    /// intersect() of `count` rays (tMax ∞) at once, in packets of the device's native width
    /// (16, 8 or 4 lanes; one at a time without packet support): found[i] says whether
    /// *rays[i] hit, and hits[i] is its hit. Packets pay Embree's per-query overhead once per
    /// packet and keep its traversal code hot (docs/renderer.md, "Wavefront").
    void intersectMany(std::size_t count, const Ray* const* rays, Hit* hits, bool* found,
                       bool coherent) const;
    /// visibility() of `count` segments at once, as intersectMany.
    void visibilityMany(std::size_t count, const ShadowRay* const* rays, float* visible) const;

    /// What the device holds now and held at most (the build included).
    EmbreeMemory memory() const;

    /// Number of meshes traced as clusters (0: Embree's triangles throughout).
    int clusteredMeshCount() const { return int(m_clusters.size()); }
    /// Bytes of the clustered meshes' triangle orders (Glint's, beside memory()'s Embree bytes).
    std::size_t clusterOrderBytes() const;
    /// Triangles a cluster holds (0 without clusters).
    int clusterSize() const { return m_clusters.empty() ? 0 : int(m_clusters[0]->clusterSize()); }

    /// Whether the scene built over `accel` is traced as clusters (Auto: when the BVHs would hold
    /// more than kClusterTriangles triangles, a mesh shared by instances counted once).
    static bool buildsClusters(const detail::SceneData& scene, Accel accel);
    /// Bytes building the scene's structures takes at its peak, over clusters or over Embree's
    /// triangles: Embree's BVHs and build arrays and the clusters' triangle orders, estimated from
    /// the BVHs' triangles and geometries by the rates measured on generated meshes
    /// (docs/renderer.md, "Memory").
    static std::uint64_t estimateBytes(const detail::SceneData& scene, bool clusters);

    /// Number of moving instances built (0 for a scene without moving shapes).
    int motionGeometryCount() const { return int(m_timeSteps.size()); }
    /// Embree time steps of moving instance i (< motionGeometryCount()).
    int timeStepCount(int i) const { return m_timeSteps[std::size_t(i)]; }

  private:
    RTCSceneTy* convertScene(RTCDeviceTy* device, const detail::SceneData& data, Accel accel);
    template <int N>
    void intersectPackets(std::size_t count, const Ray* const* rays, Hit* hits, bool* found,
                          bool coherent) const;
    template <int N>
    void visibilityPackets(std::size_t count, const ShadowRay* const* rays, float* visible) const;
    /// The instance and triangle of Embree's hit (top-level instance, geometry, primitive).
    static detail::SurfaceId surfaceOf(unsigned instID, unsigned geomID, unsigned primID);

    struct MemoryCount;  // the monitor's running count (embree_scene.cpp)
    std::unique_ptr<MemoryCount> m_memory;
    RTCDeviceTy* m_device = nullptr;
    RTCSceneTy* m_scene = nullptr;
    int m_packetWidth = 1;                  // 16, 8, 4 or 1 (no packet support)
    std::vector<RTCSceneTy*> m_meshScenes;  // the scene of each shared mesh
    std::vector<int> m_timeSteps;           // of each moving instance, in instance order
    std::vector<std::unique_ptr<AlphaTest>> m_alphaTests;      // the filters' data (alpha_filter.h)
    std::vector<std::unique_ptr<ClusterGeometry>> m_clusters;  // of each clustered mesh
};

}  // namespace glint::render

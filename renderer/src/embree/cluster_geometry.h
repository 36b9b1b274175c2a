// A clustered triangle geometry for large meshes (docs/lab/gltf-assets.md, "Speed and memory"):
// Embree
// builds its BVH over clusters of a few spatially coherent triangles (an Embree user geometry),
// and Glint's own callbacks intersect a cluster's triangles with a watertight ray–triangle test.
// Embree then holds a BVH over N/k primitives instead of N; Glint adds one uint32 a triangle
// (the spatial order). The mesh itself is not touched: a hit reports the mesh's own triangle.
#pragma once

#include <cstddef>
#include <cstdint>
#include <new>
#include <vector>

#include "scene/scene_data.h"

struct RTCDeviceTy;
struct RTCGeometryTy;

namespace glint::render {

struct AlphaTest;

/// Allocates on 64-byte boundaries, so that a cluster of 16 uint32 triangle numbers is one
/// cache line (a large std::vector's storage starts 16 bytes into a page).
template <class T>
struct CacheLineAllocator {
    using value_type = T;
    CacheLineAllocator() = default;
    template <class U>
    CacheLineAllocator(const CacheLineAllocator<U>&) {}
    T* allocate(std::size_t n) {
        return static_cast<T*>(::operator new(n * sizeof(T), std::align_val_t(64)));
    }
    void deallocate(T* p, std::size_t) { ::operator delete(p, std::align_val_t(64)); }
    bool operator==(const CacheLineAllocator&) const { return true; }
};

/// The triangles of a mesh in cluster order.
using ClusterOrder = std::vector<std::uint32_t, CacheLineAllocator<std::uint32_t>>;

/// Triangles a cluster holds. Of k = 4, 8 and 16 measured on a 4M-triangle asset
/// (docs/lab/mesh-memory.md), 16 alone keeps the asset within 1.5× its mesh data; it also
/// builds fastest.
inline constexpr std::uint32_t kClusterSize = 16;
/// The most triangles a cluster may hold (one SIMD batch of 16 lanes).
inline constexpr std::uint32_t kMaxClusterSize = 16;

/// A deterministic spatial order of the mesh's triangles: by the Hilbert index of their
/// centroids (16 bits an axis over the centroids' bounding cube), ties by triangle index. Sorted
/// in buckets of the indices' top 16 bits, so that the temporary arrays are a bucket number a
/// triangle (2 bytes), a 256 KB histogram and a bucket's keys per thread, not a key per
/// triangle. Non-finite centroids come last.
ClusterOrder spatialOrder(const detail::Mesh& mesh);

/// The clusters of one mesh: cluster c is the triangles order[c·k, c·k + k) (the last one may
/// hold fewer), and the Embree user geometry that traces them.
class ClusterGeometry {
  public:
    /// Orders `mesh` (which must outlive this object, unchanged) into clusters of
    /// `clusterSize` triangles.
    explicit ClusterGeometry(const detail::Mesh& mesh, std::uint32_t clusterSize = kClusterSize);
    ClusterGeometry(const ClusterGeometry&) = delete;
    ClusterGeometry& operator=(const ClusterGeometry&) = delete;

    /// A new Embree user geometry of the clusters, for the caller to commit and attach. Hits
    /// follow Embree's triangle conventions (t, u and v with p = (1-u-v) p0 + u p1 + v p2, Ng,
    /// primID = the mesh's triangle, geomID, the instance stack). With `alpha`, every candidate
    /// hit goes through the alpha filter functions (embree/alpha_filter.h) with `alpha` as
    /// their data. This object (and `alpha`) must outlive the geometry.
    RTCGeometryTy* newGeometry(RTCDeviceTy* device, const AlphaTest* alpha);

    const detail::Mesh& mesh() const { return *m_mesh; }
    /// The triangles in cluster order (each of the mesh's triangles once).
    const ClusterOrder& order() const { return m_order; }
    std::uint32_t clusterSize() const { return m_size; }
    std::uint32_t clusterCount() const {
        return std::uint32_t((m_order.size() + m_size - 1) / m_size);
    }
    /// The alpha filter's data, or null when the geometry has no filter.
    const AlphaTest* alpha() const { return m_alpha; }
    /// Bytes of the order array (allocated).
    std::size_t bytes() const { return m_order.capacity() * sizeof(std::uint32_t); }

  private:
    const detail::Mesh* m_mesh;
    ClusterOrder m_order;
    std::uint32_t m_size;
    const AlphaTest* m_alpha = nullptr;
};

}  // namespace glint::render

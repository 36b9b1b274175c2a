// A clustered triangle geometry for large meshes (docs/assets.md, "Speed and memory"): Embree
// builds its BVH over clusters of a few spatially coherent triangles (an Embree user geometry),
// and Glint's own callbacks intersect a cluster's triangles with a watertight ray–triangle test.
// Embree then holds a BVH over N/k primitives instead of N; Glint adds one uint32 a triangle
// (the spatial order). The mesh itself is not touched: a hit reports the mesh's own triangle.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "scene/scene_data.h"

struct RTCDeviceTy;
struct RTCGeometryTy;

namespace glint::render {

struct AlphaTest;

/// Triangles a cluster holds (docs/research/mesh-memory.md: k = 4, 8 and 16 measured).
inline constexpr std::uint32_t kClusterSize = 8;

/// A deterministic spatial order of the mesh's triangles: by the Morton code of their centroids
/// (16 bits an axis over the centroids' bounding cube), ties by triangle index. Sorted in
/// buckets of the codes' top 16 bits, so that the temporary arrays are a 256 KB histogram and
/// one bucket's keys, not a key per triangle. Non-finite centroids come last.
std::vector<std::uint32_t> spatialOrder(const detail::Mesh& mesh);

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
    const std::vector<std::uint32_t>& order() const { return m_order; }
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
    std::vector<std::uint32_t> m_order;
    std::uint32_t m_size;
    const AlphaTest* m_alpha = nullptr;
};

}  // namespace glint::render

// Test and benchmark hooks of the Renderer: the ray kernel's throughput and how often the
// renderer built its structures. Not part of the public API (docs/architecture.md, "Public
// headers"); tests and lab/bench include it with renderer/src on their include path.
#pragma once

#include <cstdint>

#include "glint/render/renderer.h"

namespace glint::render::detail {

/// Throughput of the ray-tracing kernel alone (no shading), for benchmarks.
struct RayThroughput {
    std::uint64_t rays = 0;
    double seconds = 0.0;
    std::uint64_t hits = 0;
};

/// Traces `rays` rays (half camera rays, half rays with uniform origins in the scene's bounding
/// box and uniform directions) with `renderer`'s raw intersection kernel on `threads` threads
/// (0 = all): one query a ray, or with `packets` the renderer's packet queries (the device's
/// native width) over chunks of 4096 rays.
RayThroughput measureRayThroughput(const Renderer& renderer, std::uint64_t rays, int threads,
                                   std::uint64_t seed = 1, bool packets = false);

/// How many times `renderer` built its ray-tracing structures (Embree BVH): 1 for its life,
/// since look edits never need a rebuild.
int accelerationBuilds(const Renderer& renderer);
/// Bytes `renderer`'s Embree device holds now (the BVH) and held at most (the build's peak), as
/// Embree's memory monitor counts them: not the mesh arrays Embree reads in place. With
/// clusters (Accel), also the bytes of the clusters' triangle order (Glint's) and how many
/// meshes are clustered (0: Embree's triangles throughout).
struct AccelerationMemory {
    std::int64_t current = 0, peak = 0;
    std::int64_t clusterOrder = 0;
    int clusteredMeshes = 0;
    int clusterSize = 0;  ///< triangles a cluster holds (0 without clusters)
};
AccelerationMemory accelerationMemory(const Renderer& renderer);
/// How many times `renderer` built its light sampling structures (once, plus once per render
/// after a look edit).
int lightBuilds(const Renderer& renderer);

}  // namespace glint::render::detail

// Cut-outs and see-through surfaces (glTF alphaMode MASK and BLEND) through Embree's filter
// functions: a hit where a MASK surface is not there is rejected before the traversal accepts
// it, for closest hits and shadow rays alike. A BLEND hit is left to the closest-hit query's
// caller, which chooses with its sampler's numbers whether the ray meets the surface
// (PathIntegrator); a shadow ray does not choose at a BLEND surface but carries its 1 − alpha
// on (embree/shadow_context.h).
#pragma once

#include <cstdint>

#include "scene/scene_data.h"
#include "vecmath.h"

struct RTCGeometryTy;

namespace glint::render {

/// What a filter needs to find the material of a hit on one Embree geometry.
struct AlphaTest {
    const detail::SceneData* scene = nullptr;
    std::uint32_t instance = 0;  ///< the instance the geometry is (unused when shared)
    bool shared = false;         ///< a mesh of its own scene: the hit's instance ID names it
};

/// The surface's presence at barycentrics (b1, b2) of triangle `prim` of `instance`: the
/// material's opacity times its base-colour texture's alpha; 1 for an opaque material.
float surfaceAlpha(const detail::SceneData& scene, std::uint32_t instance, std::uint32_t prim,
                   float b1, float b2);

/// True when some triangle of `instance` may be cut out or see-through (its material's
/// alphaMode is not Opaque): only such geometries get a filter.
bool needsAlphaTest(const detail::SceneData& scene, std::uint32_t instance);

/// A number in [0, 1) hashed from a ray (origin, direction) and the triangle `prim` of
/// `instance` it meets: the same ray through the same surface gives the same number (the render
/// does not depend on threads), other rays or surfaces independent ones. The choice at a BLEND
/// surface where no sampler's number is left for it.
float blendHash(const Vec3& origin, const Vec3& dir, std::uint32_t instance, std::uint32_t prim);

/// Installs the filter on `geometry` (before it is committed); `test` must outlive it.
void attachAlphaFilter(RTCGeometryTy* geometry, const AlphaTest* test);
/// Installs the filter functions alone, for a geometry whose user data is its own: its
/// callbacks hand the filters an AlphaTest as their geometryUserPtr (rtcFilterIntersection,
/// rtcFilterOcclusion; embree/cluster_geometry.cpp).
void attachAlphaFilterFunctions(RTCGeometryTy* geometry);

}  // namespace glint::render

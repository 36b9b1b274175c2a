#include "embree/alpha_filter.h"

#include <bit>
#include <cstring>

#include <embree3/rtcore.h>

#include "embree/shadow_context.h"
#include "glint/image/error.h"

namespace glint::render {

float surfaceAlpha(const detail::SceneData& scene, std::uint32_t instance, std::uint32_t prim,
                   float b1, float b2) {
    const detail::Material& m = scene.materials[scene.materialOf(instance, prim)];
    if (m.alphaMode == detail::AlphaMode::Opaque) return 1.0f;
    float alpha = m.opacity;
    const detail::Mesh& mesh = scene.meshes[scene.instances[instance].mesh];
    if (m.texture >= 0 && !mesh.uvs.empty()) {
        const Vec2 uv = detail::surfaceUv(mesh, m.textureTransform.set, prim, b1, b2);
        alpha *= scene.textures[std::size_t(m.texture)].lookup(m.textureTransform.apply(uv)).w;
    }
    // glTF's COLOR_0 alpha multiplies a glTF material's alpha.
    if (m.textureTimesFactor && !mesh.colors.empty())
        alpha *= detail::vertexColor(mesh, prim, b1, b2).w;
    return alpha;
}

bool needsAlphaTest(const detail::SceneData& scene, std::uint32_t instance) {
    const detail::Instance& inst = scene.instances[instance];
    const detail::Mesh& mesh = scene.meshes[inst.mesh];
    for (std::uint32_t t = 0; t < mesh.triangleCount(); ++t) {
        if (scene.materials[scene.materialOf(instance, t)].alphaMode != detail::AlphaMode::Opaque)
            return true;
        if (inst.material >= 0) break;  // one material for every triangle
    }
    return false;
}

float blendHash(const Vec3& origin, const Vec3& dir, std::uint32_t instance, std::uint32_t prim) {
    const float key[] = {origin.x,
                         origin.y,
                         origin.z,
                         dir.x,
                         dir.y,
                         dir.z,
                         std::bit_cast<float>(prim),
                         std::bit_cast<float>(instance)};
    std::uint64_t h = 0x9e3779b97f4a7c15ULL;
    for (float value : key) {
        h ^= std::bit_cast<std::uint32_t>(value);
        h *= 0xbf58476d1ce4e5b9ULL;
        h ^= h >> 31;
    }
    h *= 0x94d049bb133111ebULL;
    h ^= h >> 29;
    return float(h >> 40) * 0x1p-24f;
}

namespace {

/// Lane i's hit on a surface that may be cut out or see-through: where it is and how present.
struct AlphaHit {
    std::uint32_t instance = 0, prim = 0;
    detail::AlphaMode mode = detail::AlphaMode::Opaque;
    float alpha = 1.0f;   ///< surfaceAlpha at the hit
    float cutoff = 0.0f;  ///< the material's MASK cut-off
};

/// Lane i's hit, or false for an opaque material, or for a BLEND one unless `blend` (the filter
/// leaves such a hit alone).
bool alphaHit(const RTCFilterFunctionNArguments* args, unsigned i, bool blend, AlphaHit& hit) {
    const auto* test = static_cast<const AlphaTest*>(args->geometryUserPtr);
    hit.prim = RTCHitN_primID(args->hit, args->N, i);
    hit.instance = test->shared ? RTCHitN_instID(args->hit, args->N, i, 0) : test->instance;
    const detail::Material& m =
        test->scene->materials[test->scene->materialOf(hit.instance, hit.prim)];
    if (m.alphaMode == detail::AlphaMode::Opaque ||
        (!blend && m.alphaMode == detail::AlphaMode::Blend))
        return false;
    hit.mode = m.alphaMode;
    hit.cutoff = m.alphaCutoff;
    hit.alpha = surfaceAlpha(*test->scene, hit.instance, hit.prim, RTCHitN_u(args->hit, args->N, i),
                             RTCHitN_v(args->hit, args->N, i));
    return true;
}

/// Stochastic transparency: lane i's ray passes a BLEND surface of presence alpha with
/// probability 1 − alpha, the same way every time it meets the same triangle.
bool passesStochastically(const RTCFilterFunctionNArguments* args, unsigned i,
                          const AlphaHit& hit) {
    const Vec3 origin{RTCRayN_org_x(args->ray, args->N, i), RTCRayN_org_y(args->ray, args->N, i),
                      RTCRayN_org_z(args->ray, args->N, i)};
    const Vec3 dir{RTCRayN_dir_x(args->ray, args->N, i), RTCRayN_dir_y(args->ray, args->N, i),
                   RTCRayN_dir_z(args->ray, args->N, i)};
    return blendHash(origin, dir, hit.instance, hit.prim) >= hit.alpha;
}

/// Closest hits: MASK cuts out below its cut-off. A BLEND hit is accepted: the caller chooses
/// whether its ray meets the surface (PathIntegrator, with the bounce's component number).
void intersectFilter(const RTCFilterFunctionNArguments* args) {
    for (unsigned i = 0; i < args->N; ++i) {
        AlphaHit hit;
        if (args->valid[i] != -1 || !alphaHit(args, i, false, hit)) continue;
        if (hit.alpha < hit.cutoff) args->valid[i] = 0;
    }
}

/// Shadow rays (the context is a ShadowContext): MASK as for closest hits; a BLEND hit
/// multiplies the lane's transmittance by 1 − alpha and is rejected so that the traversal goes
/// on — once per triangle, however often Embree reports it; past ShadowContext::kSeen counted
/// triangles a lane falls back to the stochastic decision, which keeps the estimate unbiased.
void occludedFilter(const RTCFilterFunctionNArguments* args) {
    auto* shadow =
        reinterpret_cast<ShadowContext*>(const_cast<RTCIntersectContext*>(args->context));
    for (unsigned i = 0; i < args->N; ++i) {
        AlphaHit hit;
        if (args->valid[i] != -1 || !alphaHit(args, i, true, hit)) continue;
        if (hit.mode == detail::AlphaMode::Mask) {
            if (hit.alpha < hit.cutoff) args->valid[i] = 0;
            continue;
        }
        const unsigned lane = RTCRayN_id(args->ray, args->N, i);
        GLINT_DCHECK(lane < unsigned(ShadowContext::kLanes));
        const int seen = shadow->seenCount[lane];
        bool counted = false;
        for (int s = 0; s < seen && !counted; ++s)
            counted = shadow->seenPrim[lane][s] == hit.prim &&
                      shadow->seenInstance[lane][s] == hit.instance;
        if (!counted && seen < ShadowContext::kSeen) {
            shadow->seenInstance[lane][seen] = hit.instance;
            shadow->seenPrim[lane][seen] = hit.prim;
            shadow->seenCount[lane] = std::uint8_t(seen + 1);
            shadow->transmittance[lane] *= 1.0f - hit.alpha;
            counted = true;
        }
        // Reject (pass through) unless nothing gets through any more: then accepting the hit
        // ends the traversal with the segment blocked.
        const bool pass =
            counted ? shadow->transmittance[lane] > 0.0f : passesStochastically(args, i, hit);
        if (pass) args->valid[i] = 0;
    }
}

}  // namespace

void attachAlphaFilter(RTCGeometryTy* geometry, const AlphaTest* test) {
    rtcSetGeometryUserData(geometry, const_cast<AlphaTest*>(test));
    attachAlphaFilterFunctions(geometry);
}

void attachAlphaFilterFunctions(RTCGeometryTy* geometry) {
    rtcSetGeometryIntersectFilterFunction(geometry, intersectFilter);
    rtcSetGeometryOccludedFilterFunction(geometry, occludedFilter);
}

}  // namespace glint::render

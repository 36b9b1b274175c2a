#include "embree/alpha_filter.h"

#include <bit>
#include <cstring>

#include <embree3/rtcore.h>

namespace glint::render {

float surfaceAlpha(const detail::SceneData& scene, std::uint32_t instance, std::uint32_t prim,
                   float b1, float b2) {
    const detail::Material& m = scene.materials[scene.materialOf(instance, prim)];
    if (m.alphaMode == detail::AlphaMode::Opaque) return 1.0f;
    float alpha = m.opacity;
    const detail::Mesh& mesh = scene.meshes[scene.instances[instance].mesh];
    if (m.texture >= 0 && !mesh.uvs.empty()) {
        const std::uint32_t* idx = &mesh.indices[3 * std::size_t(prim)];
        const float b0 = 1.0f - b1 - b2;
        const Vec2 &a = mesh.uvs[idx[0]], &b = mesh.uvs[idx[1]], &c = mesh.uvs[idx[2]];
        const Vec2 uv{a.x * b0 + b.x * b1 + c.x * b2, a.y * b0 + b.y * b1 + c.y * b2};
        alpha *= scene.textures[std::size_t(m.texture)].lookup(m.textureTransform.apply(uv)).w;
    }
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

namespace {

/// A number in [0, 1) from the ray and the surface it meets, so that the same ray through the
/// same surface decides the same way (determinism) and other rays independently.
float hashUniform(const float* values, int count) {
    std::uint64_t h = 0x9e3779b97f4a7c15ULL;
    for (int i = 0; i < count; ++i) {
        h ^= std::bit_cast<std::uint32_t>(values[i]);
        h *= 0xbf58476d1ce4e5b9ULL;
        h ^= h >> 31;
    }
    h *= 0x94d049bb133111ebULL;
    h ^= h >> 29;
    return float(h >> 40) * 0x1p-24f;
}

void alphaFilter(const RTCFilterFunctionNArguments* args) {
    const auto* test = static_cast<const AlphaTest*>(args->geometryUserPtr);
    const detail::SceneData& scene = *test->scene;
    for (unsigned i = 0; i < args->N; ++i) {
        if (args->valid[i] != -1) continue;
        const unsigned prim = RTCHitN_primID(args->hit, args->N, i);
        const float b1 = RTCHitN_u(args->hit, args->N, i), b2 = RTCHitN_v(args->hit, args->N, i);
        const std::uint32_t instance =
            test->shared ? RTCHitN_instID(args->hit, args->N, i, 0) : test->instance;
        const detail::Material& m = scene.materials[scene.materialOf(instance, prim)];
        if (m.alphaMode == detail::AlphaMode::Opaque) continue;
        const float alpha = surfaceAlpha(scene, instance, prim, b1, b2);
        bool reject = false;
        if (m.alphaMode == detail::AlphaMode::Mask) {
            reject = alpha < m.alphaCutoff;
        } else {
            // Blend: the surface is met with probability alpha (stochastic transparency).
            const float key[] = {
                RTCRayN_org_x(args->ray, args->N, i), RTCRayN_org_y(args->ray, args->N, i),
                RTCRayN_org_z(args->ray, args->N, i), RTCRayN_dir_x(args->ray, args->N, i),
                RTCRayN_dir_y(args->ray, args->N, i), RTCRayN_dir_z(args->ray, args->N, i),
                std::bit_cast<float>(prim),           std::bit_cast<float>(instance)};
            reject = hashUniform(key, 8) >= alpha;
        }
        if (reject) args->valid[i] = 0;
    }
}

}  // namespace

void attachAlphaFilter(RTCGeometryTy* geometry, const AlphaTest* test) {
    rtcSetGeometryUserData(geometry, const_cast<AlphaTest*>(test));
    rtcSetGeometryIntersectFilterFunction(geometry, alphaFilter);
    rtcSetGeometryOccludedFilterFunction(geometry, alphaFilter);
}

}  // namespace glint::render

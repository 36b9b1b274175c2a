#include "integrators/surface_inputs.h"

#include <algorithm>
#include <cmath>

namespace glint::render {

namespace {

/// Texture slot `slot` looked up at the hit (its uv transform applied).
Vec4 lookup(const detail::SceneData& scene, const detail::TextureSlot& slot,
            const SurfacePoint& at) {
    return scene.textures[std::size_t(slot.texture)].lookup(slot.transform.apply(at.uv));
}

}  // namespace

SurfaceInputs evaluateInputs(const detail::SceneData& scene, const detail::Material& material,
                             const SurfacePoint& at) {
    SurfaceInputs in;
    in.albedo = material.albedo;
    in.metallic = material.metallic;
    in.roughness = material.roughness;
    in.transmission = material.transmission;
    if (!at.hasUv) return in;
    if (material.texture >= 0) {
        const Vec4 t = scene.textures[std::size_t(material.texture)].lookup(
            material.textureTransform.apply(at.uv));
        const Vec3 rgb{t.x, t.y, t.z};
        in.albedo = material.textureTimesFactor ? in.albedo * rgb : rgb;
    }
    if (material.type == detail::MaterialType::MetallicRoughness &&
        material.roughnessMetallicMap.present()) {
        // glTF: roughness in G, metallic in B, each multiplying its factor.
        const Vec4 t = lookup(scene, material.roughnessMetallicMap, at);
        in.roughness = std::clamp(in.roughness * t.y, 0.0f, 1.0f);
        in.metallic = std::clamp(in.metallic * t.z, 0.0f, 1.0f);
    }
    if (material.type == detail::MaterialType::MetallicRoughness &&
        material.transmissionMap.present()) {
        // KHR_materials_transmission: the texture's R multiplies the factor.
        const Vec4 t = lookup(scene, material.transmissionMap, at);
        in.transmission = std::clamp(in.transmission * t.x, 0.0f, 1.0f);
    }
    return in;
}

Vec3 emissionAt(const detail::SceneData& scene, const detail::Material& material,
                const SurfacePoint& at) {
    if (!material.emissionMap.present() || !at.hasUv) return material.emission;
    const Vec4 t = lookup(scene, material.emissionMap, at);
    return material.emission * Vec3{t.x, t.y, t.z};
}

Vec3 applyNormalMap(const detail::SceneData& scene, const detail::Material& material,
                    const SurfacePoint& at, const Vec3& ns) {
    if (!material.normalMap.present() || !at.hasUv) return ns;
    const detail::Instance& inst = scene.instances[at.id.instance];
    const detail::Mesh& mesh = scene.meshes[inst.mesh];
    if (mesh.tangents.empty()) return ns;
    const std::uint32_t* idx = &mesh.indices[3 * std::size_t(at.id.prim)];
    const float b0 = 1.0f - at.b1 - at.b2;
    const Vec4 &t0 = mesh.tangents[idx[0]], &t1 = mesh.tangents[idx[1]],
               &t2 = mesh.tangents[idx[2]];
    Vec3 tangent{t0.x * b0 + t1.x * at.b1 + t2.x * at.b2, t0.y * b0 + t1.y * at.b1 + t2.y * at.b2,
                 t0.z * b0 + t1.z * at.b1 + t2.z * at.b2};
    const float handedness = t0.w < 0.0f ? -1.0f : 1.0f;
    // The bitangent in the mesh's space, from its own normal, then both into the world (a
    // moving instance takes its shutter-open pose: the bend is a shading detail).
    Vec3 normal = ns;
    if (!mesh.normals.empty()) {
        const Vec3 &n0 = mesh.normals[idx[0]], &n1 = mesh.normals[idx[1]],
                   &n2 = mesh.normals[idx[2]];
        normal = n0 * b0 + n1 * at.b1 + n2 * at.b2;
    }
    Vec3 bitangent = cross(normal, tangent) * handedness;
    if (!inst.identity) {
        tangent = inst.transform.vector(tangent);
        bitangent = inst.transform.vector(bitangent);
    }
    // Orthogonal to the shading normal (Gram–Schmidt); degenerate frames leave ns as it is.
    tangent = tangent - ns * dot(ns, tangent);
    const float tl = length(tangent);
    if (!(tl > 0.0f)) return ns;
    tangent = tangent / tl;
    // The side the viewer sees: ns may have been flipped for a two-sided surface.
    const float side = dot(cross(ns, tangent), bitangent) < 0.0f ? -1.0f : 1.0f;
    bitangent = cross(ns, tangent) * side;
    const Vec4 t = lookup(scene, material.normalMap, at);
    const float x = (2.0f * t.x - 1.0f) * material.normalScale;
    const float y = (2.0f * t.y - 1.0f) * material.normalScale;
    const float z = 2.0f * t.z - 1.0f;
    const Vec3 bent = tangent * x + bitangent * y + ns * z;
    const float len = length(bent);
    return len > 0.0f && std::isfinite(len) ? bent / len : ns;
}

}  // namespace glint::render

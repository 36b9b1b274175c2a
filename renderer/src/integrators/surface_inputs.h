// What a material's textures give at one hit, before its BSDF is built: the base colour, the
// metallic-roughness material's metallic, roughness and transmission (factors times their
// texture), and the shading normal bent by a tangent-space normal map (glTF's conventions:
// docs/assets.md).
#pragma once

#include "materials/bsdf.h"
#include "scene/scene_data.h"
#include "vecmath.h"

namespace glint::render {

/// A hit's place on its mesh: the instance and triangle, barycentrics (p = (1−b1−b2) p0 + b1 p1
/// + b2 p2) and the interpolated texture coordinates (when the mesh has them).
struct SurfacePoint {
    detail::SurfaceId id;
    float b1 = 0.0f, b2 = 0.0f;
    Vec2 uv;
    bool hasUv = false;
    /// The change of uv for a step of one pixel in x and y (zero: texture lookups are bilinear).
    detail::TexFootprint footprint;
    /// The second set (Mesh::uvs1) and its footprint, read by slots with UvTransform::set 1.
    bool hasUv1 = false;
    Vec2 uv1;
    detail::TexFootprint footprint1;
};

/// True when `material` reads a texture (so that a hit needs its footprint).
inline bool usesTextures(const detail::Material& material) {
    return material.texture >= 0 || material.roughnessMetallicMap.present() ||
           material.normalMap.present() || material.emissionMap.present() ||
           material.bumpMap.present();
}

/// The uv footprint (SurfacePoint::footprint) of surface steps dpdx and dpdy (world space) on
/// triangle `tri` (world space) whose corners have texture coordinates uv0, uv1, uv2: each step
/// written in the triangle's edges by least squares (as pbrt-v4's
/// SurfaceInteraction::ComputeDifferentials, with the edges for dp/du, dp/dv), then mapped to uv.
detail::TexFootprint uvFootprint(const detail::TriangleView& tri, const Vec2& uv0, const Vec2& uv1,
                                 const Vec2& uv2, const Vec3& dpdx, const Vec3& dpdy);

/// The textured inputs of `material` at `at`.
using SurfaceInputs = BsdfInputs;

/// The inputs of `material` where it reads no texture nor vertex colour: its factors.
inline SurfaceInputs factorInputs(const detail::Material& material) {
    return {material.albedo, material.metallic, material.roughness, material.transmission};
}
/// evaluateInputs() of a hit with texture coordinates or a material that reads vertex colours.
SurfaceInputs texturedInputs(const detail::SceneData& scene, const detail::Material& material,
                             const SurfacePoint& at);
/// The inputs of `material` at `at`: its factors, times (or replaced by) its textures and the
/// mesh's vertex colours.
inline SurfaceInputs evaluateInputs(const detail::SceneData& scene,
                                    const detail::Material& material, const SurfacePoint& at) {
    // Without texture coordinates or vertex colours, the factors (inline: every hit asks).
    if (!at.hasUv && !material.textureTimesFactor) return factorInputs(material);
    return texturedInputs(scene, material, at);
}

/// The material's emitted radiance at `at`: its emission times its emission texture's colour
/// (glTF's emissiveTexture) where it has one and the mesh has texture coordinates.
Vec3 emissionAt(const detail::SceneData& scene, const detail::Material& material,
                const SurfacePoint& at);

/// The shading normal `ns` (unit, world space, on the viewer's side) bent by the material's
/// normal map: n = normalize(T x + B y + N z) with (x, y, z) = (2 rgb − 1) × (s, s, 1), T and
/// B the mesh's tangent frame at the hit in world space (glTF: B = w · N × T) made orthogonal to
/// N. A material without a normal map but with a bump map gets applyBumpMap(). Returns ns
/// unchanged without either, texture coordinates or tangents.
Vec3 applyNormalMap(const detail::SceneData& scene, const detail::Material& material,
                    const SurfacePoint& at, const Vec3& ns);

/// The shading normal `ns` (unit, world space, on the viewer's side) bent by the material's bump
/// map (pbrt-v4's BumpMap): the surface displaced along ns by the height d = luminance ×
/// bumpMultiplier (scene units) has tangents ∂p/∂u + ∂d/∂u ns and ∂p/∂v + ∂d/∂v ns, with
/// ∂p/∂u, ∂p/∂v the triangle's (world space at shutter open, in the bump texture's transformed
/// coordinates) made orthogonal to ns, and ∂d/∂u, ∂d/∂v central differences over half the
/// texture footprint (0.0005 where it is zero); their cross product, on ns's side, is the
/// result. Returns ns itself (bit for bit) where the differences vanish (a constant height) and
/// without a bump map or texture coordinates.
Vec3 applyBumpMap(const detail::SceneData& scene, const detail::Material& material,
                  const SurfacePoint& at, const Vec3& ns);

}  // namespace glint::render

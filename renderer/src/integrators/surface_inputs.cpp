#include "integrators/surface_inputs.h"

#include <algorithm>
#include <bit>
#include <cmath>

#include "glint/image/random.h"

namespace glint::render {

namespace {

/// The number in [0, 1) that picks the MIP level of a hit's texture filters: a hash of where
/// the hit lies on its triangle, which differs from sample to sample as the rays do, so that
/// the picked levels average to the trilinear filter over a pixel's samples (and a lookup
/// depends on the hit alone, not on the thread or the sampler).
float levelNumber(const SurfacePoint& at) {
    // One SplitMix64 finaliser over the barycentrics' bits and the triangle.
    const std::uint64_t bary = (std::uint64_t(std::bit_cast<std::uint32_t>(at.b1)) << 32) |
                               std::bit_cast<std::uint32_t>(at.b2);
    const std::uint64_t triangle = (std::uint64_t(at.id.instance) << 32) | at.id.prim;
    return float(mix64(bary ^ (triangle * 0x9e3779b97f4a7c15ULL)) >> 40) * 0x1p-24f;
}

/// Texture `texture` at the hit through `transform` (applied to the uv of its set and to that
/// set's footprint axes): its filter at one of two MIP levels, picked by levelNumber().
Vec4 lookup(const detail::SceneData& scene, int texture, const detail::UvTransform& transform,
            const SurfacePoint& at) {
    const bool second = transform.set != 0 && at.hasUv1;
    const detail::TexFootprint& footprint = second ? at.footprint1 : at.footprint;
    const detail::TexFootprint fp{transform.applyLinear(footprint.dx),
                                  transform.applyLinear(footprint.dy)};
    return scene.textures[std::size_t(texture)].lookupOneLevel(
        transform.apply(second ? at.uv1 : at.uv), fp, levelNumber(at));
}

Vec4 lookup(const detail::SceneData& scene, const detail::TextureSlot& slot,
            const SurfacePoint& at) {
    return lookup(scene, slot.texture, slot.transform, at);
}

}  // namespace

detail::TexFootprint uvFootprint(const detail::TriangleView& tri, const Vec2& uv0, const Vec2& uv1,
                                 const Vec2& uv2, const Vec3& dpdx, const Vec3& dpdy) {
    // Least squares: the (db1, db2) with db1 e1 + db2 e2 nearest to the step, from the normal
    // equations [e1·e1 e1·e2; e1·e2 e2·e2] (db1, db2) = (e1·dp, e2·dp).
    const Vec3 e1 = tri.p[1] - tri.p[0], e2 = tri.p[2] - tri.p[0];
    const float a00 = dot(e1, e1), a01 = dot(e1, e2), a11 = dot(e2, e2);
    const float det = a00 * a11 - a01 * a01;
    if (!(det > 0.0f) || !std::isfinite(det)) return {};
    const float inv = 1.0f / det;  // one division for the four
    const Vec2 du1{uv1.x - uv0.x, uv1.y - uv0.y}, du2{uv2.x - uv0.x, uv2.y - uv0.y};
    auto map = [&](const Vec3& dp) -> Vec2 {
        const float b0 = dot(e1, dp), b1 = dot(e2, dp);
        const float db1 = (a11 * b0 - a01 * b1) * inv, db2 = (a00 * b1 - a01 * b0) * inv;
        const Vec2 d{du1.x * db1 + du2.x * db2, du1.y * db1 + du2.y * db2};
        return std::isfinite(d.x) && std::isfinite(d.y) ? d : Vec2{};
    };
    return {map(dpdx), map(dpdy)};
}

SurfaceInputs texturedInputs(const detail::SceneData& scene, const detail::Material& material,
                             const SurfacePoint& at) {
    SurfaceInputs in = factorInputs(material);
    // glTF's COLOR_0 multiplies a glTF material's base colour (factor × texture).
    if (material.textureTimesFactor) {
        const detail::Mesh& mesh = scene.meshes[scene.instances[at.id.instance].mesh];
        if (!mesh.colors.empty()) {
            const Vec4 c = detail::vertexColor(mesh, at.id.prim, at.b1, at.b2);
            in.albedo = in.albedo * Vec3{c.x, c.y, c.z};
        }
    }
    if (!at.hasUv) return in;
    if (material.texture >= 0) {
        const Vec4 t = lookup(scene, material.texture, material.textureTransform, at);
        const Vec3 rgb{t.x, t.y, t.z};
        in.albedo = material.textureTimesFactor ? in.albedo * rgb : rgb;
    }
    // (Only metallic-roughness materials have these two maps.)
    if (material.roughnessMetallicMap.present()) {
        // glTF: roughness in G, metallic in B, each multiplying its factor.
        const Vec4 t = lookup(scene, material.roughnessMetallicMap, at);
        in.roughness = std::clamp(in.roughness * t.y, 0.0f, 1.0f);
        in.metallic = std::clamp(in.metallic * t.z, 0.0f, 1.0f);
    }
    if (material.transmissionMap.present()) {
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
    if (!material.normalMap.present())
        return material.bumpMap.present() ? applyBumpMap(scene, material, at, ns) : ns;
    if (!at.hasUv) return ns;
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

Vec3 applyBumpMap(const detail::SceneData& scene, const detail::Material& material,
                  const SurfacePoint& at, const Vec3& ns) {
    const detail::TextureSlot& slot = material.bumpMap;
    if (!slot.present() || !at.hasUv) return ns;
    const detail::Mesh& mesh = scene.meshes[scene.instances[at.id.instance].mesh];
    const bool second = slot.transform.set != 0 && at.hasUv1;
    const std::vector<Vec2>& uvs = second ? mesh.uvs1 : mesh.uvs;
    const std::uint32_t* idx = &mesh.indices[3 * std::size_t(at.id.prim)];

    // The triangle's dp/du and dp/dv in the texture's coordinates (Lengyel 2001: solve
    // e1 = du1 dp/du + dv1 dp/dv, e2 = du2 dp/du + dv2 dp/dv), in double: a bump's slope is
    // the ratio of two derivatives, either of which may be tiny or huge.
    const detail::TriangleView tri = scene.triangle(at.id.instance, at.id.prim);
    const Vec2 a = slot.transform.apply(uvs[idx[0]]), b = slot.transform.apply(uvs[idx[1]]),
               c = slot.transform.apply(uvs[idx[2]]);
    const double du1 = double(b.x) - a.x, dv1 = double(b.y) - a.y;
    const double du2 = double(c.x) - a.x, dv2 = double(c.y) - a.y;
    const double det = du1 * dv2 - du2 * dv1;
    if (!(std::abs(det) > 0.0) || !std::isfinite(det)) return ns;
    const Vec3 e1 = tri.p[1] - tri.p[0], e2 = tri.p[2] - tri.p[0];
    double dpdu[3], dpdv[3];
    for (int k = 0; k < 3; ++k) {
        dpdu[k] = (double(e1[k]) * dv2 - double(e2[k]) * dv1) / det;
        dpdv[k] = (double(e2[k]) * du1 - double(e1[k]) * du2) / det;
    }

    // The steps of the differences: half the footprint (pbrt-v4's BumpMap), 0.0005 where it is
    // zero, and no finer than 2^-16, below which float texture coordinates and the filter's
    // rounding make the differences noise.
    const detail::TexFootprint& footprint = second ? at.footprint1 : at.footprint;
    const detail::TexFootprint fp{slot.transform.applyLinear(footprint.dx),
                                  slot.transform.applyLinear(footprint.dy)};
    auto step = [](float x, float y) {
        const float s = 0.5f * (std::abs(x) + std::abs(y));
        return !(s > 0.0f) || !std::isfinite(s) ? 0.0005f : std::max(s, 0x1p-16f);
    };
    const float su = step(fp.dx.x, fp.dy.x), sv = step(fp.dx.y, fp.dy.y);

    // The heights around the hit, every lookup at the same MIP level (one level number), so
    // that their differences are the texture's slope and not a change of level.
    const Vec2 uv = slot.transform.apply(second ? at.uv1 : at.uv);
    const detail::Texture& texture = scene.textures[std::size_t(slot.texture)];
    const float level = levelNumber(at);
    auto height = [&](float u, float v) {
        const Vec4 t = texture.lookupOneLevel({u, v}, fp, level);
        return 0.2126f * t.x + 0.7152f * t.y + 0.0722f * t.z;  // Rec. 709 luminance
    };
    // A difference within a few float roundings of the heights (a constant texture filtered at
    // two places) is no slope.
    auto difference = [](float hi, float lo) {
        const float d = hi - lo;
        return std::abs(d) <= 0x1p-20f * std::max(std::abs(hi), std::abs(lo)) ? 0.0f : d;
    };
    const float hu = difference(height(uv.x + su, uv.y), height(uv.x - su, uv.y));
    const float hv = difference(height(uv.x, uv.y + sv), height(uv.x, uv.y - sv));
    if (hu == 0.0f && hv == 0.0f) return ns;
    const double gu = double(hu) * material.bumpMultiplier / (2.0 * su);
    const double gv = double(hv) * material.bumpMultiplier / (2.0 * sv);

    // The displaced surface's tangents: dp/du and dp/dv in the plane of ns, plus the height's
    // derivative along ns (pbrt-v4, BumpMap; the dn/du term of a curved surface is left out,
    // as the shading normal's own change over a triangle is not a height).
    const double n[3] = {ns.x, ns.y, ns.z};
    const double pu = dpdu[0] * n[0] + dpdu[1] * n[1] + dpdu[2] * n[2];
    const double pv = dpdv[0] * n[0] + dpdv[1] * n[1] + dpdv[2] * n[2];
    double tu[3], tv[3];
    for (int k = 0; k < 3; ++k) {
        tu[k] = dpdu[k] - n[k] * pu + n[k] * gu;
        tv[k] = dpdv[k] - n[k] * pv + n[k] * gv;
    }
    double bent[3] = {tu[1] * tv[2] - tu[2] * tv[1], tu[2] * tv[0] - tu[0] * tv[2],
                      tu[0] * tv[1] - tu[1] * tv[0]};
    // On ns's side: the displaced surface's normal does not depend on the uv's handedness.
    const double side = bent[0] * n[0] + bent[1] * n[1] + bent[2] * n[2] < 0.0 ? -1.0 : 1.0;
    const double len = std::sqrt(bent[0] * bent[0] + bent[1] * bent[1] + bent[2] * bent[2]);
    if (!(len > 0.0) || !std::isfinite(len)) return ns;
    for (double& x : bent) x *= side / len;
    return {float(bent[0]), float(bent[1]), float(bent[2])};
}

}  // namespace glint::render

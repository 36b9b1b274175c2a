#include "scene/tangent_frames.h"

#include <cmath>
#include <unordered_map>

namespace glint::render::detail {

namespace {

/// The angle at corner a of triangle (a, b, c).
float cornerAngle(const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 u = b - a, v = c - a;
    const float lu = length(u), lv = length(v);
    if (!(lu > 0.0f) || !(lv > 0.0f)) return 0.0f;
    return std::acos(std::clamp(dot(u, v) / (lu * lv), -1.0f, 1.0f));
}

}  // namespace

void generateTangents(Mesh& mesh, std::size_t firstTriangle, std::size_t lastTriangle, int uvSet) {
    const std::size_t originalVertices = mesh.vertexCount();
    mesh.tangents.resize(originalVertices, Vec4{});

    // Each triangle's texture-space directions and handedness (Lengyel 2001: solve
    // e1 = du1 T + dv1 B, e2 = du2 T + dv2 B).
    struct Direction {
        Vec3 t, b;
        float sign = 0.0f;  // 0: the texture coordinates are degenerate
    };
    std::vector<Direction> directions(lastTriangle - firstTriangle);
    // Read only in this loop, before vertices are split (which appends to both sets).
    const std::vector<Vec2>& uvs = uvSet != 0 && !mesh.uvs1.empty() ? mesh.uvs1 : mesh.uvs;
    for (std::size_t f = firstTriangle; f < lastTriangle; ++f) {
        const std::uint32_t* idx = &mesh.indices[3 * f];
        const Vec3 e1 = mesh.positions[idx[1]] - mesh.positions[idx[0]];
        const Vec3 e2 = mesh.positions[idx[2]] - mesh.positions[idx[0]];
        const Vec2 a = uvs[idx[0]], b = uvs[idx[1]], c = uvs[idx[2]];
        const float du1 = b.x - a.x, dv1 = b.y - a.y, du2 = c.x - a.x, dv2 = c.y - a.y;
        const float det = du1 * dv2 - du2 * dv1;
        if (!std::isfinite(det) || std::abs(det) < 1e-20f) continue;
        const float r = 1.0f / det;
        Direction& d = directions[f - firstTriangle];
        d.t = (e1 * dv2 - e2 * dv1) * r;
        d.b = (e2 * du1 - e1 * du2) * r;
        // Handedness against the face normal: does (T, B, N) turn the way (u, v, n) does?
        const Vec3 n = cross(e1, e2);
        d.sign = dot(cross(d.t, d.b), n) < 0.0f ? -1.0f : 1.0f;
        if (!isFinite(d.t) || !isFinite(d.b)) d.sign = 0.0f;
    }

    // A vertex used by triangles of both handednesses is split: the mirrored side's corners
    // get a copy of it.
    std::vector<std::int8_t> seen(originalVertices, 0);  // bit 0: positive, bit 1: negative
    for (std::size_t f = firstTriangle; f < lastTriangle; ++f) {
        const float sign = directions[f - firstTriangle].sign;
        if (sign == 0.0f) continue;
        for (int k = 0; k < 3; ++k)
            seen[mesh.indices[3 * f + std::size_t(k)]] |= sign > 0.0f ? 1 : 2;
    }
    std::unordered_map<std::uint32_t, std::uint32_t> mirrored;
    for (std::size_t f = firstTriangle; f < lastTriangle; ++f) {
        if (directions[f - firstTriangle].sign >= 0.0f) continue;
        for (int k = 0; k < 3; ++k) {
            std::uint32_t& v = mesh.indices[3 * f + std::size_t(k)];
            if (v >= originalVertices || seen[v] != 3) continue;
            auto [it, inserted] = mirrored.try_emplace(v, std::uint32_t(mesh.positions.size()));
            if (inserted) {
                mesh.positions.push_back(mesh.positions[v]);
                mesh.normals.push_back(mesh.normals[v]);
                mesh.uvs.push_back(mesh.uvs[v]);
                if (!mesh.uvs1.empty()) mesh.uvs1.push_back(mesh.uvs1[v]);
                if (!mesh.colors.empty()) mesh.colors.push_back(mesh.colors[v]);
                mesh.tangents.push_back(Vec4{});
            }
            v = it->second;
        }
    }

    // Sum the directions into the corners, weighted by the corner angle.
    const std::size_t vertices = mesh.vertexCount();
    std::vector<Vec3> sumT(vertices), sumB(vertices);
    std::vector<bool> touched(vertices, false);
    for (std::size_t f = firstTriangle; f < lastTriangle; ++f) {
        const std::uint32_t* idx = &mesh.indices[3 * f];
        for (int k = 0; k < 3; ++k) touched[idx[k]] = true;
        const Direction& d = directions[f - firstTriangle];
        if (d.sign == 0.0f) continue;
        for (int k = 0; k < 3; ++k) {
            const Vec3& p = mesh.positions[idx[k]];
            const float w =
                cornerAngle(p, mesh.positions[idx[(k + 1) % 3]], mesh.positions[idx[(k + 2) % 3]]);
            sumT[idx[k]] += d.t * w;
            sumB[idx[k]] += d.b * w;
        }
    }
    // Orthogonalise against the normal (Gram–Schmidt) and record the handedness.
    for (std::size_t v = 0; v < vertices; ++v) {
        if (!touched[v]) continue;
        Vec3 n = mesh.normals[v];
        const float ln = length(n);
        if (!(ln > 0.0f)) continue;  // no normal: nothing to map against
        n = n / ln;
        Vec3 t = sumT[v] - n * dot(n, sumT[v]);
        const float lt = length(t);
        if (!(lt > 1e-20f) || !std::isfinite(lt)) {
            const Frame frame = Frame::fromNormal(n);
            mesh.tangents[v] = {frame.s.x, frame.s.y, frame.s.z, 1.0f};
            continue;
        }
        t = t / lt;
        const float w = dot(cross(n, t), sumB[v]) < 0.0f ? -1.0f : 1.0f;
        mesh.tangents[v] = {t.x, t.y, t.z, w};
    }
}

}  // namespace glint::render::detail

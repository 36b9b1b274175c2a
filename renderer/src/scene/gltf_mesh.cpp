// glTF meshes → scene meshes (GltfImport::mesh): the triangle primitives (lists, strips, fans)
// of a mesh appended into one Glint mesh with their vertex attributes. Every array is reserved at
// its final size before the first primitive is read, and the accessors append straight into it:
// a mesh is allocated once, never grown by doubling nor copied, and its positions hold the
// vertex of padding Embree reads past the last (SceneData::finishMeshes).
#include <tiny_gltf.h>

#include <algorithm>
#include <limits>
#include <set>
#include <string>

#include "scene/gltf_import.h"
#include "scene/tangent_frames.h"

namespace glint::render::detail {

namespace {

/// The accessor of a primitive's attribute `name`, or -1.
int meshAttribute(const tinygltf::Primitive& prim, const char* name) {
    const auto it = prim.attributes.find(name);
    return it == prim.attributes.end() ? -1 : it->second;
}

/// A primitive's mode (triangles when it has none).
int meshMode(const tinygltf::Primitive& prim) {
    return prim.mode < 0 ? TINYGLTF_MODE_TRIANGLES : prim.mode;
}

bool rendersTriangles(int mode) {
    return mode == TINYGLTF_MODE_TRIANGLES || mode == TINYGLTF_MODE_TRIANGLE_STRIP ||
           mode == TINYGLTF_MODE_TRIANGLE_FAN;
}

/// Readies a mesh's optional per-vertex array `to` (empty until a primitive has it) for a
/// primitive whose `count` vertices follow the `base` of the earlier ones: when the primitive
/// has the attribute (`has`), an array the earlier primitives lacked is filled to `base` with
/// `fill` for the primitive's elements to be appended; when it lacks it, an existing array gets
/// `count` copies of `fill`.
template <typename T>
void readyMeshAttribute(std::vector<T>& to, bool has, std::size_t base, std::size_t count,
                        const T& fill = T{}) {
    if (has ? count > 0 : !to.empty()) to.resize(has ? base : base + count, fill);
}

/// Frees the capacity of an array that ended empty.
template <typename T>
void freeIfEmpty(std::vector<T>& v) {
    if (v.empty()) std::vector<T>().swap(v);
}

}  // namespace

int GltfImport::mesh(int index) {
    int& cached = m_meshes[std::size_t(index)];
    if (cached != -1) return cached;
    const tinygltf::Mesh& gm = m_model.meshes[std::size_t(index)];
    const std::string meshPlace = "meshes[" + std::to_string(index) + "]";
    Mesh mesh;
    mesh.name = m_file.filename().string() + ": " + (gm.name.empty() ? meshPlace : gm.name);
    if (!gm.weights.empty()) warn("morph targets are ignored (the base shape is rendered)");

    // Reserve every array at the size it reaches once all primitives are appended, from the
    // counts of accessors whose bytes lie in their buffers (the readers below check each one
    // and name what is wrong); a strip's or fan's triangles are reserved at their most.
    std::size_t vertices = 0, indices = 0;
    bool normals = false, uvs = false, uvs1 = false, colors = false, tangents = false;
    std::set<int> materials;
    for (const tinygltf::Primitive& prim : gm.primitives) {
        const int mode = meshMode(prim);
        if (!rendersTriangles(mode)) continue;
        const std::size_t n = m_accessors.readableCount(meshAttribute(prim, "POSITION"));
        if (n == 0) continue;
        vertices += n;
        const std::size_t i = prim.indices >= 0 ? m_accessors.readableCount(prim.indices) : n;
        indices += mode == TINYGLTF_MODE_TRIANGLES ? i : i >= 3 ? 3 * (i - 2) : 0;
        const bool hasNormals = meshAttribute(prim, "NORMAL") >= 0;
        normals = normals || hasNormals;
        uvs = uvs || meshAttribute(prim, "TEXCOORD_0") >= 0;
        uvs1 = uvs1 || meshAttribute(prim, "TEXCOORD_1") >= 0;
        colors = colors || meshAttribute(prim, "COLOR_0") >= 0;
        // Tangents when the asset has them, or when a normal map will have them generated.
        const int m = m_overrides.material;
        const bool normalMapped =
            m >= 0 ? m_scene.materials[std::size_t(m)].normalMap.present()
                   : prim.material >= 0 && std::size_t(prim.material) < m_model.materials.size() &&
                         m_model.materials[std::size_t(prim.material)].normalTexture.index >= 0;
        tangents =
            tangents || (hasNormals && (meshAttribute(prim, "TANGENT") >= 0 ||
                                        (normalMapped && meshAttribute(prim, "TEXCOORD_0") >= 0)));
        materials.insert(prim.material);
    }
    if (vertices < std::numeric_limits<std::uint32_t>::max()) {
        mesh.positions.reserve(vertices + 1);
        if (normals) mesh.normals.reserve(vertices);
        if (uvs) mesh.uvs.reserve(vertices);
        if (uvs1) mesh.uvs1.reserve(vertices);
        if (colors) mesh.colors.reserve(vertices);
        if (tangents) mesh.tangents.reserve(vertices);
        mesh.indices.reserve(indices);
        if (materials.size() > 1) mesh.materials.reserve(indices / 3);
    }

    for (std::size_t p = 0; p < gm.primitives.size(); ++p) {
        const tinygltf::Primitive& prim = gm.primitives[p];
        const std::string place = meshPlace + ".primitives[" + std::to_string(p) + "]";
        const int mode = meshMode(prim);
        if (mode > TINYGLTF_MODE_TRIANGLE_FAN)
            fail(place + ".mode", "is " + std::to_string(mode) + ", expected 0 to 6");
        if (!rendersTriangles(mode)) {
            ++m_skippedPrimitives;
            warnOnce("mode " + std::to_string(mode),
                     "primitives of mode " + std::to_string(mode) +
                         " (points or lines) are skipped; Glint renders modes 4, 5 and 6 "
                         "(triangles, strips, fans), first at " +
                         place + ".mode");
            continue;
        }
        auto attribute = [&](const char* name) { return meshAttribute(prim, name); };
        if (!prim.targets.empty()) warn("morph targets are ignored (the base shape is rendered)");
        const int position = attribute("POSITION");
        if (position < 0) fail(place + ".attributes", "has no POSITION");
        const std::size_t base = mesh.positions.size();
        const std::size_t n =
            m_accessors.appendVec3(position, place + ".attributes.POSITION", true, mesh.positions);
        if (n > std::numeric_limits<std::uint32_t>::max() - base - 1)
            fail(place, "has more vertices than Glint can index in one mesh (2^32)");
        auto sameCount = [&](std::size_t count, const char* name) {
            if (count != n)
                fail(place + ".attributes." + name, "has " + std::to_string(count) +
                                                        " elements, POSITION has " +
                                                        std::to_string(n));
        };

        // The optional per-vertex arrays (normals, uvs, colours, tangents) exist once a
        // primitive has them: they are then as long as positions, zero (colours: white) where
        // a primitive lacks them.
        const int normal = attribute("NORMAL");
        readyMeshAttribute(mesh.normals, normal >= 0, base, n);
        if (normal >= 0)
            sameCount(
                m_accessors.appendVec3(normal, place + ".attributes.NORMAL", true, mesh.normals),
                "NORMAL");
        const int uv = attribute("TEXCOORD_0");
        readyMeshAttribute(mesh.uvs, uv >= 0, base, n);
        if (uv >= 0)
            sameCount(m_accessors.appendVec2(uv, place + ".attributes.TEXCOORD_0", mesh.uvs),
                      "TEXCOORD_0");
        // A second uv set, which texture slots pick by texCoord 1; sets are numbered from 0
        // without gaps (spec 3.7.2.1).
        const int uv1 = attribute("TEXCOORD_1");
        if (uv1 >= 0 && (uv < 0 || n == 0))
            fail(place + ".attributes", "has TEXCOORD_1 but no TEXCOORD_0");
        readyMeshAttribute(mesh.uvs1, uv1 >= 0, base, n);
        if (uv1 >= 0)
            sameCount(m_accessors.appendVec2(uv1, place + ".attributes.TEXCOORD_1", mesh.uvs1),
                      "TEXCOORD_1");
        // Vertex colours, linear RGB(A), multiplying the base colour (spec 3.7.2.1).
        const int color = attribute("COLOR_0");
        readyMeshAttribute(mesh.colors, color >= 0, base, n, Vec4{1.0f, 1.0f, 1.0f, 1.0f});
        if (color >= 0)
            sameCount(m_accessors.appendColor(color, place + ".attributes.COLOR_0", mesh.colors),
                      "COLOR_0");
        const int tangent = normal >= 0 && n > 0 ? attribute("TANGENT") : -1;
        readyMeshAttribute(mesh.tangents, tangent >= 0, base, n);
        if (tangent >= 0)
            sameCount(m_accessors.appendVec4(tangent, place + ".attributes.TANGENT", mesh.tangents),
                      "TANGENT");
        const bool hasNormals = normal >= 0 && n > 0, hasUvs = uv >= 0 && n > 0,
                   hasTangents = tangent >= 0;
        // glTF's texture origin is the top-left, Glint's the bottom-left: v' = 1 − v.
        if (hasUvs)
            for (std::size_t v = base; v < base + n; ++v) mesh.uvs[v].y = 1.0f - mesh.uvs[v].y;
        if (uv1 >= 0 && n > 0)
            for (std::size_t v = base; v < base + n; ++v) mesh.uvs1[v].y = 1.0f - mesh.uvs1[v].y;
        if (hasTangents)
            for (std::size_t v = base; v < base + n; ++v)
                mesh.tangents[v].w = mesh.tangents[v].w < 0.0f ? -1.0f : 1.0f;

        // The triangles, their indices offset by the earlier primitives' vertices.
        const std::size_t firstTriangle = mesh.triangleCount();
        const std::string indicesPlace = prim.indices >= 0 ? place + ".indices" : place;
        const std::string indicesWhat = prim.indices >= 0 ? " indices" : " vertices and no indices";
        if (mode == TINYGLTF_MODE_TRIANGLES) {
            const std::size_t before = mesh.indices.size();
            if (prim.indices >= 0) {
                m_accessors.appendIndices(prim.indices, indicesPlace, n, std::uint32_t(base),
                                          mesh.indices);
            } else {
                mesh.indices.resize(before + n);
                for (std::size_t i = 0; i < n; ++i)
                    mesh.indices[before + i] = std::uint32_t(base + i);
            }
            const std::size_t count = mesh.indices.size() - before;
            if (count % 3 != 0)
                fail(indicesPlace, "has " + std::to_string(count) + indicesWhat +
                                       ": not a multiple of 3 (triangles)");
        } else {
            std::vector<std::uint32_t> list;
            if (prim.indices >= 0) {
                m_accessors.appendIndices(prim.indices, indicesPlace, n, 0, list);
            } else {
                list.resize(n);
                for (std::size_t i = 0; i < n; ++i) list[i] = std::uint32_t(i);
            }
            if (list.size() < 3)
                fail(indicesPlace, "has " + std::to_string(list.size()) + indicesWhat +
                                       ": a triangle " +
                                       (mode == TINYGLTF_MODE_TRIANGLE_STRIP ? "strip" : "fan") +
                                       " needs at least 3");
            for (std::uint32_t i : unrollTriangles(list, mode == TINYGLTF_MODE_TRIANGLE_STRIP))
                mesh.indices.push_back(std::uint32_t(base) + i);
        }
        const int materialIndex = material(prim.material);
        mesh.assignMaterial(firstTriangle, std::uint32_t(std::max(materialIndex, 0)));
        // Tangents for a normal map, generated (MikkTSpace convention) when the asset has none.
        const int used = m_overrides.material >= 0 ? m_overrides.material : materialIndex;
        if (m_scene.materials[std::size_t(used)].normalMap.present() && !hasTangents) {
            if (!hasNormals || !hasUvs)
                warn(place + " has a normal-mapped material but no " +
                     (hasNormals ? "TEXCOORD_0" : "NORMAL") + ": its normal map is not applied");
            else
                generateTangents(mesh, firstTriangle, mesh.triangleCount(),
                                 m_scene.materials[std::size_t(used)].normalMap.transform.set);
        }
    }
    if (mesh.triangleCount() == 0) return cached = -2;
    // Reserved capacity no primitive used (a mesh of one material keeps one entry).
    freeIfEmpty(mesh.normals), freeIfEmpty(mesh.uvs), freeIfEmpty(mesh.uvs1);
    freeIfEmpty(mesh.colors), freeIfEmpty(mesh.tangents);
    if (mesh.materials.size() == 1) mesh.materials.shrink_to_fit();
    m_scene.meshes.push_back(std::move(mesh));
    return cached = int(m_scene.meshes.size() - 1);
}

}  // namespace glint::render::detail

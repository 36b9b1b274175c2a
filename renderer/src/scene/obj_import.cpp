// OBJ/MTL import through tinyobjloader: triangles, per-vertex normals and uvs, MTL materials
// (JSON materials of the same name take precedence), map_Kd textures.
#include <algorithm>
#include <cmath>
#include <sstream>

#include <tiny_obj_loader.h>

#include "glint/image/error.h"
#include "scene/loader.h"
#include "scene/obj_scan.h"

namespace glint::render::detail {

namespace fs = std::filesystem;

namespace {

Material materialFromMtl(const tinyobj::material_t& mtl) {
    Material m;
    m.name = mtl.name;
    m.albedo = {mtl.diffuse[0], mtl.diffuse[1], mtl.diffuse[2]};
    m.emission = {mtl.emission[0], mtl.emission[1], mtl.emission[2]};
    const Vec3 ks{mtl.specular[0], mtl.specular[1], mtl.specular[2]};
    if (mtl.ior > 1.0f && (mtl.illum == 4 || mtl.illum == 6 || mtl.illum == 7)) {
        m.type = MaterialType::Dielectric;
        m.ior = mtl.ior;
        m.albedo = {1.0f, 1.0f, 1.0f};
    } else if (isBlack(m.albedo) && !isBlack(ks) && mtl.diffuse_texname.empty()) {
        m.type = MaterialType::Conductor;
        m.specular = ks;
        m.albedo = {1.0f, 1.0f, 1.0f};
        m.roughness = std::sqrt(2.0f / (std::max(mtl.shininess, 0.0f) + 2.0f));
    }
    for (int c = 0; c < 3; ++c) {
        m.albedo[c] = std::clamp(m.albedo[c], 0.0f, 1.0f);
        m.specular[c] = std::clamp(m.specular[c], 0.0f, 1.0f);
        m.emission[c] = std::max(m.emission[c], 0.0f);
    }
    return m;
}

}  // namespace

void Loader::importObj(const fs::path& objPath, const Affine& xf, bool moving, int overrideMaterial,
                       const std::string& where, std::vector<Vec3>& objectPositions,
                       std::vector<Vec3>& objectNormals) {
    std::error_code ec;  // odd paths (too long...) are reported, not thrown as filesystem errors
    if (!fs::exists(objPath, ec))
        throw Error(ErrorKind::Io, "OBJ file '" + objPath.string() + "' not found",
                    m_reader.file().string(), where + "/obj");
    if (!fs::is_regular_file(objPath, ec))
        throw Error(ErrorKind::Io, "'" + objPath.string() + "' is not a file",
                    m_reader.file().string(), where + "/obj");
    // Indices and numbers checked with their line first: tinyobjloader trusts them.
    const ObjLines lines = scanObj(objPath);

    tinyobj::ObjReaderConfig config;
    config.triangulate = true;
    config.vertex_color = false;
    config.mtl_search_path = objPath.parent_path().string();
    tinyobj::ObjReader obj;
    if (!obj.ParseFromFile(objPath.string(), config) || !obj.Valid())
        throw Error(ErrorKind::Format, "cannot parse OBJ: " + obj.Error(), objPath.string(),
                    where + "/obj");
    if (obj.Warning().find("not found") != std::string::npos) {
        // One line: tinyobjloader's warning repeats itself for every material.
        std::string first = obj.Warning().substr(0, obj.Warning().find('\n'));
        throw Error(ErrorKind::Io, "OBJ references a missing file (" + first + ")",
                    objPath.string(), "mtllib");
    }

    // Map the OBJ's materials to scene materials (JSON overrides MTL by name).
    std::vector<int> objMaterial;
    for (const tinyobj::material_t& mtl : obj.GetMaterials()) {
        int index = materialIndex(mtl.name);
        if (index < 0) {
            Material m = materialFromMtl(mtl);
            if (!mtl.diffuse_texname.empty())
                m.texture = loadTexture(objPath.parent_path() / mtl.diffuse_texname,
                                        where + "/obj (map_Kd of " + mtl.name + ")");
            index = addMaterial(std::move(m));
        }
        objMaterial.push_back(index);
    }
    int defaultMaterial = -1;

    const tinyobj::attrib_t& attrib = obj.GetAttrib();
    const std::size_t vertexCount = attrib.vertices.size() / 3;
    const std::size_t normalCount = attrib.normals.size() / 3;
    const std::size_t texcoordCount = attrib.texcoords.size() / 2;
    if (vertexCount != lines.vertices.size() || normalCount != lines.normals.size() ||
        texcoordCount != lines.texcoords.size())
        throw Error(ErrorKind::Format, "the OBJ reader and the scan disagree on the statements",
                    objPath.string());
    // Every vertex after the shape's transform: finite and within kMaxCoordinate, so that areas,
    // distances and the BVH stay finite.
    std::vector<Vec3> world(vertexCount);
    for (std::size_t i = 0; i < vertexCount; ++i) {
        const float* p = &attrib.vertices[3 * i];
        world[i] = xf.point({p[0], p[1], p[2]});
        if (!isFinite(world[i]) || maxAbsComponent(world[i]) > kMaxCoordinate) {
            std::ostringstream msg;
            msg << "vertex (" << p[0] << ", " << p[1] << ", " << p[2] << ") lies beyond "
                << kMaxCoordinate << " (the largest coordinate) after the transform of " << where;
            throw Error(ErrorKind::Format, msg.str(), objPath.string(),
                        "line " + std::to_string(lines.vertices[i]));
        }
    }
    const std::size_t firstTriangle = m_scene.triangleCount();
    bool anyNormals = false, anyUvs = false;
    for (const tinyobj::shape_t& shape : obj.GetShapes()) {
        const auto& mesh = shape.mesh;
        std::size_t offset = 0;
        for (std::size_t f = 0; f < mesh.num_face_vertices.size(); ++f) {
            const int fv = mesh.num_face_vertices[f];
            if (fv != 3) {
                offset += std::size_t(fv);
                continue;
            }
            int mat = overrideMaterial;
            if (mat < 0) {
                const int id = f < mesh.material_ids.size() ? mesh.material_ids[f] : -1;
                if (id >= 0 && id < int(objMaterial.size())) {
                    mat = objMaterial[id];
                } else {
                    if (defaultMaterial < 0) {
                        defaultMaterial = materialIndex("default");
                        if (defaultMaterial < 0) {
                            Material m;
                            m.name = "default";
                            defaultMaterial = addMaterial(m);
                        }
                    }
                    mat = defaultMaterial;
                }
            }
            for (int v = 0; v < 3; ++v) {
                const tinyobj::index_t idx = mesh.indices[offset + std::size_t(v)];
                // scanObj checked every index; this guards the reader's own resolution.
                if (idx.vertex_index < 0 || std::size_t(idx.vertex_index) >= vertexCount ||
                    idx.normal_index >= int(normalCount) ||
                    idx.texcoord_index >= int(texcoordCount))
                    throw Error(ErrorKind::Format, "a face index is out of range",
                                objPath.string());
                const float* p = &attrib.vertices[3 * std::size_t(idx.vertex_index)];
                m_scene.positions.push_back(world[std::size_t(idx.vertex_index)]);
                Vec3 n{};
                if (idx.normal_index >= 0) {
                    const float* q = &attrib.normals[3 * std::size_t(idx.normal_index)];
                    n = xf.normal({q[0], q[1], q[2]});
                    if (length(n) > 0.0f) n = normalize(n), anyNormals = true;
                    if (moving) objectNormals.push_back({q[0], q[1], q[2]});
                } else if (moving) {
                    objectNormals.push_back({});
                }
                if (moving) objectPositions.push_back({p[0], p[1], p[2]});
                m_scene.normals.push_back(n);
                Vec2 uv{};
                if (idx.texcoord_index >= 0) {
                    const float* t = &attrib.texcoords[2 * std::size_t(idx.texcoord_index)];
                    uv = {t[0], t[1]};
                    anyUvs = true;
                }
                m_scene.uvs.push_back(uv);
            }
            m_scene.triangleMaterial.push_back(std::uint32_t(mat));
            offset += 3;
        }
    }
    m_hasNormals = m_hasNormals || anyNormals;
    m_hasUvs = m_hasUvs || anyUvs;

    // A shape whose emissive faces have no area cannot emit: reject it clearly.
    double emissiveArea = 0.0;
    bool anyEmissive = false;
    for (std::size_t t = firstTriangle; t < m_scene.triangleCount(); ++t) {
        if (!m_scene.materials[m_scene.triangleMaterial[t]].emissive()) continue;
        anyEmissive = true;
        const Vec3& a = m_scene.positions[3 * t];
        emissiveArea += triangleArea(a, m_scene.positions[3 * t + 1], m_scene.positions[3 * t + 2]);
    }
    if (anyEmissive && !(emissiveArea > 0.0))
        throw Error(ErrorKind::Format, "emissive faces have zero total area (zero-area light)",
                    objPath.string(), where);
}

}  // namespace glint::render::detail

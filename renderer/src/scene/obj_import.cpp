// OBJ/MTL import through tinyobjloader: triangles, per-vertex normals and uvs, MTL materials
// (JSON materials of the same name take precedence): colours, d/Tr, the PBR extension's Pr/Pm,
// map_Kd (with -s, -o, -clamp), norm, bump (heights, with -bm) and map_d where it is map_Kd's
// alpha (docs/obj-assets.md).
#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string_view>
#include <unordered_map>
#if defined(__GLIBC__)
#include <malloc.h>  // malloc_trim
#endif

#include <tiny_obj_loader.h>

#include "glint/image/error.h"
#include "scene/asset_format.h"
#include "scene/input_file.h"
#include "scene/load_memory.h"
#include "scene/obj_scan.h"
#include "scene/polygon_triangulation.h"
#include "scene/scene_data.h"
#include "scene/tangent_frames.h"

namespace glint::render::detail {

namespace fs = std::filesystem;

namespace {

/// An OBJ face corner: its position, normal and texture coordinate indices (-1: none), and the
/// smoothing group of a face without normals (0: none), whose normals are made per group.
struct Corner {
    int v, n, t;
    unsigned group;
    bool operator==(const Corner&) const = default;
};
/// A corner at a known position: its normal, texture coordinate and smoothing group.
struct CornerAt {
    int n, t;
    unsigned group;
    bool operator==(const CornerAt&) const = default;
};
constexpr std::uint32_t kNoVertex = ~0u;
struct CornerHash {
    std::size_t operator()(const Corner& c) const {
        std::uint64_t h = std::uint64_t(std::uint32_t(c.v)) * 0x9e3779b97f4a7c15ULL;
        h ^= (std::uint64_t(std::uint32_t(c.n)) + 0x632be59bd9b4e019ULL + (h << 6) + (h >> 2));
        h ^= (std::uint64_t(std::uint32_t(c.t)) + 0x8cb92ba72f3d8dd7ULL + (h << 6) + (h >> 2));
        h ^= (std::uint64_t(c.group) + 0x94d049bb133111ebULL + (h << 6) + (h >> 2));
        return std::size_t(h);
    }
};

// Vertex normals for the faces of smoothing groups that give none (an OBJ's "s 1" without "vn",
// as ZBrush and older exporters write): the face normals around each (position, group) summed,
// weighted by the corner's angle (as Blender weights them), then normalised. `group[i]` is the
// key of mesh vertex i ((position + 1) << 32 | group), 0 for a vertex with its own normal.
void smoothGroupNormals(Mesh& mesh, const std::vector<std::uint64_t>& group) {
    std::unordered_map<std::uint64_t, Vec3> sum;
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
        const std::uint32_t* idx = &mesh.indices[3 * t];
        const Vec3 p[3] = {mesh.positions[idx[0]], mesh.positions[idx[1]], mesh.positions[idx[2]]};
        const Vec3 n = cross(p[1] - p[0], p[2] - p[0]);
        if (!(length(n) > 0.0f)) continue;
        for (int k = 0; k < 3; ++k) {
            if (group[idx[k]] == 0) continue;
            const Vec3 a = p[(k + 1) % 3] - p[k], b = p[(k + 2) % 3] - p[k];
            const float la = length(a), lb = length(b);
            if (!(la > 0.0f && lb > 0.0f)) continue;
            const float angle = std::acos(std::clamp(dot(a, b) / (la * lb), -1.0f, 1.0f));
            sum[group[idx[k]]] += normalize(n) * angle;
        }
    }
    for (std::size_t i = 0; i < group.size(); ++i)
        if (group[i] != 0)
            if (const Vec3 n = sum[group[i]]; length(n) > 0.0f) mesh.normals[i] = normalize(n);
}

Material materialFromMtl(const tinyobj::material_t& mtl, bool pbr) {
    Material m;
    m.name = mtl.name;
    m.albedo = {mtl.diffuse[0], mtl.diffuse[1], mtl.diffuse[2]};
    m.emission = {mtl.emission[0], mtl.emission[1], mtl.emission[2]};
    const Vec3 ks{mtl.specular[0], mtl.specular[1], mtl.specular[2]};
    if (mtl.ior > 1.0f && (mtl.illum == 4 || mtl.illum == 6 || mtl.illum == 7)) {
        m.type = MaterialType::Dielectric;
        m.ior = mtl.ior;
        m.albedo = {1.0f, 1.0f, 1.0f};
    } else if (pbr) {
        // The PBR extension (Pr, Pm) as Blender's importer reads it: a metallic-roughness
        // surface with Kd as its base colour.
        m.type = MaterialType::MetallicRoughness;
        m.metallic = std::clamp(mtl.metallic, 0.0f, 1.0f);
        m.roughness = std::clamp(mtl.roughness, 0.0f, 1.0f);
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
    // d (or 1 - Tr; d wins where both are given, as in tinyobjloader): let light through.
    if (mtl.dissolve < 1.0f) {
        m.alphaMode = AlphaMode::Blend;
        m.opacity = std::clamp(mtl.dissolve, 0.0f, 1.0f);
    }
    return m;
}

// The mean colour (read as data) of a texture's texels that are not black, and their share of
// the texels: the texture in memory, or a level of at most 512 texels a side from the store.
std::pair<Vec3, double> meanOfNonBlack(const Texture& texture) {
    std::vector<float> rgba;
    const float* texels = texture.image.data().data();
    std::size_t count = texture.image.pixelCount(), stride = std::size_t(texture.image.channels());
    if (texture.store) {
        const auto sizes = texture.store->levelSizes(texture.file);
        std::size_t level = 0;
        while (level + 1 < sizes.size() && std::max(sizes[level].first, sizes[level].second) > 512)
            ++level;
        if (!texture.store->readLevel(texture.file, int(level), rgba)) return {{}, 0.0};
        texels = rgba.data(), count = rgba.size() / 4, stride = 4;
    }
    double sum[3] = {0.0, 0.0, 0.0};
    std::size_t kept = 0;
    for (std::size_t i = 0; i < count; ++i) {
        const float* t = texels + i * stride;
        if (t[0] + t[1] + t[2] < 0.05f) continue;  // padding around an atlas' islands
        for (int c = 0; c < 3; ++c) sum[c] += t[c];
        ++kept;
    }
    if (kept == 0) return {{}, 0.0};
    return {
        {float(sum[0] / double(kept)), float(sum[1] / double(kept)), float(sum[2] / double(kept))},
        double(kept) / double(count)};
}

// True when a texture holds tangent-space normals: over its texels that are not black (Crytek
// Sponza's normal maps pad their islands with black), red and green near 0.5 on average
// (normals leaning every way) and blue near 1 and well above both (normals mostly along +z),
// with such texels a quarter of the texture at least. A height map's grey, or a photograph,
// is not.
bool holdsTangentNormals(const Texture& texture, Vec3& mean) {
    const auto [m, share] = meanOfNonBlack(texture);
    mean = m;
    return share >= 0.25 && std::abs(m.x - 0.5f) <= 0.15f && std::abs(m.y - 0.5f) <= 0.15f &&
           m.z >= 0.75f && m.z - std::max(m.x, m.y) >= 0.25f;
}

// An MTL texture's -s and -o (u, v) as a transform of the texture coordinates.
UvTransform uvTransformOf(const MtlTexture& tex) {
    UvTransform t;
    t.m[0][0] = tex.scale[0], t.m[1][1] = tex.scale[1];
    t.m[0][2] = tex.offset[0], t.m[1][2] = tex.offset[1];
    t.identity = tex.scale[0] == 1.0f && tex.scale[1] == 1.0f && tex.offset[0] == 0.0f &&
                 tex.offset[1] == 0.0f;
    return t;
}

// tinyobjloader's material reader given the MTL files the scan found: the first `mtllib` reads
// them all (tinyobjloader itself reads only the first file of a line that exists), without a
// byte order mark.
class ScannedMtlReader final : public tinyobj::MaterialReader {
  public:
    explicit ScannedMtlReader(const std::vector<fs::path>& files) : m_files(files) {}
    bool operator()(const std::string&, std::vector<tinyobj::material_t>* materials,
                    std::map<std::string, int>* names, std::string* warn,
                    std::string* err) override {
        if (!m_read)
            for (const fs::path& file : m_files) {
                std::istringstream in(readObjText(file, "MTL"));
                tinyobj::LoadMtl(names, materials, &in, warn, err);
            }
        m_read = true;
        return true;
    }

  private:
    const std::vector<fs::path>& m_files;
    bool m_read = false;
};

// The OBJ file as tinyobjloader reads it: a block at a time, after a UTF-8 byte order mark
// (which it would read as part of the first statement), with a group statement after the last
// whole line of each block. The reader keeps each face of a group as an array of its own until
// the group ends, which for a large file of one group is most of its memory; a group ends the
// shape but changes nothing the faces hold (their material and smoothing group carry over, and
// Glint reads no group names).
class GroupedObjBuffer final : public std::streambuf {
  public:
    explicit GroupedObjBuffer(const fs::path& path) : m_in(path, std::ios::binary) {
        // A block of at most the file's size: a small file's block is small.
        std::error_code ec;
        m_blockSize = std::clamp<std::uintmax_t>(fs::file_size(path, ec), 1, m_blockSize);
        char bom[3] = {};
        if (!m_in.read(bom, 3) || std::string_view(bom, 3) != "\xEF\xBB\xBF") {
            m_in.clear();
            m_in.seekg(0);
        }
    }
    bool good() const { return bool(m_in); }

  protected:
    int_type underflow() override {
        if (gptr() < egptr()) return traits_type::to_int_type(*gptr());
        static constexpr std::string_view kGroup = "g glint-block\n";
        m_block.assign(m_rest.begin(), m_rest.end());
        m_rest.clear();
        const std::size_t had = m_block.size();
        m_block.resize(had + m_blockSize);
        m_in.read(m_block.data() + had, std::streamsize(m_blockSize));
        m_block.resize(had + std::size_t(std::max<std::streamsize>(m_in.gcount(), 0)));
        if (m_block.empty()) return traits_type::eof();
        const auto newline = std::find(m_block.rbegin(), m_block.rend(), '\n');
        if (m_in && newline != m_block.rend()) {  // more to come: a group after the last line
            const auto end = m_block.begin() + (m_block.rend() - newline);
            m_rest.assign(end, m_block.end());
            m_block.erase(end, m_block.end());
            m_block.insert(m_block.end(), kGroup.begin(), kGroup.end());
        }
        setg(m_block.data(), m_block.data(), m_block.data() + m_block.size());
        return traits_type::to_int_type(m_block[0]);
    }

  private:
    std::ifstream m_in;
    std::size_t m_blockSize = std::size_t(1) << 22;
    std::vector<char> m_block, m_rest;
};

/// Adds the OBJ file as one mesh in its object space and returns its index, adding its MTL
/// materials unless JSON overrides them by name. Every vertex must stay within the coordinate
/// range in each of `poses` (the shape's transform, or every time step of its motion). With
/// `overrideMaterial` >= 0 the caller's instance replaces every material (the mesh's own are
/// then 0).
std::uint32_t importObj(ImportContext& loader, const fs::path& objPath,
                        const std::vector<Affine>& poses, int overrideMaterial,
                        const std::string& where) {
    SceneData& scene = loader.scene();
    std::error_code ec;  // odd paths (too long...) are reported, not thrown as filesystem errors
    // Indices and numbers checked with their line first: tinyobjloader trusts them.
    ObjLines lines = scanObj(objPath);
    scene.addInput(objPath);
    for (const fs::path& mtl : lines.mtlFiles) scene.addInput(mtl);

    // Faces come whole: tinyobjloader's triangulation splits a concave face wrongly, and
    // differently where it sits; polygon_triangulation.cpp clips ears in the face's plane.
    tinyobj::attrib_t attrib;
    std::vector<tinyobj::shape_t> shapes;
    std::vector<tinyobj::material_t> materials;
    {
        // Read from the file as it goes (the scan has released its text), in blocks.
        GroupedObjBuffer buffer(objPath);
        if (!buffer.good())
            throw Error(ErrorKind::Io, "cannot read the OBJ file", objPath.string());
        std::istream text(&buffer);
        ScannedMtlReader mtlReader(lines.mtlFiles);
        std::string warn, err;
        if (!tinyobj::LoadObj(&attrib, &shapes, &materials, &warn, &err, &text, &mtlReader,
                              /*triangulate=*/false, /*default_vcols_fallback=*/false))
            throw Error(ErrorKind::Format, "cannot parse OBJ: " + err, objPath.string(),
                        where + "/obj");
    }
    auto warn = [&](const std::string& text) {
        const std::string line = objPath.filename().string() + ": " + text;
        if (std::find(scene.warnings.begin(), scene.warnings.end(), line) == scene.warnings.end())
            scene.warnings.push_back(line);
    };
    for (const std::string& w : lines.warnings) warn(w);
    // A texture an MTL statement names: found as findNamedFile finds it, or refused with the
    // MTL's file and line.
    auto mtlTexture = [&](const MtlMaterialInfo& info, const MtlTexture& tex, const char* key,
                          const std::string& material, TextureUse use) {
        const fs::path file = findNamedFile(info.file.parent_path(), tex.name);
        const fs::path written = info.file.parent_path() / tex.name;
        if (const InputKind kind = inputKind(written); file.empty() && kind != InputKind::Missing)
            throw Error(ErrorKind::Io,
                        std::string(key) + " '" + tex.name + "' of material '" + material + "' " +
                            notARegularFile(kind, "an image file"),
                        info.file.string(), "line " + std::to_string(tex.line));
        if (file.empty())
            throw Error(ErrorKind::Io,
                        std::string(key) + " '" + tex.name + "' of material '" + material +
                            "' not found (looked for " +
                            (info.file.parent_path() / tex.name).string() + ")",
                        info.file.string(), "line " + std::to_string(tex.line));
        Texture source;
        source.path = fs::absolute(file, ec);  // so that loadTexture does not prefix the scene's
        source.use = use;                      // folder again
        if (tex.clamp) source.wrapS = source.wrapT = TextureWrap::Clamp;
        return TextureSlot{
            loader.loadTexture(source, where + "/obj (" + key + " of " + material + ")"),
            uvTransformOf(tex)};
    };

    // Map the OBJ's materials to scene materials (JSON overrides MTL by name).
    std::vector<int> objMaterial;
    bool normalMapped = false, bumpMapped = false;
    // MTL files warned of a bump map beside a normal map, and of one that is a normal map.
    std::vector<fs::path> bumpBesideNorm, bumpAsNormals;
    for (tinyobj::material_t mtl : materials) {
        int index = loader.materialIndex(mtl.name);
        if (index < 0) {
            // Where the scan saw tinyobjloader part from the MTL specification: one value is
            // a grey (it sets red only), and paths are relative to the MTL file's folder.
            const auto found = lines.materials.find(mtl.name);
            const MtlMaterialInfo* info = found == lines.materials.end() ? nullptr : &found->second;
            if (info) {
                if (info->greyKd) mtl.diffuse[1] = mtl.diffuse[2] = mtl.diffuse[0];
                if (info->greyKs) mtl.specular[1] = mtl.specular[2] = mtl.specular[0];
                if (info->greyKe) mtl.emission[1] = mtl.emission[2] = mtl.emission[0];
            }
            Material m = materialFromMtl(mtl, info && info->pbr);
            if (info && !info->mapKd.name.empty()) {
                const TextureSlot slot =
                    mtlTexture(*info, info->mapKd, "map_Kd", mtl.name, TextureUse::Color);
                m.texture = slot.texture;
                m.textureTransform = slot.transform;
            }
            if (info && !info->norm.name.empty()) {
                m.normalMap = mtlTexture(*info, info->norm, "norm", mtl.name, TextureUse::Data);
                normalMapped = true;
            }
            // Heights are data (read linearly, as normal maps are), whatever the file's encoding.
            if (info && !info->bump.name.empty() && m.normalMap.present()) {
                if (std::find(bumpBesideNorm.begin(), bumpBesideNorm.end(), info->file) ==
                    bumpBesideNorm.end()) {
                    bumpBesideNorm.push_back(info->file);
                    warn(info->file.filename().string() + " line " +
                         std::to_string(info->bump.line) + ": the bump map of material '" +
                         mtl.name + "' is ignored: it has a normal map ('norm'), which is used");
                }
            } else if (info && !info->bump.name.empty()) {
                const TextureSlot slot =
                    mtlTexture(*info, info->bump, "bump", mtl.name, TextureUse::Data);
                Vec3 mean;
                if (holdsTangentNormals(scene.textures[std::size_t(slot.texture)], mean)) {
                    // Blender's exporter writes a normal map as map_Bump (and its importer reads
                    // map_Bump as one): read as a normal map, -bm its strength.
                    m.normalMap = slot;
                    m.normalScale = info->bump.bumpMultiplier;
                    normalMapped = true;
                    if (std::find(bumpAsNormals.begin(), bumpAsNormals.end(), info->file) ==
                        bumpAsNormals.end()) {
                        bumpAsNormals.push_back(info->file);
                        std::ostringstream msg;
                        msg.precision(3);
                        msg << info->file.filename().string() << " line " << info->bump.line
                            << ": the bump map '" << info->bump.name << "' of material '"
                            << mtl.name << "' holds tangent-space normals (mean colour " << mean.x
                            << ", " << mean.y << ", " << mean.z
                            << " where not black): read as a normal map, as Blender writes it";
                        warn(msg.str());
                    }
                } else {
                    m.bumpMap = slot;
                    m.bumpMultiplier = info->bump.bumpMultiplier;
                    bumpMapped = true;
                }
            }
            if (info && !info->mapD.name.empty()) {
                // The base texture's alpha is the opacity Glint reads; another file is not.
                const fs::path d = findNamedFile(info->file.parent_path(), info->mapD.name);
                if (m.texture >= 0 && !d.empty() &&
                    fs::equivalent(d, scene.textures[std::size_t(m.texture)].path, ec))
                    m.alphaMode = AlphaMode::Blend;
                else
                    warn(info->file.filename().string() + " line " +
                         std::to_string(info->mapD.line) + ": 'map_d' of material '" + mtl.name +
                         "' is ignored (only map_Kd's own alpha is read as opacity)");
            }
            if (m.alphaMode == AlphaMode::Blend && m.opacity == 0.0f)
                warn("material '" + mtl.name +
                     "' is fully transparent (d 0, or Tr 1: some exporters mean opaque by it)");
            index = loader.addMaterial(std::move(m));
        }
        objMaterial.push_back(index);
    }
    int defaultMaterial = -1;

    const std::size_t vertexCount = attrib.vertices.size() / 3;
    const std::size_t normalCount = attrib.normals.size() / 3;
    const std::size_t texcoordCount = attrib.texcoords.size() / 2;
    if (vertexCount != lines.vertices.size() || normalCount != lines.normalCount ||
        texcoordCount != lines.texcoordCount)
        throw Error(ErrorKind::Format, "the OBJ reader and the scan disagree on the statements",
                    objPath.string());
    // Every vertex in every pose of the shape: finite and within kMaxCoordinate, so that areas,
    // distances and the BVH stay finite.
    for (std::size_t i = 0; i < vertexCount; ++i) {
        const float* p = &attrib.vertices[3 * i];
        for (const Affine& pose : poses) {
            const Vec3 w = pose.point({p[0], p[1], p[2]});
            if (isFinite(w) && maxAbsComponent(w) <= kMaxCoordinate) continue;
            std::ostringstream msg;
            msg << "vertex (" << p[0] << ", " << p[1] << ", " << p[2] << ") lies beyond "
                << kMaxCoordinate << " (the largest coordinate) after the transform of " << where;
            if (poses.size() > 1) msg << " during its motion";
            throw Error(ErrorKind::Format, msg.str(), objPath.string(),
                        "line " + std::to_string(lines.vertices[i]));
        }
    }
    lines.vertices = std::vector<int>();

    // One mesh vertex per distinct (position, normal, texture coordinate) triple of the faces,
    // numbered in the order the faces first name them. The first corner named at each position
    // is held in a flat table (a grid's `a//a` corners are all such); only the others (texture
    // seams, hard edges) go to a map.
    Mesh mesh;
    mesh.name = objPath.filename().string();
    std::vector<CornerAt> firstCorner(vertexCount);
    std::vector<std::uint32_t> firstVertex(vertexCount, kNoVertex);
    std::unordered_map<Corner, std::uint32_t, CornerHash> corners;
    bool anyNormals = false, anyUvs = false, anySmoothed = false;
    std::vector<std::uint64_t> smoothKey;  // per mesh vertex once one is smoothed
    std::size_t triangleCount = 0;
    for (const tinyobj::shape_t& shape : shapes)
        for (const unsigned char fv : shape.mesh.num_face_vertices) triangleCount += fv - 2u;
    mesh.indices.reserve(3 * triangleCount);
    mesh.positions.reserve(vertexCount);
    if (normalCount > 0) mesh.normals.reserve(vertexCount);
    if (texcoordCount > 0) mesh.uvs.reserve(vertexCount);
    auto addCorner = [&](tinyobj::index_t idx, unsigned group) -> std::uint32_t {
        // Normals and texture coordinates named in a file that has none are ignored (scanObj).
        if (normalCount == 0) idx.normal_index = -1;
        if (texcoordCount == 0) idx.texcoord_index = -1;
        // scanObj checked every index; this guards the reader's own resolution.
        if (idx.vertex_index < 0 || std::size_t(idx.vertex_index) >= vertexCount ||
            idx.normal_index >= int(normalCount) || idx.texcoord_index >= int(texcoordCount))
            throw Error(ErrorKind::Format, "a face index is out of range", objPath.string());
        const Corner key{idx.vertex_index, idx.normal_index, idx.texcoord_index,
                         idx.normal_index >= 0 ? 0u : group};
        const auto next = std::uint32_t(mesh.positions.size());
        const std::size_t at = std::size_t(idx.vertex_index);
        if (firstVertex[at] == kNoVertex) {
            firstVertex[at] = next, firstCorner[at] = {key.n, key.t, key.group};
        } else if (firstCorner[at] == CornerAt{key.n, key.t, key.group}) {
            return firstVertex[at];
        } else if (const auto [it, inserted] = corners.try_emplace(key, next); !inserted) {
            return it->second;
        }
        const float* p = &attrib.vertices[3 * at];
        mesh.positions.push_back({p[0], p[1], p[2]});
        if (normalCount > 0) {  // else every normal is zero (or smoothed below)
            Vec3 n{};
            if (idx.normal_index >= 0) {
                const float* q = &attrib.normals[3 * std::size_t(idx.normal_index)];
                n = {q[0], q[1], q[2]};
                anyNormals = anyNormals || length(n) > 0.0f;
            }
            mesh.normals.push_back(n);
        }
        if (idx.normal_index < 0 && group != 0) {
            anySmoothed = true;
            smoothKey.resize(next, 0);
            smoothKey.push_back((std::uint64_t(idx.vertex_index) + 1) << 32 | std::uint64_t(group));
        }
        if (texcoordCount > 0) {  // else every uv is zero, and none is kept
            Vec2 uv{};
            if (idx.texcoord_index >= 0) {
                const float* t = &attrib.texcoords[2 * std::size_t(idx.texcoord_index)];
                uv = {t[0], t[1]};
                anyUvs = true;
            }
            mesh.uvs.push_back(uv);
        }
        return next;
    };
    std::size_t released = 0;  // bytes of the shapes released since the heap was trimmed
    for (tinyobj::shape_t& shape : shapes) {
        const auto& faces = shape.mesh;
        std::size_t offset = 0;
        std::vector<Vec3> polygon;
        std::vector<std::uint32_t> triangles;
        for (std::size_t f = 0; f < faces.num_face_vertices.size(); ++f) {
            const std::size_t fv = faces.num_face_vertices[f];
            // The face's triangles as corner numbers (scanObj refused faces of under 3 corners).
            triangles.clear();
            if (fv == 3) {
                triangles = {0, 1, 2};
            } else {
                polygon.clear();
                for (std::size_t k = 0; k < fv; ++k) {
                    const int v = faces.indices[offset + k].vertex_index;
                    const float* p = &attrib.vertices[3 * std::size_t(std::max(v, 0))];
                    polygon.push_back({p[0], p[1], p[2]});
                }
                // A face of at most kMaxObjFaceCorners stays far within the clipper's budget.
                GLINT_CHECK(triangulatePolygon(polygon, triangles));
            }
            const unsigned group =
                f < faces.smoothing_group_ids.size() ? faces.smoothing_group_ids[f] : 0u;
            int mat = -1;
            const int id = f < faces.material_ids.size() ? faces.material_ids[f] : -1;
            if (id >= 0 && id < int(objMaterial.size())) {
                mat = objMaterial[id];
            } else if (overrideMaterial < 0) {
                if (defaultMaterial < 0) {
                    defaultMaterial = loader.materialIndex("default");
                    if (defaultMaterial < 0) {
                        Material m;
                        m.name = "default";
                        defaultMaterial = loader.addMaterial(m);
                    }
                }
                mat = defaultMaterial;
            }
            for (std::size_t t = 0; t + 2 < triangles.size(); t += 3) {
                for (int v = 0; v < 3; ++v)
                    mesh.indices.push_back(
                        addCorner(faces.indices[offset + triangles[t + std::size_t(v)]], group));
                mesh.assignMaterial(mesh.triangleCount() - 1, std::uint32_t(std::max(mat, 0)));
            }
            offset += fv;
        }
        // Released as it is read, and its pages handed back to the system (the heap would
        // keep them) every 8 MB, so that the mesh's arrays take their place instead of adding
        // to them.
        released += faces.indices.size() * sizeof(tinyobj::index_t) +
                    faces.num_face_vertices.size() + 4 * faces.material_ids.size() +
                    4 * faces.smoothing_group_ids.size();
        shape = tinyobj::shape_t();
#if defined(__GLIBC__)
        if (released >= (std::size_t(8) << 20)) malloc_trim(0), released = 0;
#endif
    }
    // What the reader gave is no longer needed.
    attrib = tinyobj::attrib_t(), shapes = std::vector<tinyobj::shape_t>();
    corners = decltype(corners)(), firstCorner = std::vector<CornerAt>();
    firstVertex = std::vector<std::uint32_t>();
    if (anySmoothed) {
        smoothKey.resize(mesh.positions.size(), 0);
        mesh.normals.resize(mesh.positions.size());  // zero where the file gave none
        smoothGroupNormals(mesh, smoothKey);
        anyNormals = true;
    }
    if (!anyNormals) mesh.normals = std::vector<Vec3>();
    if (!anyUvs) mesh.uvs = std::vector<Vec2>();
    // Tangents for `norm` normal maps (MikkTSpace convention, as Blender's importer reads them).
    if (normalMapped && overrideMaterial < 0) {
        if (anyNormals && anyUvs)
            generateTangents(mesh, 0, mesh.triangleCount());
        else
            warn(std::string("a material has a 'norm' normal map but the faces have no ") +
                 (anyNormals ? "texture coordinates" : "normals") + ": it is not applied");
    }
    if (bumpMapped && overrideMaterial < 0 && !anyUvs)
        warn(
            "a material has a bump map but the faces have no texture coordinates: it is not "
            "applied");
    if (overrideMaterial >= 0) mesh.assignMaterial(0, 0u);

    // A shape whose emissive faces have no area cannot emit: reject it clearly.
    double emissiveArea = 0.0;
    bool anyEmissive = false;
    const Affine& pose = poses.front();
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
        const int material = overrideMaterial >= 0 ? overrideMaterial : int(mesh.materialOf(t));
        if (!scene.materials[std::size_t(material)].emissive()) continue;
        anyEmissive = true;
        const std::uint32_t* idx = &mesh.indices[3 * t];
        emissiveArea +=
            triangleArea(pose.point(mesh.positions[idx[0]]), pose.point(mesh.positions[idx[1]]),
                         pose.point(mesh.positions[idx[2]]));
    }
    if (anyEmissive && !(emissiveArea > 0.0))
        throw Error(ErrorKind::Format, "emissive faces have zero total area (zero-area light)",
                    objPath.string(), where);
    scene.meshes.push_back(std::move(mesh));
    return std::uint32_t(scene.meshes.size() - 1);
}

}  // namespace

const AssetFormat& objAssetFormat() {
    static const AssetFormat format{
        .name = "Wavefront OBJ",
        .key = "obj",
        .shapeDescription = "a Wavefront OBJ file",
        .fileWord = "OBJ",
        .expected = "an OBJ file",
        .extensions = {".obj"},
        .shapeKeys = {},
        .refusedKeys = {{"materials",
                         "'materials' renames a glTF asset's materials; an OBJ shape takes "
                         "'material', and JSON materials override MTL materials by name"},
                        {"edits",
                         "'edits' changes a glTF asset's material factors; an OBJ shape's "
                         "materials are edited as JSON materials of the same name"}},
        // Predicted from a count of the statements before the reader reads the text.
        .predictLoad = predictObjLoad,
        .import =
            [](ImportContext& loader, const AssetShape& shape) {
                loader.placeMesh(
                    importObj(loader, shape.file, shape.poses, shape.material, shape.where), shape);
            },
    };
    return format;
}

}  // namespace glint::render::detail

// The private contents of a loaded Scene: camera, film, materials, textures, triangles,
// environment. Shapes are flattened into one triangle soup in world space.
#pragma once

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "glint/image/image.h"
#include "glint/render/settings.h"
#include "materials/material_kinds.h"
#include "scene/texture_levels.h"
#include "scene/texture_store.h"
#include "scene/transform.h"
#include "vecmath.h"

namespace glint::render::detail {

/// Kinds of material ("type" in scene.json), in the order of their registration
/// (materials/material_kinds.h); what each kind is and does is its MaterialKind
/// (materials/bsdf.h, materialKind()).
enum class MaterialType {
#define GLINT_MATERIAL_TYPE(Enum, object) Enum,
    GLINT_MATERIAL_KINDS(GLINT_MATERIAL_TYPE)
#undef GLINT_MATERIAL_TYPE
};

/// How a material lets light through its surface where it is not opaque (glTF alphaMode).
enum class AlphaMode { Opaque, Mask, Blend };

/// An affine map of texture coordinates, uv' = m · (u, v, 1): glTF's KHR_texture_transform
/// (offset, rotation, scale) composed with the flip between glTF's top-left and Glint's
/// bottom-left texture origin; applied to the mesh's texture coordinate set `set`.
struct UvTransform {
    float m[2][3] = {{1.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}};
    bool identity = true;
    /// The set read (glTF texCoord): 0 Mesh::uvs, 1 Mesh::uvs1 (set 0 where the mesh has none).
    std::uint8_t set = 0;

    Vec2 apply(Vec2 uv) const {
        if (identity) return uv;
        return {m[0][0] * uv.x + m[0][1] * uv.y + m[0][2],
                m[1][0] * uv.x + m[1][1] * uv.y + m[1][2]};
    }
    /// Maps a difference of texture coordinates (a footprint's axis).
    Vec2 applyLinear(Vec2 d) const {
        if (identity) return d;
        return {m[0][0] * d.x + m[0][1] * d.y, m[1][0] * d.x + m[1][1] * d.y};
    }
};

/// A texture a material reads, and how its texture coordinates are transformed.
struct TextureSlot {
    int texture = -1;  ///< index into SceneData::textures; -1: none
    UvTransform transform;

    bool present() const { return texture >= 0; }
};

/// The largest radiance a scene may emit (emission, environment colour × scale): its variance
/// (up to about the square) must still fit a float EXR (3.4e38).
inline constexpr double kMaxRadiance = 1e18;
/// The largest world coordinate (after transforms): squared distances and the light sampling
/// densities (distance² / area) stay within float range. The Cornell box at scale 1e6 is 5.6e8.
inline constexpr float kMaxCoordinate = 1e9f;
/// The smallest camera-to-lookAt distance: the camera normalises the view direction in float,
/// and the square of a shorter one leaves float's normal range (1.2e-38).
inline constexpr double kMinViewDistance = 1e-18;

/// The scene.json name of a material type ("diffuse", ...).
const char* materialTypeName(MaterialType type);

/// One material. albedo is the diffuse reflectance, the mirror/conductor tint or the dielectric
/// transmittance tint; `texture` (index into SceneData::textures) replaces it when >= 0.
struct Material {
    std::string name;
    MaterialType type = MaterialType::Diffuse;
    Vec3 albedo{0.8f, 0.8f, 0.8f};  ///< metallicRoughness: the base colour factor
    int texture = -1;               ///< base colour texture (multiplies albedo for glTF assets)
    UvTransform textureTransform;   ///< of `texture`
    Vec3 emission{};
    float ior = 1.5f;           ///< dielectric index of refraction
    float roughness = 0.0f;     ///< conductor, dielectric: GGX alpha = roughness^2
    float metallic = 1.0f;      ///< metallicRoughness: 0 dielectric base, 1 metal
    float transmission = 0.0f;  ///< metallicRoughness: KHR_materials_transmission factor
    bool hasEtaK = false;       ///< conductor: complex Fresnel with eta/k, else Schlick(specular)
    Vec3 eta{1.0f, 1.0f, 1.0f};
    Vec3 k{};
    Vec3 specular{1.0f, 1.0f, 1.0f};
    /// The emission as a look panel shows it: colour × strength = emission (derived from the
    /// emission at load: strength = its largest component; kept apart after look edits so that
    /// a strength of 0 keeps the colour).
    Vec3 emissionColor{1.0f, 1.0f, 1.0f};
    float emissionStrength = 0.0f;
    /// metallicRoughness textures (glTF): roughness in G and metallic in B multiply the
    /// factors; a tangent-space normal map scaled in xy by normalScale; emission multiplies
    /// `emission`; transmission in R multiplies `transmission`.
    TextureSlot roughnessMetallicMap, normalMap, emissionMap, transmissionMap;
    float normalScale = 1.0f;
    /// A height map (MTL `bump`, `map_Bump`): the luminance of its texture, read as data, times
    /// bumpMultiplier (`-bm`) is a height in scene units along the shading normal, which bends
    /// it (applyNormalMap). Read where the material has no normalMap.
    TextureSlot bumpMap;
    float bumpMultiplier = 1.0f;
    /// Where the surface is not there: alpha = opacity × base colour texture alpha; Mask cuts
    /// out alpha < alphaCutoff, Blend lets light through with probability 1 − alpha.
    AlphaMode alphaMode = AlphaMode::Opaque;
    float opacity = 1.0f;
    float alphaCutoff = 0.5f;
    /// A texture's factor multiplies it (glTF) rather than being replaced by it (OBJ, JSON).
    bool textureTimesFactor = false;
    bool fromJson = false;  ///< defined in scene.json's /materials (else by an MTL file)
    /// A material an asset brought and edits in place (a glTF material): its name in the
    /// asset and the index of the scene.json shape that placed the asset (-1: none, or the
    /// asset's materials are edited as JSON materials of the same name, as MTL ones are), where
    /// saveScene writes its look edits ("edits"; ImportContext::applyLookEdits reads them).
    std::string assetName;
    int assetShape = -1;
    bool edited = false;  ///< changed through Scene::setLook since loading

    bool emissive() const { return !isBlack(emission); }
    /// Sets emissionColor and emissionStrength from emission.
    void deriveEmissionLook() {
        emissionStrength = std::max(emission.x, std::max(emission.y, emission.z));
        emissionColor =
            emissionStrength > 0.0f ? emission / emissionStrength : Vec3{1.0f, 1.0f, 1.0f};
    }
};

/// What a texture's values are: colour (decoded from sRGB when the file is sRGB-encoded, as
/// 8-bit PNG and JPEG are) or data (normals, roughness and metallic: used as stored).
enum class TextureUse { Color, Data };

/// The side of the MIP level that hits after a diffuse or glossy bounce read (kCoarseFootprint).
inline constexpr int kCoarseTextureSize = 64;

/// The footprint of hits after a diffuse or glossy bounce: a texel of a 64² level, so that they
/// read the texture's resident levels, not the tile cache (a widened footprint; docs/assets.md,
/// "Textures").
inline constexpr TexFootprint kCoarseFootprint{{1.0f / kCoarseTextureSize, 0.0f},
                                               {0.0f, 1.0f / kCoarseTextureSize}};

/// An RGBA texture: a file read through the scene's TextureStore (tiled, MIP-mapped, cached)
/// and filtered by the lookup's footprint (TextureLevels), or an image held in memory (embedded
/// glTF images, textures made by code) looked up bilinearly.
struct Texture {
    std::filesystem::path path;  ///< the file, or for an embedded image "ASSET#images[i]"
    /// An embedded image's encoded bytes (glTF bufferView or data URI); null for a file.
    std::shared_ptr<const std::vector<unsigned char>> bytes;
    TextureUse use = TextureUse::Color;
    TextureWrap wrapS = TextureWrap::Repeat, wrapT = TextureWrap::Repeat;
    Image image;  ///< in memory: 4 channels (RGBA; alpha 1 where the file has none), linear
    /// A file: the store that reads it and its index there (store null: `image` is the texture).
    std::shared_ptr<const TextureStore> store;
    int file = -1;
    bool decodeSrgb = false;  ///< a colour texture stored sRGB-encoded: decoded after filtering
    /// The file's content hash for sceneContentHash: OIIO's fingerprint if it has one, else a
    /// hash of its bytes (computed once at load).
    std::uint64_t contentHash = 0;

    /// A file texture's MIP levels, filtered by Glint: those of at most kResidentTextureSize
    /// texels a side held in memory, finer ones read from the store's tile cache.
    TextureLevels levels;

    /// The value at `uv` (origin at the bottom-left of the image, the OBJ convention) filtered
    /// over `footprint` (the change of uv per ray step in x and y; zero: bilinear). An image in
    /// memory is always looked up bilinearly.
    Vec4 lookup(Vec2 uv, const TexFootprint& footprint = {}) const;
    /// lookup()'s filter at one of its two MIP levels, picked by `u` in [0, 1)
    /// (TextureLevels::lookupOneLevel): its mean over uniform u is lookup()'s value. An image in
    /// memory: lookup().
    Vec4 lookupOneLevel(Vec2 uv, const TexFootprint& footprint, float u) const;
    /// Fills `levels` from the store (a file texture). A file that cannot be read there is
    /// recorded in the store (throwIfFailed()).
    void readLevels();
    /// The mean colour over the whole texture (light power estimates).
    Vec3 meanColour() const;
};

/// A punctual light of a glTF asset (KHR_lights_punctual): a delta light, reached only by
/// next-event estimation. Intensities are radiometric: glTF's candela and lux divided by
/// 683 lm/W, as Blender's importer converts them.
struct PunctualLight {
    enum class Kind { Point, Spot, Directional };
    Kind kind = Kind::Point;
    std::string name;
    Vec3 position;          ///< world space (point, spot)
    Vec3 direction;         ///< unit, where the light shines (spot, directional)
    Vec3 intensity;         ///< W/sr (point, spot) or W/m² (directional), per channel
    float cosInner = 1.0f;  ///< spot: full intensity inside this cone
    float cosOuter = 0.0f;  ///< spot: none outside this cone
};

/// A camera an asset brings (glTF perspective cameras), in world space.
struct AssetCamera {
    std::string name;
    Vec3 position, lookAt, up;
    float fovY = 45.0f;        ///< degrees
    float aspectRatio = 0.0f;  ///< width / height, 0 when the asset leaves it open
};

/// The camera of scene.json. With motion, position and lookAt move linearly from their values
/// at shutter open to motionPosition / motionLookAt at shutter close (up stays fixed).
struct CameraDesc {
    Vec3 position{0.0f, 0.0f, 0.0f};
    Vec3 lookAt{0.0f, 0.0f, -1.0f};
    Vec3 up{0.0f, 1.0f, 0.0f};
    float fovY = 45.0f;  ///< vertical field of view, degrees
    float lensRadius = 0.0f;
    float focusDistance = 1.0f;
    float shutterOpen = 0.0f, shutterClose = 1.0f;
    bool hasMotion = false;
    Vec3 motionPosition{}, motionLookAt{};
};

/// The camera an asset brings, as scene.json would give it (pinhole, static).
inline CameraDesc cameraOf(const AssetCamera& a) {
    CameraDesc cam;
    cam.position = a.position;
    cam.lookAt = a.lookAt;
    cam.up = a.up;
    cam.fovY = a.fovY;
    return cam;
}

/// The environment: none, a constant colour or a lat-long image (+y up, u = 0.5 looks down -z).
struct EnvironmentDesc {
    enum class Kind { None, Constant, Image };
    Kind kind = Kind::None;
    Vec3 baseColor{};        ///< constant radiance as given (before scale)
    Vec3 color{};            ///< constant radiance (baseColor multiplied by scale)
    float scale = 1.0f;      ///< multiplies the colour or the image
    float rotateDeg = 0.0f;  ///< rotation about +y
    std::filesystem::path path;
    Image source;         ///< the image as read (3 channels, linear), before scale
    Image image;          ///< source multiplied by scale
    bool edited = false;  ///< changed through Scene::setLook since loading
};

/// A triangle mesh, indexed: triangle t has corners indices[3t..3t+2]. Loaders build meshes in
/// their object space; SceneData::finishMeshes then moves a mesh that only one static
/// instance uses into world space (its instance's transform becomes the identity), so that only
/// shared or moving meshes are transformed at render time.
struct Mesh {
    std::string name;             ///< for messages: the OBJ file, or the glTF mesh
    std::vector<Vec3> positions;  ///< per vertex
    std::vector<Vec3> normals;    ///< per vertex, or empty; a zero normal means none
    std::vector<Vec4> tangents;   ///< per vertex, or empty: xyz unit tangent, w = ±1 handedness
    std::vector<Vec2> uvs;        ///< per vertex, or empty
    std::vector<Vec2> uvs1;       ///< a second set (glTF TEXCOORD_1) per vertex, or empty
    std::vector<Vec4> colors;     ///< linear RGBA per vertex (glTF COLOR_0), or empty
    std::vector<std::uint32_t> indices;  ///< 3 per triangle
    /// Indices into SceneData::materials: one per triangle, or a single one that every triangle
    /// shares (a mesh of one material holds 4 bytes, not 4 per triangle). Read through
    /// materialOf; written through assignMaterial, which keeps the single entry while it can.
    std::vector<std::uint32_t> materials;
    /// The unit geometric normal of each triangle (triangleNormal of its corners) of a mesh in
    /// world space, in a scene of at most kFaceNormalTriangles triangles; else empty, and
    /// SceneData::triangle computes it at every hit (SceneData::finishMeshes).
    std::vector<Vec3> faceNormals;

    std::size_t triangleCount() const { return indices.size() / 3; }
    std::size_t vertexCount() const { return positions.size(); }
    /// The material of triangle `prim`.
    std::uint32_t materialOf(std::size_t prim) const {
        return materials[materials.size() == 1 ? 0 : prim];
    }
    /// Gives the triangles from `first` to triangleCount() (those appended since the last call)
    /// material `material`: one entry stays one while every triangle has the same material, and
    /// becomes one per triangle at the first triangle of another.
    void assignMaterial(std::size_t first, std::uint32_t material) {
        const std::size_t count = triangleCount();
        if (first >= count) return;
        const bool shared = first == 0 || (materials.size() == 1 && materials[0] == material);
        if (shared) {
            materials.assign(1, material);
            return;
        }
        if (materials.size() == 1) materials.assign(first, materials[0]);
        materials.resize(count, material);
    }
    /// Bytes of the arrays above (for memory figures).
    std::size_t bytes() const;
};

/// The vertex colour (Mesh::colors) at barycentrics (b1, b2) of triangle `prim`; the mesh must
/// have colours.
inline Vec4 vertexColor(const Mesh& mesh, std::uint32_t prim, float b1, float b2) {
    const std::uint32_t* idx = &mesh.indices[3 * std::size_t(prim)];
    const Vec4 &c0 = mesh.colors[idx[0]], &c1 = mesh.colors[idx[1]], &c2 = mesh.colors[idx[2]];
    const float b0 = 1.0f - b1 - b2;
    return {c0.x * b0 + c1.x * b1 + c2.x * b2, c0.y * b0 + c1.y * b1 + c2.y * b2,
            c0.z * b0 + c1.z * b1 + c2.z * b2, c0.w * b0 + c1.w * b1 + c2.w * b2};
}

/// The texture coordinates of set `set` (1: TEXCOORD_1 where the mesh has it, else set 0) at
/// barycentrics (b1, b2) of triangle `prim`; the mesh must have uvs.
inline Vec2 surfaceUv(const Mesh& mesh, int set, std::uint32_t prim, float b1, float b2) {
    const std::vector<Vec2>& uvs = set != 0 && !mesh.uvs1.empty() ? mesh.uvs1 : mesh.uvs;
    const std::uint32_t* idx = &mesh.indices[3 * std::size_t(prim)];
    const Vec2 &a = uvs[idx[0]], &b = uvs[idx[1]], &c = uvs[idx[2]];
    const float b0 = 1.0f - b1 - b2;
    return {a.x * b0 + b.x * b1 + c.x * b2, a.y * b0 + b.y * b1 + c.y * b2};
}

/// One placement of a mesh in the world. A static instance maps object to world space by
/// `transform`; a moving one (motion >= 0) follows SceneData::motions[motion] over the shutter
/// (its `transform` is the shutter-open pose).
struct Instance {
    std::uint32_t mesh = 0;
    Affine transform;
    bool identity = true;        ///< transform is the identity (mesh in world space)
    std::int32_t motion = -1;    ///< index into SceneData::motions, or -1 (static)
    std::int32_t material = -1;  ///< replaces every triangle's material when >= 0
    std::string name;            ///< for messages: the JSON place or glTF node
};

/// The motion of a moving instance: the pose at time step k (normalised time k / (steps - 1)) is
/// steps[k]; between steps the vertices move linearly, exactly as they do under Embree's
/// instance transform interpolated linearly between the step poses.
struct InstanceMotion {
    std::vector<Affine> steps;  ///< at least 2
};

/// A triangle at one instant in world space: vertices, per-vertex shading normals (valid when
/// hasNormals; a zero normal means none) and the unit geometric normal.
struct TriangleView {
    Vec3 p[3];
    Vec3 n[3];
    Vec3 ng;
    bool hasNormals = false;
};

/// Scenes of at most this many triangles keep their world-space meshes' face normals
/// (Mesh::faceNormals, 12 bytes a triangle; Embree's own triangles hold more than that): a hit
/// then reads its normal instead of waiting on a square root and three divisions in double
/// (the largest part of what each ray of the Cornell box lost after 8123d93: docs/renderer.md,
/// "Performance"). Larger scenes compute it at each hit, the same bits, without the memory.
inline constexpr std::size_t kFaceNormalTriangles = std::size_t(1) << 20;

/// The unit geometric normal of triangle `prim`, with corners p0, p1, p2, of a mesh in world
/// space: the kept one (Mesh::faceNormals) where the mesh keeps them, else triangleNormal of the
/// corners (the same bits). The one place that choice is made (worldTriangle, shading a hit).
[[gnu::always_inline]] inline Vec3 faceNormal(const Mesh& mesh, std::uint32_t prim, const Vec3& p0,
                                              const Vec3& p1, const Vec3& p2) {
    return prim < mesh.faceNormals.size() ? mesh.faceNormals[prim] : triangleNormal(p0, p1, p2);
}

/// Triangle `prim` of a mesh in world space (an identity, static instance's). Always inlined:
/// called at every hit, its copies fold into the caller's registers.
[[gnu::always_inline]] inline TriangleView worldTriangle(const Mesh& mesh, std::uint32_t prim) {
    const std::uint32_t* idx = &mesh.indices[3 * std::size_t(prim)];
    TriangleView tri;
    tri.hasNormals = !mesh.normals.empty();
    for (int v = 0; v < 3; ++v) {
        tri.p[v] = mesh.positions[idx[v]];
        if (tri.hasNormals) tri.n[v] = mesh.normals[idx[v]];
    }
    tri.ng = faceNormal(mesh, prim, tri.p[0], tri.p[1], tri.p[2]);
    return tri;
}

/// Where a ray hit: an instance and one of its mesh's triangles.
struct SurfaceId {
    std::uint32_t instance = 0, prim = 0;
};

/// Everything a Scene holds.
/// An axis-aligned box; empty (lo above hi) until it holds a point.
struct Box {
    Vec3 lo{std::numeric_limits<float>::max(), std::numeric_limits<float>::max(),
            std::numeric_limits<float>::max()};
    Vec3 hi = lo * -1.0f;

    bool empty() const { return !(lo.x <= hi.x); }
    void grow(const Vec3& p) {
        for (int c = 0; c < 3; ++c) lo[c] = std::min(lo[c], p[c]), hi[c] = std::max(hi[c], p[c]);
    }
};

struct SceneData {
    std::filesystem::path path;
    std::string sourceJson;          ///< the text the scene was parsed from (saveScene edits it)
    std::uint64_t lookRevision = 0;  ///< counts look edits (Scene::setLook)
    int width = 0, height = 0;
    Settings settings;
    CameraDesc camera;
    std::vector<Material> materials;
    std::vector<Texture> textures;
    /// Reads the texture files (null until the loader opens the first one).
    std::shared_ptr<TextureStore> textureStore;
    std::vector<Mesh> meshes;
    std::vector<Instance> instances;
    std::vector<InstanceMotion> motions;
    /// The bounding box of every vertex of every instance at shutter open (empty without
    /// geometry), computed once when loading ends (computeBounds): the bare asset's framing
    /// camera, the power of lights at infinity.
    Box bounds;
    /// The largest side of the bounding box of every vertex (every pose of moving shapes): the
    /// scale that ray offsets follow (1 for a scene without geometry).
    float extent = 1.0f;
    EnvironmentDesc environment;
    std::vector<PunctualLight> punctualLights;
    std::vector<AssetCamera> assetCameras;
    /// What the loader ignored and the user should know (an unread glTF extension...), one line
    /// each.
    std::vector<std::string> warnings;
    /// Every file the loader read, once each in the order read: the scene file, OBJ and MTL
    /// files, glTF files and their buffer files, texture and environment images (Scene::inputs).
    std::vector<std::filesystem::path> inputs;

    /// Records `file` among the inputs (once).
    void addInput(const std::filesystem::path& file) {
        if (std::find(inputs.begin(), inputs.end(), file) == inputs.end()) inputs.push_back(file);
    }

    /// Triangles over every instance (an instanced mesh counts once per instance).
    std::size_t triangleCount() const;
    /// True when a shape or the camera moves during the shutter.
    bool hasMotion() const { return !motions.empty() || camera.hasMotion; }

    /// The material index of a triangle of an instance.
    std::uint32_t materialOf(std::uint32_t instance, std::uint32_t prim) const {
        const Instance& inst = instances[instance];
        return inst.material >= 0 ? std::uint32_t(inst.material)
                                  : meshes[inst.mesh].materialOf(prim);
    }
    std::uint32_t materialOf(SurfaceId s) const { return materialOf(s.instance, s.prim); }

    /// Triangle `prim` of `instance` in world space at normalised shutter time `time` in [0, 1].
    [[gnu::always_inline]] TriangleView triangle(std::uint32_t instance, std::uint32_t prim,
                                                 float time) const {
        const Instance& inst = instances[instance];
        if (inst.motion < 0 && inst.identity) return worldTriangle(meshes[inst.mesh], prim);
        return posedTriangle(inst, prim, time);
    }
    /// triangle() of a moving or transformed instance.
    TriangleView posedTriangle(const Instance& inst, std::uint32_t prim, float time) const;
    /// The same at shutter open, for static instances (lights, bounds).
    TriangleView triangle(std::uint32_t instance, std::uint32_t prim) const {
        return triangle(instance, prim, 0.0f);
    }

    /// Ends loading: moves every mesh used by exactly one static instance into world space (the
    /// instance's transform becomes the identity; meshes used by several instances or by moving
    /// ones stay in object space), pads each mesh's position storage by one vertex so that
    /// Embree can read it in place (it reads 16 bytes per float3), and keeps the face normals of
    /// the world-space meshes of a scene of at most kFaceNormalTriangles triangles.
    void finishMeshes();
};

}  // namespace glint::render::detail

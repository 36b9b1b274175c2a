// The private contents of a loaded Scene: camera, film, materials, textures, triangles,
// environment. Shapes are flattened into one triangle soup in world space.
#pragma once

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "glint/image/image.h"
#include "glint/render/settings.h"
#include "scene/transform.h"
#include "vecmath.h"

namespace glint::render::detail {

/// Kinds of material ("type" in scene.json).
enum class MaterialType { Diffuse, Mirror, Dielectric, Conductor };

/// The largest radiance a scene may emit (emission, environment colour × scale): its variance
/// (up to about the square) must still fit a float EXR (3.4e38).
inline constexpr double kMaxRadiance = 1e18;
/// The largest world coordinate (after transforms): squared distances and the light sampling
/// densities (distance² / area) stay within float range. The Cornell box at scale 1e6 is 5.6e8.
inline constexpr float kMaxCoordinate = 1e9f;

/// The scene.json name of a material type ("diffuse", ...).
const char* materialTypeName(MaterialType type);

/// One material. albedo is the diffuse reflectance, the mirror/conductor tint or the dielectric
/// transmittance tint; `texture` (index into SceneData::textures) replaces it when >= 0.
struct Material {
    std::string name;
    MaterialType type = MaterialType::Diffuse;
    Vec3 albedo{0.8f, 0.8f, 0.8f};
    int texture = -1;
    Vec3 emission{};
    float ior = 1.5f;        ///< dielectric index of refraction
    float roughness = 0.0f;  ///< conductor: GGX alpha = roughness^2
    bool hasEtaK = false;    ///< conductor: complex Fresnel with eta/k, else Schlick(specular)
    Vec3 eta{1.0f, 1.0f, 1.0f};
    Vec3 k{};
    Vec3 specular{1.0f, 1.0f, 1.0f};
    /// The emission as a look panel shows it: colour × strength = emission (derived from the
    /// emission at load: strength = its largest component; kept apart after look edits so that
    /// a strength of 0 keeps the colour).
    Vec3 emissionColor{1.0f, 1.0f, 1.0f};
    float emissionStrength = 0.0f;
    bool fromJson = false;  ///< defined in scene.json's /materials (else by an MTL file)
    bool edited = false;    ///< changed through Scene::setLook since loading

    bool emissive() const { return !isBlack(emission); }
    /// Sets emissionColor and emissionStrength from emission.
    void deriveEmissionLook() {
        emissionStrength = std::max(emission.x, std::max(emission.y, emission.z));
        emissionColor =
            emissionStrength > 0.0f ? emission / emissionStrength : Vec3{1.0f, 1.0f, 1.0f};
    }
};

/// An RGB texture (linear values) looked up bilinearly with repeat wrapping.
struct Texture {
    std::filesystem::path path;
    Image image;  ///< 3 channels, linear

    /// Bilinear lookup; uv origin at the bottom-left of the image (OBJ convention).
    Vec3 lookup(Vec2 uv) const;
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

/// A shape that moves during the shutter. Its triangles [firstTriangle, firstTriangle + count)
/// keep their shutter-open pose in SceneData::positions / normals; the pose at time step k
/// (normalised time k / (steps.size() - 1)) is steps[k] applied to the object-space vertices.
/// Between steps the vertices move linearly, exactly as Embree's motion-blur triangles do.
struct ShapeMotion {
    std::uint32_t firstTriangle = 0, triangleCount = 0;
    std::vector<Affine> steps;          ///< at least 2
    std::vector<Vec3> objectPositions;  ///< 3 per triangle, object space
    std::vector<Vec3> objectNormals;    ///< 3 per triangle (zero = none), object space
};

/// Scratch storage for the pose of a moving triangle (see SceneData::triangleAt).
struct PosedTriangle {
    Vec3 p[3], n[3];
};

/// A triangle at one instant: vertices, per-vertex shading normals (nullptr when the scene has
/// none; a zero normal means none) and the unit geometric normal.
struct TriangleView {
    const Vec3* p;
    const Vec3* n;
    Vec3 ng;
};

/// Everything a Scene holds.
struct SceneData {
    std::filesystem::path path;
    std::string sourceJson;          ///< the text the scene was parsed from (saveScene edits it)
    std::uint64_t lookRevision = 0;  ///< counts look edits (Scene::setLook)
    int width = 0, height = 0;
    Settings settings;
    CameraDesc camera;
    std::vector<Material> materials;
    std::vector<Texture> textures;
    /// Triangle t has vertices positions[3t..3t+2] (world space).
    std::vector<Vec3> positions;
    /// Per-vertex shading normals parallel to positions, or empty; a zero normal means none.
    std::vector<Vec3> normals;
    /// Per-vertex texture coordinates parallel to positions, or empty.
    std::vector<Vec2> uvs;
    std::vector<std::uint32_t> triangleMaterial;
    /// Unit geometric normal per triangle, cross(p1 - p0, p2 - p0) (+z for degenerate ones).
    std::vector<Vec3> faceNormals;
    /// The largest side of the bounding box of every vertex (every pose of moving shapes): the
    /// scale that ray offsets follow (1 for a scene without geometry).
    float extent = 1.0f;
    EnvironmentDesc environment;
    /// Moving shapes (empty for a static scene).
    std::vector<ShapeMotion> motions;
    /// Per triangle: index into motions or -1; empty when no shape moves.
    std::vector<std::int32_t> triangleMotion;

    std::size_t triangleCount() const { return triangleMaterial.size(); }
    /// True when a shape or the camera moves during the shutter.
    bool hasMotion() const { return !motions.empty() || camera.hasMotion; }

    /// Triangle t at normalised shutter time `time` in [0, 1]. Static triangles return views of
    /// the scene arrays; moving ones are posed into `scratch` (which the view then points to).
    TriangleView triangleAt(std::size_t t, float time, PosedTriangle& scratch) const {
        const Vec3* n = normals.empty() ? nullptr : &normals[3 * t];
        if (triangleMotion.empty() || triangleMotion[t] < 0)
            return {&positions[3 * t], n, faceNormals[t]};
        return poseMoving(t, time, scratch);
    }
    /// The moving-triangle case of triangleAt.
    TriangleView poseMoving(std::size_t t, float time, PosedTriangle& scratch) const;
};

}  // namespace glint::render::detail

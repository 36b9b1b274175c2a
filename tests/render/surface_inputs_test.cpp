// What a material's textures give at a hit (integrators/surface_inputs.cpp): the base colour
// factor times or replaced by its texture, glTF's roughness (G) and metallic (B) channels times
// their factors, and a tangent-space normal map bending the shading normal in the mesh's
// tangent frame (handedness, scale, instance transforms), checked against hand-computed normals.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <vector>

#include "glint/render/renderer.h"
#include "glint/render/scene.h"
#include "integrators/surface_inputs.h"
#include "scene/camera.h"
#include "scene/scene_access.h"
#include "scene/scene_data.h"
#include "scene/transform.h"
#include "test_util.h"

namespace glint::render {
namespace {

/// One triangle in the xy plane (normal +z, tangent +x with handedness `w`), one instance with
/// `transform`, one material whose normal map is the single texel `rgb`.
detail::SceneData oneTriangle(Vec3 rgb, float w = 1.0f, detail::Affine transform = {}) {
    detail::SceneData d;
    detail::Mesh mesh;
    mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    mesh.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
    mesh.tangents = {{1, 0, 0, w}, {1, 0, 0, w}, {1, 0, 0, w}};
    mesh.uvs = {{0, 0}, {1, 0}, {0, 1}};
    mesh.indices = {0, 1, 2};
    mesh.materials = {0};
    d.meshes.push_back(mesh);
    detail::Instance inst;
    inst.transform = transform;
    inst.identity = false;
    d.instances.push_back(inst);
    detail::Texture t;
    t.use = detail::TextureUse::Data;
    t.image = Image(1, 1, 4, 1.0f);
    for (int c = 0; c < 3; ++c) t.image(0, 0, c) = rgb[c];
    d.textures.push_back(t);
    detail::Material m;
    m.type = detail::MaterialType::MetallicRoughness;
    m.normalMap.texture = 0;
    d.materials.push_back(m);
    return d;
}

SurfacePoint centre() {
    SurfacePoint at;
    at.b1 = at.b2 = 1.0f / 3.0f;
    at.uv = {1.0f / 3.0f, 1.0f / 3.0f};
    at.hasUv = true;
    return at;
}

void expectNear(const Vec3& a, const Vec3& b, float tol = 1e-5f) {
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(a[c], b[c], tol) << "component " << c;
}

/// The texel encoding unit tangent-space normal n: (n + 1) / 2.
Vec3 encode(const Vec3& n) {
    return (n + Vec3{1, 1, 1}) * 0.5f;
}

}  // namespace

TEST(SurfaceInputs, AFlatNormalMapKeepsTheShadingNormal) {
    const detail::SceneData d = oneTriangle({0.5f, 0.5f, 1.0f});
    expectNear(applyNormalMap(d, d.materials[0], centre(), {0, 0, 1}), {0, 0, 1});
}

TEST(SurfaceInputs, ANormalMapBendsAlongTheTangentFrame) {
    const float s = std::sin(0.5f), c = std::cos(0.5f);
    // Tilted towards +u (the tangent, +x) and towards +v (the bitangent, +y for w = +1).
    detail::SceneData d = oneTriangle(encode({s, 0, c}));
    expectNear(applyNormalMap(d, d.materials[0], centre(), {0, 0, 1}), {s, 0, c}, 2e-3f);
    d = oneTriangle(encode({0, s, c}));
    expectNear(applyNormalMap(d, d.materials[0], centre(), {0, 0, 1}), {0, s, c}, 2e-3f);
    // Handedness −1 (a mirrored texture): the bitangent is −y.
    d = oneTriangle(encode({0, s, c}), -1.0f);
    expectNear(applyNormalMap(d, d.materials[0], centre(), {0, 0, 1}), {0, -s, c}, 2e-3f);
    // normalScale scales the xy tilt before normalising.
    d = oneTriangle(encode({s, 0, c}));
    d.materials[0].normalScale = 0.0f;
    expectNear(applyNormalMap(d, d.materials[0], centre(), {0, 0, 1}), {0, 0, 1}, 2e-3f);
}

TEST(SurfaceInputs, TheTangentFrameFollowsTheInstanceTransform) {
    // The instance turns the triangle 90° about z: its tangent +x becomes +y in the world.
    const float s = std::sin(0.5f), c = std::cos(0.5f);
    detail::TransformDesc turn;
    turn.axis = {0, 0, 1};
    turn.degrees = 90.0f;
    const detail::SceneData d = oneTriangle(encode({s, 0, c}), 1.0f, detail::toAffine(turn));
    expectNear(applyNormalMap(d, d.materials[0], centre(), {0, 0, 1}), {0, s, c}, 2e-3f);
}

TEST(SurfaceInputs, TexturesMultiplyOrReplaceTheirFactors) {
    detail::SceneData d = oneTriangle({0.5f, 0.5f, 1.0f});
    detail::Material& m = d.materials[0];
    detail::Texture colour;
    colour.image = Image(1, 1, 4, 0.5f);
    d.textures.push_back(colour);
    detail::Texture mr;
    mr.use = detail::TextureUse::Data;
    mr.image = Image(1, 1, 4, 0.0f);
    mr.image(0, 0, 1) = 0.25f;  // roughness
    mr.image(0, 0, 2) = 0.5f;   // metallic
    d.textures.push_back(mr);
    m.albedo = {0.8f, 0.4f, 0.2f};
    m.texture = 1;
    m.roughness = 0.8f;
    m.metallic = 0.6f;
    m.roughnessMetallicMap.texture = 2;
    m.textureTimesFactor = true;  // glTF
    SurfaceInputs in = evaluateInputs(d, m, centre());
    expectNear(in.albedo, {0.4f, 0.2f, 0.1f});
    EXPECT_NEAR(in.roughness, 0.2f, 1e-6f);
    EXPECT_NEAR(in.metallic, 0.3f, 1e-6f);
    m.textureTimesFactor = false;  // OBJ and JSON: the texture replaces the colour
    in = evaluateInputs(d, m, centre());
    expectNear(in.albedo, {0.5f, 0.5f, 0.5f});
    // Without texture coordinates, the factors alone.
    SurfacePoint bare = centre();
    bare.hasUv = false;
    in = evaluateInputs(d, m, bare);
    expectNear(in.albedo, m.albedo);
    EXPECT_EQ(in.roughness, 0.8f);
}

}  // namespace glint::render

namespace glint::render {
namespace {

/// A lamp quad (1 above a white floor, facing down) whose material's emission is `emission`,
/// times the texture `texel` values (2 × 1, clamped) when given; the camera looks at the floor.
Scene lampOverFloor(const test::TempDir& dir, float emission, std::vector<float> texels = {}) {
    dir.write("lamp.obj",
              "v -1 1 -1\nv 1 1 -1\nv 1 1 1\nv -1 1 1\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
              "f 1/1 3/3 2/2\nf 1/1 4/4 3/3\n");
    dir.write("floor.obj", "v -4 0 -4\nv 4 0 -4\nv 4 0 4\nv -4 0 4\nf 1 3 2\nf 1 4 3\n");
    const Scene parsed = parseScene(
        R"({"camera": {"position": [0, 0.5, 3], "lookAt": [0, 0, 0]},
            "film": {"width": 24, "height": 16},
            "materials": {"lamp": {"type": "diffuse", "albedo": [0, 0, 0],
                                   "emission": [)" +
            std::to_string(emission) + ", " + std::to_string(emission) + ", " +
            std::to_string(emission) + R"(]},
                          "floor": {"type": "diffuse", "albedo": [0.8, 0.8, 0.8]}},
            "shapes": [{"obj": "lamp.obj", "material": "lamp"},
                       {"obj": "floor.obj", "material": "floor"}]})",
        dir.path() / "scene.json");
    auto data = std::make_unique<detail::SceneData>(detail::sceneData(parsed));
    if (!texels.empty()) {
        detail::Texture t;
        t.wrapS = t.wrapT = detail::TextureWrap::Clamp;
        t.image = Image(2, 1, 4, 1.0f);
        for (int x = 0; x < 2; ++x)
            for (int c = 0; c < 3; ++c) t.image(x, 0, c) = texels[std::size_t(x)];
        data->textures.push_back(t);
        for (detail::Material& m : data->materials)
            if (m.name == "lamp") m.emissionMap.texture = int(data->textures.size()) - 1;
    }
    return Scene(std::move(data));
}

Image renderColour(Scene scene) {
    Renderer renderer(std::move(scene));
    Settings s = renderer.scene().settings();
    s.spp = 8;
    s.threads = 2;
    return renderer.render(s).frame.color();
}

}  // namespace

TEST(SurfaceInputs, AnEmissionTextureLightsAsItsColourDoesForHitsAndLightSamples) {
    // Emission 1 through a texture of 0.5 everywhere is emission 0.5: the same bits, through
    // BSDF hits (the lamp seen in a bounce) and light samples (the floor's next-event
    // estimate) alike.
    test::TempDir dir("emission");
    const Image textured = renderColour(lampOverFloor(dir, 1.0f, {0.5f, 0.5f}));
    const Image plain = renderColour(lampOverFloor(dir, 0.5f));
    for (std::size_t i = 0; i < plain.data().size(); ++i)
        ASSERT_EQ(textured.data()[i], plain.data()[i]) << i;
    // Dark where u < 0.5 (x < 0), lit where u > 0.5: the floor under the lamp's lit half is
    // brighter than under its dark half, and the picture is not mirror-symmetric any more.
    const Image half = renderColour(lampOverFloor(dir, 1.0f, {0.0f, 1.0f}));
    double left = 0.0, right = 0.0;
    for (int y = 0; y < half.height(); ++y)
        for (int x = 0; x < half.width() / 2; ++x) {
            left += half(x, y, 0);
            right += half(half.width() - 1 - x, y, 0);
        }
    EXPECT_GT(right, 1.5 * left);
}

TEST(SurfaceInputs, TheFootprintIsOnePixelsStepOnTheSurface) {
    // A 100-pixel-high film with a 40° field of view: a pixel spans `spread` radians at the
    // image centre. Each axis p + dp lies on the surface's plane, on the line of sight turned by
    // that angle, within the plane of the line of sight and the camera's right (x) or the axis
    // across both (y), for surfaces straight ahead, tilted and off to the side.
    detail::CameraDesc desc;
    desc.position = {0.5f, 1.0f, 3.0f};
    desc.lookAt = {0.5f, 1.0f, 0.0f};
    desc.fovY = 40.0f;
    const Camera camera(desc, 100, 100);
    const float spread = 2.0f * std::tan(20.0f * kPi / 180.0f) / 100.0f;
    const Vec3 right{1, 0, 0};
    const Vec3 points[] = {{0.5f, 1.0f, -2.0f}, {1.7f, 0.2f, -1.0f}, {-0.8f, 2.0f, 0.5f}};
    const Vec3 normals[] = {
        {0, 0, 1}, normalize(Vec3{0.3f, 0.2f, 1.0f}), normalize(Vec3{-0.5f, 0.1f, 0.4f})};
    for (const Vec3& p : points)
        for (const Vec3& n : normals) {
            Vec3 dpdx, dpdy;
            camera.footprintAxes(p, n, 0.0f, dpdx, dpdy);
            const Vec3 w = p - desc.position;
            for (const Vec3& dp : {dpdx, dpdy}) {
                EXPECT_NEAR(dot(n, dp), 0.0f, 1e-5f * length(dp));
                const Vec3 v = normalize(w + dp), d = normalize(w);
                EXPECT_NEAR(length(cross(v, d)) / dot(v, d), spread, 1e-3f * spread);
            }
            // x turns the line of sight towards the right, y across both.
            const Vec3 across = normalize(cross(w, right));
            EXPECT_NEAR(dot(normalize(w + dpdx), across), 0.0f, 1e-5f);
            EXPECT_NEAR(dot(normalize(w + dpdy), normalize(cross(across, w))), 0.0f, 1e-5f);
        }
    // Straight ahead on a facing plane: a step of dist × spread along the right.
    Vec3 dpdx, dpdy;
    camera.footprintAxes({0.5f, 1.0f, -2.0f}, {0, 0, 1}, 0.0f, dpdx, dpdy);
    EXPECT_NEAR(dpdx.x, 5.0f * spread, 1e-5f);
    EXPECT_NEAR(std::abs(dpdy.y), 5.0f * spread, 1e-5f);
    // A point at the camera: zero axes.
    camera.footprintAxes(desc.position, {0, 0, 1}, 0.0f, dpdx, dpdy);
    EXPECT_EQ(length(dpdx), 0.0f);
    EXPECT_EQ(length(dpdy), 0.0f);
}

TEST(SurfaceInputs, AFootprintMapsSurfaceStepsToTextureSteps) {
    // A triangle whose uv is half its (x, z) position, tilted out of the xz plane: a step in
    // the triangle's plane maps to half its x and z; a step off the plane to that of its
    // projection (least squares).
    detail::TriangleView tri;
    tri.p[0] = {0, 0, 0}, tri.p[1] = {2, 1, 0}, tri.p[2] = {0, 0, 2};
    const Vec2 uv0{0, 0}, uv1{1, 0}, uv2{0, 1};
    const Vec3 inPlane{0.2f, 0.1f, 0.06f};
    const Vec3 normal = normalize(cross(tri.p[1] - tri.p[0], tri.p[2] - tri.p[0]));
    const detail::TexFootprint fp =
        uvFootprint(tri, uv0, uv1, uv2, inPlane, inPlane + normal * 0.3f);
    EXPECT_NEAR(fp.dx.x, 0.1f, 1e-6f);
    EXPECT_NEAR(fp.dx.y, 0.03f, 1e-6f);
    EXPECT_NEAR(fp.dy.x, 0.1f, 1e-6f);
    EXPECT_NEAR(fp.dy.y, 0.03f, 1e-6f);
    // A degenerate triangle: no footprint.
    tri.p[2] = {4, 2, 0};
    const detail::TexFootprint none = uvFootprint(tri, uv0, uv1, uv2, inPlane, inPlane);
    EXPECT_EQ(none.dx.x, 0.0f);
    EXPECT_EQ(none.dy.y, 0.0f);
}

TEST(SurfaceInputs, VertexColoursMultiplyAGltfBaseColourAtTheBarycentrics) {
    detail::SceneData d = oneTriangle({0.5f, 0.5f, 1.0f});
    detail::Material& m = d.materials[0];
    m.albedo = {0.5f, 0.8f, 1.0f};
    m.textureTimesFactor = true;  // glTF
    d.meshes[0].colors = {{1, 0, 0, 1}, {0, 1, 0, 1}, {0, 0, 1, 1}};
    SurfacePoint at = centre();
    at.b1 = 0.25f, at.b2 = 0.5f;  // colour (0.25, 0.25, 0.5)
    expectNear(evaluateInputs(d, m, at).albedo, {0.125f, 0.2f, 0.5f});
    // Without texture coordinates too.
    at.hasUv = false;
    expectNear(evaluateInputs(d, m, at).albedo, {0.125f, 0.2f, 0.5f});
    // Times the base colour texture (a grey 0.5 texel).
    detail::Texture grey;
    grey.image = Image(1, 1, 4, 0.5f);
    d.textures.push_back(grey);
    m.texture = 1;
    at.hasUv = true;
    expectNear(evaluateInputs(d, m, at).albedo, {0.0625f, 0.1f, 0.25f});
}

TEST(SurfaceInputs, ASlotOnTheSecondSetReadsItsUvs) {
    // A 2 × 1 texture, black on the left and white on the right, clamped: set 0 sits on the
    // left texel, set 1 on the right one.
    detail::SceneData d = oneTriangle({0.5f, 0.5f, 1.0f});
    detail::Texture t;
    t.wrapS = t.wrapT = detail::TextureWrap::Clamp;
    t.image = Image(2, 1, 4, 1.0f);
    for (int c = 0; c < 3; ++c) t.image(0, 0, c) = 0.0f;
    d.textures.push_back(t);
    detail::Material& m = d.materials[0];
    m.albedo = {1, 1, 1};
    m.texture = 1;
    m.textureTimesFactor = true;
    SurfacePoint at = centre();
    at.uv = {0.1f, 0.5f};
    at.hasUv1 = true;
    at.uv1 = {0.9f, 0.5f};
    expectNear(evaluateInputs(d, m, at).albedo, {0, 0, 0});
    m.textureTransform.set = 1;
    expectNear(evaluateInputs(d, m, at).albedo, {1, 1, 1});
    // A mesh without the second set falls back to set 0.
    at.hasUv1 = false;
    expectNear(evaluateInputs(d, m, at).albedo, {0, 0, 0});
}

}  // namespace glint::render

// glTF 2.0 import (renderer/src/scene/gltf_import.cpp, gltf_material.cpp) on small assets written
// by the test: .gltf files with base64 data-URI buffers and .glb files built byte by byte. Node
// hierarchies (TRS and matrix), shared meshes, indexed and non-indexed primitives,
// KHR_texture_transform, cameras, punctual lights, material factors, overrides by name and the
// bare asset. Bad input is in gltf_hostile_test.cpp.

#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_fixture.h"
#include "glint/image/error.h"
#include "glint/image/io.h"
#include "glint/render/renderer.h"
#include "glint/render/scene.h"
#include "gltf_builder.h"
#include "integrators/surface_inputs.h"
#include "scene/scene_access.h"
#include "scene/scene_data.h"
#include "test_util.h"

namespace glint::render {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using namespace test_gltf;

const detail::SceneData& dataOf(const Scene& s) {
    return detail::sceneData(s);
}

/// World-space corner v of triangle prim of instance i.
Vec3 corner(const detail::SceneData& d, std::uint32_t i, std::uint32_t prim, int v) {
    return d.triangle(i, prim).p[v];
}

void expectNear(const Vec3& a, const Vec3& b, float tol = 1e-5f) {
    EXPECT_NEAR(a.x, b.x, tol);
    EXPECT_NEAR(a.y, b.y, tol);
    EXPECT_NEAR(a.z, b.z, tol);
}

TEST(GltfImport, NodeHierarchyComposesTrsMatrixAndTheShapeTransform) {
    test::TempDir dir("gltf_hierarchy");
    GltfBuilder b;
    const int mesh = b.quad();
    // child: a column-major matrix scaling by 2; parent: translate (10, 0, 0) then rotate 90°
    // about z (quaternion [0, 0, sin 45°, cos 45°]) — T · R · S order.
    const int child =
        b.node({{"mesh", mesh}, {"matrix", {2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 1}}});
    const double h = std::sqrt(0.5);
    const int parent =
        b.node({{"children", {child}}, {"translation", {10, 0, 0}}, {"rotation", {0, 0, h, h}}});
    b.scene({parent});
    dir.write("a.gltf", b.gltf());
    const fs::path scene = dir.write(
        "scene.json", sceneJson("a.gltf", "", R"(, "transform": {"translate": [0, 0, 5]})"));
    const Scene s = loadScene(scene);
    const detail::SceneData& d = dataOf(s);
    ASSERT_EQ(d.instances.size(), 1u);
    ASSERT_EQ(d.meshes.size(), 1u);
    // Local (1, 0, 0) → scaled (2, 0, 0) → rotated (0, 2, 0) → (10, 2, 0) → shape (10, 2, 5).
    expectNear(corner(d, 0, 0, 0), {10, 0, 5});
    expectNear(corner(d, 0, 0, 1), {10, 2, 5});
    expectNear(corner(d, 0, 0, 2), {8, 2, 5});
    // The normal (+z) stays +z under a rotation about z.
    expectNear(normalize(d.triangle(0, 0).n[0]), {0, 0, 1});
}

TEST(GltfImport, AMeshUsedByTwoNodesIsOneMeshWithTwoInstances) {
    test::TempDir dir("gltf_shared");
    GltfBuilder b;
    const int mesh = b.quad();
    const int a = b.node({{"mesh", mesh}, {"translation", {0, 0, 0}}});
    const int c = b.node({{"mesh", mesh}, {"translation", {3, 0, 0}}});
    b.scene({a, c});
    const fs::path asset = writeBytes(dir.path() / "shared.glb", b.glb());
    const Scene s = loadScene(dir.write("scene.json", sceneJson("shared.glb")));
    const detail::SceneData& d = dataOf(s);
    EXPECT_EQ(d.meshes.size(), 1u) << "the mesh is shared, not copied";
    ASSERT_EQ(d.instances.size(), 2u);
    EXPECT_EQ(d.instances[0].mesh, d.instances[1].mesh);
    EXPECT_EQ(s.triangleCount(), 4u);
    expectNear(corner(d, 1, 0, 1), {4, 0, 0});
    expectNear(corner(d, 0, 0, 1), {1, 0, 0});
}

TEST(GltfImport, IndexedAndNonIndexedPrimitivesGiveTheSameTriangles) {
    test::TempDir dir("gltf_indexed");
    for (bool indexed : {true, false}) {
        GltfBuilder b;
        b.scene({b.node({{"mesh", b.quad(-1, indexed)}})});
        const std::string name = indexed ? "i.gltf" : "n.gltf";
        dir.write(name, b.gltf());
        const Scene s = loadScene(dir.write("scene.json", sceneJson(name)));
        const detail::SceneData& d = dataOf(s);
        ASSERT_EQ(s.triangleCount(), 2u) << name;
        EXPECT_EQ(d.meshes[0].vertexCount(), indexed ? 4u : 6u);
        expectNear(corner(d, 0, 1, 1), {1, 1, 0});
        expectNear(corner(d, 0, 1, 2), {0, 1, 0});
        // glTF's top-left uv origin becomes Glint's bottom-left: v' = 1 − v.
        const Vec2 uv = d.meshes[0].uvs[0];
        EXPECT_FLOAT_EQ(uv.x, 0.0f);
        EXPECT_FLOAT_EQ(uv.y, 0.0f) << "glTF (0, 1) is the bottom-left corner";
    }
}

TEST(GltfImport, TriangleStripsAndFansBecomeTriangles) {
    // trimesh's mode5.gltf (strips only) loaded as "no triangle mesh" before. Strip
    // 0 1 3 2 2 (a restart at the end), fan 0 1 2 3: two counter-clockwise triangles each.
    test::TempDir dir("gltf_strips");
    for (const auto& [mode, order] : {std::pair{5, std::vector<std::uint16_t>{0, 1, 3, 2, 2}},
                                      std::pair{6, std::vector<std::uint16_t>{0, 1, 2, 3}}}) {
        GltfBuilder b;
        b.quad();
        b.doc["meshes"][0]["primitives"][0]["mode"] = mode;
        b.doc["meshes"][0]["primitives"][0]["indices"] = b.u16(order);
        b.scene({b.node({{"mesh", 0}})});
        dir.write("s.gltf", b.gltf());
        const Scene s = loadScene(dir.write("scene.json", sceneJson("s.gltf")));
        ASSERT_EQ(s.triangleCount(), 2u) << "mode " << mode;
        for (std::uint32_t t = 0; t < 2; ++t) {
            const detail::TriangleView tri = dataOf(s).triangle(0, t);
            EXPECT_NEAR(cross(tri.p[1] - tri.p[0], tri.p[2] - tri.p[0]).z, 1.0f, 1e-6f)
                << mode << t;
        }
    }
}

/// A 2×2 RGBA PNG: red, green / blue, white (top row first).
std::vector<unsigned char> smallPng(const fs::path& dir) {
    Image im(2, 2, 4, 1.0f);
    const float colours[4][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}};
    for (int i = 0; i < 4; ++i)
        for (int c = 0; c < 3; ++c) im(i % 2, i / 2, c) = colours[i][c];
    writeImage(im, dir / "tex.png");
    std::ifstream in(dir / "tex.png", std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST(GltfImport, TexturesFromFilesBufferViewsAndDataUrisWithTextureTransform) {
    test::TempDir dir("gltf_textures");
    const std::vector<unsigned char> png = smallPng(dir.path());
    GltfBuilder b;
    b.doc["images"] = json::array();
    b.doc["images"].push_back({{"uri", "tex.png"}});  // a file beside the asset
    b.doc["images"].push_back(
        {{"bufferView", b.view(png.data(), png.size())}, {"mimeType", "image/png"}});
    b.doc["images"].push_back({{"uri", "data:image/png;base64," + base64(png)}});
    b.doc["samplers"] = json::array({{{"wrapS", 33071}, {"wrapT", 33648}, {"magFilter", 9728}}});
    b.doc["textures"] =
        json::array({{{"source", 0}, {"sampler", 0}}, {{"source", 1}}, {{"source", 2}}});
    const double rotation = 0.3;
    b.doc["materials"] = json::array(
        {{{"name", "textured"},
          {"pbrMetallicRoughness",
           {{"baseColorTexture",
             {{"index", 0},
              {"extensions",
               {{"KHR_texture_transform",
                 {{"offset", {0.25, 0.5}}, {"rotation", rotation}, {"scale", {2, 3}}}}}}}},
            {"metallicRoughnessTexture", {{"index", 1}}}}},
          {"emissiveTexture", {{"index", 2}}},
          {"emissiveFactor", {1, 1, 1}}}});
    b.doc["extensionsUsed"] = {"KHR_texture_transform"};
    b.scene({b.node({{"mesh", b.quad(0)}})});
    dir.write("t.gltf", b.gltf());
    const Scene s = loadScene(dir.write("scene.json", sceneJson("t.gltf")));
    const detail::SceneData& d = dataOf(s);
    ASSERT_EQ(d.textures.size(), 3u);
    const detail::Material& m = d.materials[d.meshes[0].materials[0]];
    EXPECT_EQ(m.type, detail::MaterialType::MetallicRoughness);
    ASSERT_GE(m.texture, 0);
    const detail::Texture& base = d.textures[std::size_t(m.texture)];
    EXPECT_EQ(base.path, dir.path() / "tex.png");
    EXPECT_EQ(base.use, detail::TextureUse::Color);
    EXPECT_EQ(base.wrapS, detail::TextureWrap::Clamp);
    EXPECT_EQ(base.wrapT, detail::TextureWrap::Mirror);
    // NEAREST (pixel art: computermouth/gltf-test's manuvmapshapekey.gltf) is named, not read.
    ASSERT_EQ(s.warnings().size(), 1u);
    EXPECT_NE(s.warnings()[0].find("samplers[0].magFilter is NEAREST"), std::string::npos);
    ASSERT_TRUE(m.roughnessMetallicMap.present());
    EXPECT_EQ(d.textures[std::size_t(m.roughnessMetallicMap.texture)].use,
              detail::TextureUse::Data);
    EXPECT_TRUE(d.textures[std::size_t(m.roughnessMetallicMap.texture)].bytes != nullptr);
    ASSERT_TRUE(m.emissionMap.present());
    EXPECT_EQ(d.textures[std::size_t(m.emissionMap.texture)].image.width(), 2);
    // The top-left texel is red in every copy (glTF's and Glint's origins agree on the image).
    const Vec4 topLeft = d.textures[std::size_t(m.emissionMap.texture)].lookup({0.25f, 0.75f});
    EXPECT_GT(topLeft.x, 0.9f);
    EXPECT_LT(topLeft.y, 0.1f);

    // KHR_texture_transform in glTF's space: uv' = T R S uv, R = [[c, s], [−s, c]]; Glint's
    // transform must give the same lookup point through the flip v ↦ 1 − v.
    ASSERT_FALSE(m.textureTransform.identity);
    for (const Vec2 g : {Vec2{0.1f, 0.2f}, Vec2{0.7f, 0.4f}, Vec2{1.5f, -0.3f}}) {
        const float c = std::cos(float(rotation)), sn = std::sin(float(rotation));
        const float su = 2.0f * g.x, sv = 3.0f * g.y;
        const Vec2 gltfOut{c * su + sn * sv + 0.25f, -sn * su + c * sv + 0.5f};
        const Vec2 glint = m.textureTransform.apply({g.x, 1.0f - g.y});
        EXPECT_NEAR(glint.x, gltfOut.x, 1e-5f);
        EXPECT_NEAR(glint.y, 1.0f - gltfOut.y, 1e-5f);
    }
    EXPECT_TRUE(m.roughnessMetallicMap.transform.identity);
}

TEST(GltfImport, MaterialFactorsExtensionsAndTheDefaultMaterial) {
    test::TempDir dir("gltf_materials");
    GltfBuilder b;
    b.doc["materials"] =
        json::array({{{"name", "paint"},
                      {"pbrMetallicRoughness",
                       {{"baseColorFactor", {0.5, 0.25, 0.125, 0.75}},
                        {"metallicFactor", 0.0},
                        {"roughnessFactor", 0.3}}},
                      {"emissiveFactor", {0.5, 1.0, 0.0}},
                      {"alphaMode", "MASK"},
                      {"alphaCutoff", 0.4},
                      {"doubleSided", true},
                      {"extensions",
                       {{"KHR_materials_emissive_strength", {{"emissiveStrength", 4.0}}},
                        {"KHR_materials_ior", {{"ior", 1.33}}},
                        {"KHR_materials_transmission", {{"transmissionFactor", 0.6}}}}}}});
    b.doc["extensionsUsed"] = {"KHR_materials_emissive_strength", "KHR_materials_ior",
                               "KHR_materials_transmission"};
    const int painted = b.quad(0);
    const int plain = b.quad(-1);
    b.scene({b.node({{"mesh", painted}}), b.node({{"mesh", plain}, {"translation", {2, 0, 0}}})});
    dir.write("m.gltf", b.gltf());
    const Scene s = loadScene(dir.write("scene.json", sceneJson("m.gltf")));
    const detail::SceneData& d = dataOf(s);
    // Transmission is rendered now: no warning.
    EXPECT_TRUE(s.warnings().empty()) << s.warnings()[0];
    const detail::Material& m = d.materials[d.meshes[0].materials[0]];
    EXPECT_EQ(m.name, "paint");
    EXPECT_EQ(m.type, detail::MaterialType::MetallicRoughness);
    expectNear(m.albedo, {0.5f, 0.25f, 0.125f});
    EXPECT_FLOAT_EQ(m.opacity, 0.75f);
    EXPECT_FLOAT_EQ(m.metallic, 0.0f);
    EXPECT_FLOAT_EQ(m.roughness, 0.3f);
    expectNear(m.emission, {2.0f, 4.0f, 0.0f});
    EXPECT_FLOAT_EQ(m.ior, 1.33f);
    EXPECT_FLOAT_EQ(m.transmission, 0.6f);
    EXPECT_EQ(m.alphaMode, detail::AlphaMode::Mask);
    EXPECT_FLOAT_EQ(m.alphaCutoff, 0.4f);
    EXPECT_TRUE(m.textureTimesFactor);
    // A primitive without a material: white, metallic 1, roughness 1 (glTF 2.0, 3.9.6).
    const detail::Material& def = d.materials[d.meshes[1].materials[0]];
    expectNear(def.albedo, {1, 1, 1});
    EXPECT_FLOAT_EQ(def.metallic, 1.0f);
    EXPECT_FLOAT_EQ(def.roughness, 1.0f);
    EXPECT_EQ(s.areaLightCount(), 2u) << "the emissive quad's two triangles";
}

TEST(GltfImport, JsonMaterialsOverrideByNameAndThroughTheShapesMap) {
    test::TempDir dir("gltf_override");
    GltfBuilder b;
    b.doc["materials"] = json::array({{{"name", "body"}}, {{"name", "glass"}}});
    b.scene(
        {b.node({{"mesh", b.quad(0)}}), b.node({{"mesh", b.quad(1)}, {"translation", {2, 0, 0}}})});
    dir.write("o.gltf", b.gltf());
    const std::string materials =
        R"(, "materials": {"glass": {"type": "dielectric", "ior": 1.5},
                           "red": {"type": "diffuse", "albedo": [1, 0, 0]}})";
    const Scene s = loadScene(dir.write(
        "scene.json", sceneJson("o.gltf", materials, R"(, "materials": {"body": "red"})")));
    const detail::SceneData& d = dataOf(s);
    EXPECT_EQ(d.materials[d.meshes[0].materials[0]].name, "red");
    EXPECT_EQ(d.materials[d.meshes[1].materials[0]].type, detail::MaterialType::Dielectric);
    // A name the asset lacks is an error at its JSON place, not silently ignored.
    try {
        loadScene(dir.write("bad.json",
                            sceneJson("o.gltf", materials, R"(, "materials": {"bodi": "red"})")));
        ADD_FAILURE() << "a misspelt material name was accepted";
    } catch (const Error& e) {
        EXPECT_EQ(e.where(), "/shapes/0/materials/bodi");
        EXPECT_NE(e.message().find("body"), std::string::npos) << e.what();
    }
}

TEST(GltfImport, CamerasAndTheFirstIsUsedWithoutACameraBlock) {
    test::TempDir dir("gltf_camera");
    GltfBuilder b;
    b.doc["cameras"] =
        json::array({{{"type", "perspective"},
                      {"perspective", {{"yfov", 0.5}, {"znear", 0.1}, {"aspectRatio", 2.0}}}},
                     {{"type", "orthographic"},
                      {"orthographic", {{"xmag", 1}, {"ymag", 1}, {"znear", 0.1}, {"zfar", 10}}}},
                     {{"type", "perspective"},
                      {"name", "side"},
                      {"perspective", {{"yfov", 1.0}, {"znear", 0.1}}}}});
    const double h = std::sqrt(0.5);
    // "front" at (0, 0, 5) looking down −z; "side" at (5, 0, 0) turned 90° about y: looks down −x.
    b.scene({b.node({{"mesh", b.quad()}}),
             b.node({{"name", "front"}, {"camera", 0}, {"translation", {0, 0, 5}}}),
             b.node({{"camera", 1}}),
             b.node({{"camera", 2}, {"translation", {5, 0, 0}}, {"rotation", {0, h, 0, h}}})});
    dir.write("c.gltf", b.gltf());
    Scene s = loadScene(dir.write("scene.json", sceneJson("c.gltf")));
    const detail::SceneData& d = dataOf(s);
    ASSERT_EQ(d.assetCameras.size(), 2u) << "the orthographic camera is skipped";
    EXPECT_EQ(s.assetCameraNames(), (std::vector<std::string>{"front", "side"}));
    ASSERT_EQ(s.warnings().size(), 1u);
    EXPECT_NE(s.warnings()[0].find("orthographic"), std::string::npos) << s.warnings()[0];
    expectNear(d.camera.position, {0, 0, 5});
    expectNear(normalize(d.camera.lookAt - d.camera.position), {0, 0, -1});
    expectNear(d.camera.up, {0, 1, 0});
    EXPECT_NEAR(d.camera.fovY, 0.5 * 180.0 / 3.14159265358979, 1e-4);
    EXPECT_FLOAT_EQ(d.assetCameras[0].aspectRatio, 2.0f);
    s.useAssetCamera("side");
    expectNear(d.camera.position, {5, 0, 0});
    expectNear(normalize(d.camera.lookAt - d.camera.position), {-1, 0, 0});
    EXPECT_THROW(s.useAssetCamera("nope"), Error);
    // A camera block wins over the asset's.
    const Scene withCamera = loadScene(dir.write(
        "cam.json",
        sceneJson("c.gltf",
                  R"(, "camera": {"position": [0, 9, 0], "lookAt": [0, 0, 0], "up": [0, 0, 1]})")));
    expectNear(dataOf(withCamera).camera.position, {0, 9, 0});
}

TEST(GltfImport, PunctualLightsInRadiometricUnits) {
    test::TempDir dir("gltf_lights");
    GltfBuilder b;
    b.doc["extensionsUsed"] = {"KHR_lights_punctual"};
    b.doc["extensions"]["KHR_lights_punctual"]["lights"] = json::array(
        {{{"type", "point"}, {"color", {1, 0.5, 0}}, {"intensity", 683}, {"name", "bulb"}},
         {{"type", "spot"},
          {"intensity", 1366},
          {"spot", {{"innerConeAngle", 0.2}, {"outerConeAngle", 0.5}}}},
         {{"type", "directional"}, {"intensity", 6.83}}});
    const double h = std::sqrt(0.5);
    b.scene({b.node({{"mesh", b.quad()}}),
             b.node({{"translation", {1, 2, 3}},
                     {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}}),
             b.node({{"translation", {0, 4, 0}},
                     {"rotation", {-h, 0, 0, h}},  // −90° about x: −z → −y
                     {"extensions", {{"KHR_lights_punctual", {{"light", 1}}}}}}),
             b.node({{"extensions", {{"KHR_lights_punctual", {{"light", 2}}}}}})});
    dir.write("l.gltf", b.gltf());
    const Scene s = loadScene(dir.write("scene.json", sceneJson("l.gltf")));
    const auto& lights = dataOf(s).punctualLights;
    ASSERT_EQ(lights.size(), 3u);
    EXPECT_EQ(lights[0].kind, detail::PunctualLight::Kind::Point);
    EXPECT_EQ(lights[0].name, "bulb");
    expectNear(lights[0].position, {1, 2, 3});
    expectNear(lights[0].intensity, {1.0f, 0.5f, 0.0f});  // 683 cd = 1 W/sr
    EXPECT_EQ(lights[1].kind, detail::PunctualLight::Kind::Spot);
    expectNear(lights[1].position, {0, 4, 0});
    expectNear(lights[1].direction, {0, -1, 0});
    expectNear(lights[1].intensity, {2, 2, 2});
    EXPECT_NEAR(lights[1].cosInner, std::cos(0.2), 1e-6);
    EXPECT_NEAR(lights[1].cosOuter, std::cos(0.5), 1e-6);
    EXPECT_EQ(lights[2].kind, detail::PunctualLight::Kind::Directional);
    expectNear(lights[2].direction, {0, 0, -1});
    expectNear(lights[2].intensity, {0.01f, 0.01f, 0.01f});  // 6.83 lux = 0.01 W/m²
}

TEST(GltfImport, TangentsAreGeneratedForNormalMappedMaterialsOnly) {
    test::TempDir dir("gltf_tangents");
    const std::vector<unsigned char> png = smallPng(dir.path());
    GltfBuilder b;
    b.doc["images"] = json::array({{{"uri", "tex.png"}}});
    b.doc["textures"] = json::array({{{"source", 0}}});
    b.doc["materials"] =
        json::array({{{"normalTexture", {{"index", 0}, {"scale", 0.5}}}}, json::object()});
    b.scene(
        {b.node({{"mesh", b.quad(0)}}), b.node({{"mesh", b.quad(1)}, {"translation", {2, 0, 0}}})});
    dir.write("n.gltf", b.gltf());
    const Scene s = loadScene(dir.write("scene.json", sceneJson("n.gltf")));
    const detail::SceneData& d = dataOf(s);
    const detail::Material& m = d.materials[d.meshes[0].materials[0]];
    ASSERT_TRUE(m.normalMap.present());
    EXPECT_EQ(d.textures[std::size_t(m.normalMap.texture)].use, detail::TextureUse::Data);
    EXPECT_FLOAT_EQ(m.normalScale, 0.5f);
    ASSERT_EQ(d.meshes[0].tangents.size(), d.meshes[0].vertexCount());
    // +u runs along +x; the bitangent w · (n × t) along +v, which (Glint's v up) is +y.
    const Vec4 t = d.meshes[0].tangents[0];
    expectNear({t.x, t.y, t.z}, {1, 0, 0});
    EXPECT_FLOAT_EQ(t.w, 1.0f);
    EXPECT_TRUE(d.meshes[1].tangents.empty()) << "no normal map, no tangents";
}

TEST(GltfImport, GeneratedTangentsOfAMirroredUvLayoutAreLeftHanded) {
    // What Khronos' NormalTangentMirrorTest checks (not found in a fetchable repository): a
    // mesh whose uvs are mirrored in u gets tangents along −x, and w = −1 keeps the bitangent
    // w · (n × t) along +v (+y), so the normal map is not inverted across the mirror.
    test::TempDir dir("gltf_mirror");
    smallPng(dir.path());
    GltfBuilder b;
    b.doc["images"] = json::array({{{"uri", "tex.png"}}});
    b.doc["textures"] = json::array({{{"source", 0}}});
    b.doc["materials"] = json::array({{{"normalTexture", {{"index", 0}}}}});
    const int mesh = b.quad(0);
    // The quad's TEXCOORD_0 is accessor 2 (POSITION, NORMAL, TEXCOORD_0): mirror u in place.
    const json& uvAccessor = b.doc["accessors"][2];
    const std::size_t at = b.doc["bufferViews"][int(uvAccessor["bufferView"])]["byteOffset"];
    float* uv = reinterpret_cast<float*>(b.bin.data() + at);
    for (int v = 0; v < 4; ++v) uv[2 * v] = 1.0f - uv[2 * v];
    b.scene({b.node({{"mesh", mesh}})});
    dir.write("m.gltf", b.gltf());
    const Scene s = loadScene(dir.write("scene.json", sceneJson("m.gltf")));
    const detail::SceneData& d = dataOf(s);
    ASSERT_EQ(d.meshes[0].tangents.size(), 4u);
    for (const Vec4& t : d.meshes[0].tangents) {
        expectNear({t.x, t.y, t.z}, {-1, 0, 0});
        EXPECT_FLOAT_EQ(t.w, -1.0f);
    }
}

TEST(GltfImport, TransmissionTextureMultipliesTheFactorByItsRedChannel) {
    test::TempDir dir("gltf_transmission");
    smallPng(dir.path());
    GltfBuilder b;
    b.doc["images"] = json::array({{{"uri", "tex.png"}}});
    b.doc["textures"] = json::array({{{"source", 0}}});
    b.doc["materials"] = json::array(
        {{{"name", "glass"},
          {"pbrMetallicRoughness", {{"metallicFactor", 0.0}, {"roughnessFactor", 0.2}}},
          {"extensions",
           {{"KHR_materials_transmission",
             {{"transmissionFactor", 0.8}, {"transmissionTexture", {{"index", 0}}}}}}}}});
    b.doc["extensionsUsed"] = {"KHR_materials_transmission"};
    b.scene({b.node({{"mesh", b.quad(0)}})});
    dir.write("g.gltf", b.gltf());
    const Scene s = loadScene(dir.write("scene.json", sceneJson("g.gltf")));
    EXPECT_TRUE(s.warnings().empty()) << s.warnings()[0];
    const detail::SceneData& d = dataOf(s);
    const detail::Material& m = d.materials[d.meshes[0].materials[0]];
    EXPECT_FLOAT_EQ(m.transmission, 0.8f);
    ASSERT_TRUE(m.transmissionMap.present());
    // Data, not colour: the texel's R is used as stored.
    EXPECT_EQ(d.textures[std::size_t(m.transmissionMap.texture)].use, detail::TextureUse::Data);
    // At the top-left (red) texel R = 1 keeps the factor; at the top-right (green) one R = 0.
    SurfacePoint at;
    at.id = {0, 0};
    at.hasUv = true;
    at.uv = {0.25f, 0.75f};
    EXPECT_NEAR(evaluateInputs(d, m, at).transmission, 0.8f, 1e-6f);
    at.uv = {0.75f, 0.75f};
    EXPECT_NEAR(evaluateInputs(d, m, at).transmission, 0.0f, 1e-6f);
    // A malformed texture reference is an error, with its place.
    b.doc["materials"][0]["extensions"]["KHR_materials_transmission"]["transmissionTexture"] = {
        {"index", 0.5}};
    dir.write("g.gltf", b.gltf());
    try {
        loadScene(dir.write("scene.json", sceneJson("g.gltf")));
        ADD_FAILURE() << "a fractional texture index was accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("transmissionTexture.index"), std::string::npos)
            << e.what();
    }
}

TEST(GltfImport, UnreadExtensionsWarnOnce) {
    test::TempDir dir("gltf_ext");
    GltfBuilder b;
    b.doc["extensionsUsed"] = {"KHR_materials_clearcoat", "KHR_texture_transform"};
    b.scene({b.node({{"mesh", b.quad()}})});
    dir.write("e.gltf", b.gltf());
    const Scene s = loadScene(dir.write("scene.json", sceneJson("e.gltf")));
    ASSERT_EQ(s.warnings().size(), 1u);
    EXPECT_NE(s.warnings()[0].find("KHR_materials_clearcoat"), std::string::npos);
    EXPECT_NE(s.warnings()[0].find("e.gltf"), std::string::npos);
}

TEST(GltfImport, ABareAssetGetsAFramingCameraNeutralLightAndRenders) {
    test::TempDir dir("gltf_bare");
    GltfBuilder b;
    b.doc["materials"] =
        json::array({{{"pbrMetallicRoughness",
                       {{"baseColorFactor", {0.8, 0.6, 0.4, 1}}, {"metallicFactor", 0}}}}});
    b.scene({b.node({{"mesh", b.quad(0)}, {"translation", {-0.5, -0.5, 0}}})});
    const fs::path asset = writeBytes(dir.path() / "bare.glb", b.glb());
    Scene s = loadScene(asset);
    const detail::SceneData& d = dataOf(s);
    EXPECT_EQ(s.width(), 640);
    EXPECT_EQ(s.height(), 480);
    EXPECT_TRUE(s.hasEnvironment()) << "no light in the asset: a neutral environment";
    expectNear(d.camera.lookAt, {0, 0, 0});
    EXPECT_GT(d.camera.position.z, 1.0f);
    EXPECT_FLOAT_EQ(d.camera.fovY, 40.0f);
    // The source JSON describes the same scene.
    const json src = json::parse(d.sourceJson);
    EXPECT_EQ(src["shapes"][0]["gltf"], "bare.glb");

    Renderer renderer(std::move(s));
    Settings settings;
    settings.spp = 2;
    const FrameBuffers frame = renderer.render(settings).frame;
    double sum = 0.0, centre = 0.0;
    const Image& colour = frame.color();
    for (int y = 0; y < colour.height(); ++y)
        for (int x = 0; x < colour.width(); ++x)
            for (int c = 0; c < 3; ++c) {
                ASSERT_TRUE(std::isfinite(colour(x, y, c)));
                sum += colour(x, y, c);
            }
    for (int c = 0; c < 3; ++c) centre += colour(320, 240, c);
    EXPECT_GT(sum, 0.0);
    // The quad (albedo < 1) in front of the white environment: darker than the background.
    EXPECT_GT(centre, 0.0);
    EXPECT_LT(centre, colour(5, 5, 0) + colour(5, 5, 1) + colour(5, 5, 2));
}

TEST(GltfImport, ABareAssetWithEmissiveDetailsButNoLampsStillGetsTheEnvironment) {
    // Real assets (the Damaged Helmet) glow in places without lamps: they were rendered black
    // but for the glow. Only punctual lights stand for the asset's own lighting.
    test::TempDir dir("gltf_bare_emissive");
    GltfBuilder b;
    b.doc["materials"] = json::array({{{"emissiveFactor", {1, 0.5, 0}}}});
    b.scene({b.node({{"mesh", b.quad(0)}})});
    EXPECT_TRUE(loadScene(writeBytes(dir.path() / "glow.glb", b.glb())).hasEnvironment());
    b.doc["extensionsUsed"] = {"KHR_lights_punctual"};
    b.doc["extensions"] = {
        {"KHR_lights_punctual", {{"lights", {{{"type", "point"}, {"intensity", 10}}}}}}};
    b.doc["nodes"].push_back(
        {{"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}, {"translation", {0, 0, 2}}});
    b.doc["scenes"][0]["nodes"].push_back(1);
    EXPECT_FALSE(loadScene(writeBytes(dir.path() / "lamp.glb", b.glb())).hasEnvironment());
}

TEST(GltfImport, ABlenderExportLoadsAsBlenderBuiltIt) {
    // scenes/assets/blender_scene.glb: written by Blender 3.4's glTF exporter
    // (scenes/assets/blender_export.py).
    const Scene s = loadScene(fs::path(GLINT_SOURCE_DIR) / "scenes/assets/blender_scene.glb");
    const detail::SceneData& d = dataOf(s);
    EXPECT_TRUE(s.warnings().empty()) << s.warnings().front();
    EXPECT_EQ(d.meshes.size(), 4u) << "ground, sphere (used twice), cube, lamp panel";
    EXPECT_EQ(d.instances.size(), 5u);
    ASSERT_EQ(d.assetCameras.size(), 1u);
    EXPECT_EQ(d.assetCameras[0].name, "main_camera");
    EXPECT_EQ(s.width(), 640);
    EXPECT_EQ(s.height(), 480) << "the camera's aspect ratio, 4:3";
    // Blender's +z up becomes glTF's +y up: the camera at Blender (0, −7, 3.5) is at (0, 3.5, 7).
    expectNear(d.camera.position, {0.0f, 3.5f, 7.0f}, 1e-4f);
    ASSERT_EQ(d.punctualLights.size(), 2u);
    // A 500 W Blender point light: 500 / 4π W/sr.
    EXPECT_NEAR(d.punctualLights[0].intensity.x, 500.0 / (4.0 * 3.14159265358979), 1e-3);
    EXPECT_EQ(d.punctualLights[1].kind, detail::PunctualLight::Kind::Directional);
    EXPECT_NEAR(d.punctualLights[1].intensity.x, 2.0, 1e-5);
    EXPECT_FALSE(s.hasEnvironment()) << "the asset brings lights";
    bool gold = false, lamp = false, textured = false;
    for (const detail::Material& m : d.materials) {
        gold = gold || (m.name == "gold" && m.metallic == 1.0f);
        lamp = lamp || (m.name == "lamp_panel" && std::abs(m.emission.x - 5.0f) < 1e-4f);
        textured = textured || (m.name == "checker_paint" && m.texture >= 0);
    }
    EXPECT_TRUE(gold && lamp && textured);
}

TEST(GltfImport, TheKhronosDuckFromElsewhereRendersWithItsCameraAndTexture) {
    // scenes/assets/duck/Duck.glb: the Khronos sample Duck as three.js's exporter wrote it (no
    // Glint or Blender tool touched it): a camera under a node scaled by 0.01, an embedded PNG.
    const Scene s = loadScene(fs::path(GLINT_SOURCE_DIR) / "scenes/assets/duck/Duck.glb");
    const detail::SceneData& d = dataOf(s);
    EXPECT_TRUE(s.warnings().empty()) << s.warnings().front();
    EXPECT_EQ(d.meshes.size(), 1u);
    EXPECT_EQ(d.triangleCount(), 4212u);
    ASSERT_EQ(d.assetCameras.size(), 1u);
    EXPECT_EQ(s.width(), 640);
    EXPECT_EQ(s.height(), 427) << "the camera's aspect ratio, 1.5";
    ASSERT_EQ(d.materials.size(), 1u);
    EXPECT_GE(d.materials[0].texture, 0);
    EXPECT_TRUE(s.hasEnvironment()) << "no lights: the white sky of a bare asset";
    Renderer renderer(loadScene(fs::path(GLINT_SOURCE_DIR) / "scenes/assets/duck/Duck.glb"));
    Settings settings = renderer.scene().settings();
    settings.spp = 2;
    settings.threads = 2;
    const Image c = renderer.render(settings).frame.color();
    // The duck's body, yellow, in the middle of the frame where Cycles shows it too
    // (docs/assets.md); the sky, white, in the corner.
    double r = 0, g = 0, b = 0;
    for (int y = 170; y < 190; ++y)
        for (int x = 300; x < 320; ++x) r += c(x, y, 0), g += c(x, y, 1), b += c(x, y, 2);
    EXPECT_GT(r / 400, 0.3);
    EXPECT_GT(g / 400, 0.2);
    EXPECT_LT(b, 0.3 * r) << "yellow";
    EXPECT_EQ(c(5, 5, 0), 1.0f);
}

}  // namespace
}  // namespace glint::render

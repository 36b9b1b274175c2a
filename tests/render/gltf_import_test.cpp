// glTF 2.0 import (renderer/src/scene/gltf_import.cpp, gltf_material.cpp) on small assets written
// by the test: .gltf files with base64 data-URI buffers and .glb files built byte by byte. Node
// hierarchies (TRS and matrix), shared meshes, indexed and non-indexed primitives,
// KHR_texture_transform, cameras, punctual lights, material factors, overrides by name, the bare
// asset, and bad input through loadScene and through glint-render.

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
#include "integrators/surface_inputs.h"
#include "scene/scene_data.h"
#include "test_util.h"

namespace glint::render {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

std::string base64(const std::vector<unsigned char>& bytes) {
    static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (std::size_t i = 0; i < bytes.size(); i += 3) {
        const std::uint32_t n = std::uint32_t(bytes[i]) << 16 |
                                (i + 1 < bytes.size() ? std::uint32_t(bytes[i + 1]) << 8 : 0u) |
                                (i + 2 < bytes.size() ? std::uint32_t(bytes[i + 2]) : 0u);
        out += table[(n >> 18) & 63];
        out += table[(n >> 12) & 63];
        out += i + 1 < bytes.size() ? table[(n >> 6) & 63] : '=';
        out += i + 2 < bytes.size() ? table[n & 63] : '=';
    }
    return out;
}

/// Builds a glTF document and its one binary buffer.
class GltfBuilder {
  public:
    json doc = {{"asset", {{"version", "2.0"}}}};
    std::vector<unsigned char> bin;

    /// A bufferView over `bytes` appended to the buffer (4-byte aligned).
    int view(const void* data, std::size_t bytes) {
        while (bin.size() % 4) bin.push_back(0);
        const std::size_t offset = bin.size();
        const auto* p = static_cast<const unsigned char*>(data);
        bin.insert(bin.end(), p, p + bytes);
        doc["bufferViews"].push_back(
            {{"buffer", 0}, {"byteOffset", offset}, {"byteLength", bytes}});
        return int(doc["bufferViews"].size()) - 1;
    }
    int accessor(int view, int componentType, const char* type, std::size_t count) {
        doc["accessors"].push_back({{"bufferView", view},
                                    {"componentType", componentType},
                                    {"type", type},
                                    {"count", count}});
        return int(doc["accessors"].size()) - 1;
    }
    int floats(const std::vector<float>& v, const char* type, int components) {
        return accessor(view(v.data(), v.size() * 4), 5126, type,
                        v.size() / std::size_t(components));
    }
    int u16(const std::vector<std::uint16_t>& v) {
        return accessor(view(v.data(), v.size() * 2), 5123, "SCALAR", v.size());
    }
    /// A unit quad in z = 0 facing +z (two triangles), with normals and glTF uvs (top-left
    /// origin); indexed or not. Returns the mesh index.
    int quad(int material = -1, bool indexed = true, const std::string& name = "quad") {
        std::vector<float> p = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
        std::vector<float> n = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
        std::vector<float> uv = {0, 1, 1, 1, 1, 0, 0, 0};
        const std::vector<int> order = {0, 1, 2, 0, 2, 3};
        if (!indexed) {
            std::vector<float> p2, n2, uv2;
            for (int i : order) {
                for (int c = 0; c < 3; ++c) p2.push_back(p[std::size_t(3 * i + c)]);
                for (int c = 0; c < 3; ++c) n2.push_back(n[std::size_t(3 * i + c)]);
                for (int c = 0; c < 2; ++c) uv2.push_back(uv[std::size_t(2 * i + c)]);
            }
            p = p2, n = n2, uv = uv2;
        }
        json prim = {{"attributes",
                      {{"POSITION", floats(p, "VEC3", 3)},
                       {"NORMAL", floats(n, "VEC3", 3)},
                       {"TEXCOORD_0", floats(uv, "VEC2", 2)}}}};
        if (indexed) prim["indices"] = u16({0, 1, 2, 0, 2, 3});
        if (material >= 0) prim["material"] = material;
        doc["meshes"].push_back({{"name", name}, {"primitives", json::array({prim})}});
        return int(doc["meshes"].size()) - 1;
    }
    int node(json n) {
        doc["nodes"].push_back(std::move(n));
        return int(doc["nodes"].size()) - 1;
    }
    /// The scene of the given root nodes.
    void scene(const std::vector<int>& roots) {
        doc["scenes"] = json::array({{{"nodes", roots}}});
        doc["scene"] = 0;
    }

    /// The .gltf text with the buffer as a base64 data URI.
    std::string gltf() const {
        json d = doc;
        d["buffers"] =
            json::array({{{"byteLength", bin.size()},
                          {"uri", "data:application/octet-stream;base64," + base64(bin)}}});
        return d.dump();
    }
    /// The .glb bytes (JSON chunk, then BIN chunk).
    std::vector<unsigned char> glb() const {
        json d = doc;
        d["buffers"] = json::array({{{"byteLength", bin.size()}}});
        std::string text = d.dump();
        while (text.size() % 4) text += ' ';
        std::vector<unsigned char> data = bin;
        while (data.size() % 4) data.push_back(0);
        std::vector<unsigned char> out;
        auto u32 = [&](std::uint32_t v) {
            for (int i = 0; i < 4; ++i) out.push_back((unsigned char)(v >> (8 * i)));
        };
        u32(0x46546C67), u32(2), u32(std::uint32_t(12 + 8 + text.size() + 8 + data.size()));
        u32(std::uint32_t(text.size())), u32(0x4E4F534A);
        out.insert(out.end(), text.begin(), text.end());
        u32(std::uint32_t(data.size())), u32(0x004E4942);
        out.insert(out.end(), data.begin(), data.end());
        return out;
    }
};

fs::path writeBytes(const fs::path& path, const std::vector<unsigned char>& bytes) {
    std::ofstream(path, std::ios::binary)
        .write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
    return path;
}

/// A scene.json placing `asset` (no camera block unless given).
std::string sceneJson(const std::string& asset, const std::string& extra = "",
                      const std::string& shapeExtra = "") {
    return R"({"film": {"width": 8, "height": 6}, "environment": {"color": [1, 1, 1]},
               "shapes": [{"gltf": ")" +
           asset + "\"" + shapeExtra + "}]" + extra + "}";
}

const detail::SceneData& dataOf(const Scene& s) {
    return s.data();
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
    b.doc["samplers"] = json::array({{{"wrapS", 33071}, {"wrapT", 33648}}});
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

// ---------------------------------------------------------------------------------------------
// Bad input: one glint::Error naming the asset and the glTF place, on one line.

struct BadAsset {
    std::string name;   ///< file name (its extension chooses .gltf text or .glb bytes)
    std::string place;  ///< expected in Error::where()
    std::vector<unsigned char> bytes;
};

std::vector<unsigned char> text(const std::string& s) {
    return {s.begin(), s.end()};
}

std::vector<BadAsset> badAssets() {
    std::vector<BadAsset> cases;
    auto good = [] {
        GltfBuilder b;
        b.scene({b.node({{"mesh", b.quad()}})});
        return b;
    };
    {
        std::vector<unsigned char> glb = good().glb();
        glb.resize(glb.size() / 2);
        cases.push_back({"truncated.glb", "header", glb});
    }
    {
        std::vector<unsigned char> glb = good().glb();
        glb[3] = 'X';
        cases.push_back({"magic.glb", "byte 0", glb});
    }
    {
        GltfBuilder b = good();
        b.doc["accessors"][0]["count"] = 1000;  // POSITION past its bufferView
        cases.push_back({"accessor.gltf", "accessors[0]", text(b.gltf())});
    }
    {
        GltfBuilder b = good();
        b.doc["bufferViews"][0]["byteLength"] = 100000;  // past the end of the buffer
        cases.push_back({"buffer.glb", "bufferViews[0]", b.glb()});
    }
    {
        GltfBuilder b;
        const int p = b.floats({0, 0, 0, 1, 0, 0, 0, 1, 0}, "VEC3", 3);
        const int i = b.u16({0, 1, 7});
        b.doc["meshes"] =
            json::array({{{"primitives", {{{"attributes", {{"POSITION", p}}}, {"indices", i}}}}}});
        b.scene({b.node({{"mesh", 0}})});
        cases.push_back({"index.gltf", "accessors[1]", text(b.gltf())});
    }
    {
        GltfBuilder b;
        const float nan = std::numeric_limits<float>::quiet_NaN();
        const int p = b.floats({0, 0, 0, 1, nan, 0, 0, 1, 0}, "VEC3", 3);
        b.doc["meshes"] = json::array({{{"primitives", {{{"attributes", {{"POSITION", p}}}}}}}});
        b.scene({b.node({{"mesh", 0}})});
        cases.push_back({"nan.glb", "accessors[0]", b.glb()});
    }
    {
        GltfBuilder b;
        b.doc["images"] = json::array({{{"uri", "missing.png"}}});
        b.doc["textures"] = json::array({{{"source", 0}}});
        b.doc["materials"] =
            json::array({{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}});
        b.scene({b.node({{"mesh", b.quad(0)}})});
        cases.push_back({"image.gltf", "images[0]", text(b.gltf())});
    }
    {
        GltfBuilder b = good();
        b.doc["extensionsUsed"] = {"KHR_draco_mesh_compression"};
        b.doc["extensionsRequired"] = {"KHR_draco_mesh_compression"};
        cases.push_back({"required.gltf", "extensionsRequired[0]", text(b.gltf())});
    }
    {
        GltfBuilder b;
        b.scene({b.node({{"name", "empty"}})});
        cases.push_back({"nomesh.gltf", "meshes", text(b.doc.dump())});
    }
    {
        GltfBuilder b = good();
        b.doc["meshes"][0]["primitives"][0]["attributes"].erase("POSITION");
        cases.push_back({"noposition.gltf", "meshes[0].primitives[0].attributes", text(b.gltf())});
    }
    cases.push_back({"garbage.gltf", "", text("{\"asset\": {\"version\": \"2.0\"}, \"nodes\": [")});
    return cases;
}

TEST(GltfHostile, EveryBadAssetIsOneErrorNamingTheFileAndPlace) {
    test::TempDir dir("gltf_hostile");
    for (const BadAsset& c : badAssets()) {
        const fs::path asset = writeBytes(dir.path() / c.name, c.bytes);
        for (const bool bare : {true, false}) {
            const fs::path scene = bare ? asset : dir.write("scene.json", sceneJson(c.name));
            try {
                loadScene(scene);
                ADD_FAILURE() << c.name << " was accepted";
            } catch (const Error& e) {
                EXPECT_NE(e.kind(), ErrorKind::Internal) << e.what();
                EXPECT_EQ(e.file(), asset.string()) << c.name << ": " << e.what();
                if (!c.place.empty()) {
                    EXPECT_EQ(e.where(), c.place) << c.name << ": " << e.what();
                }
                EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
            }
        }
    }
}

class GltfCli : public glint::testing::CliFixture {
  protected:
    GltfCli() : CliFixture("glint-render") {}
};

std::string lastLine(std::string t) {
    while (!t.empty() && t.back() == '\n') t.pop_back();
    const std::size_t nl = t.rfind('\n');
    return nl == std::string::npos ? t : t.substr(nl + 1);
}

TEST_F(GltfCli, ABareAssetRendersAndBadAssetsExitTwoWithOneLine) {
    GltfBuilder b;
    b.scene({b.node({{"mesh", b.quad()}})});
    writeBytes(m_dir / "model.glb", b.glb());
    const auto ok = run(path("model.glb") + " --spp 1 --out " + path("x.exr"));
    ASSERT_EQ(ok.exitCode, 0) << ok.err;
    EXPECT_EQ(readExr(path("x.exr")).width(), 640);
    const auto badCamera = run(path("model.glb") + " --spp 1 --camera nope --out " + path("y.exr"));
    EXPECT_EQ(badCamera.exitCode, 2);
    EXPECT_NE(lastLine(badCamera.err).find("--camera"), std::string::npos) << badCamera.err;

    for (const BadAsset& c : badAssets()) {
        writeBytes(m_dir / c.name, c.bytes);
        const auto r = run(path(c.name) + " --spp 1 --out " + path("bad.exr"));
        EXPECT_EQ(r.exitCode, 2) << c.name << ": " << r.err;
        const std::string line = lastLine(r.err);
        EXPECT_NE(line.find(c.name), std::string::npos) << line;
        EXPECT_NE(line.find(c.place), std::string::npos) << line;
        for (std::size_t at = 0;
             (at = r.err.find('\n', at)) != std::string::npos && at + 1 < r.err.size(); ++at)
            EXPECT_EQ(r.err.compare(at + 1, 13, "glint-render:"), 0) << "foreign text: " << r.err;
        EXPECT_FALSE(fs::exists(path("bad.exr")));
    }
}

}  // namespace
}  // namespace glint::render

// glTF's optional vertex attributes beyond TEXCOORD_0 (renderer/src/scene/gltf_import.cpp,
// gltf_accessor.cpp, gltf_material.cpp): COLOR_0 (float or normalised unsigned bytes and shorts,
// VEC3 or VEC4) multiplying the base colour, TEXCOORD_1 picked by a texture slot's texCoord (or
// KHR_texture_transform's) and filtered by that set's own footprint, and the warning that stays
// for sets past 1. Rendered where the albedo feature buffer shows the base colour without noise.

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "glint/image/error.h"
#include "glint/image/frame_buffers.h"
#include "glint/image/io.h"
#include "glint/render/renderer.h"
#include "glint/render/scene.h"
#include "gltf_builder.h"
#include "integrators/surface_inputs.h"
#include "scene/scene_access.h"
#include "scene/scene_data.h"
#include "test_util.h"
#include "tiled_texture.h"

namespace glint::render {
namespace vertex_attributes {

namespace fs = std::filesystem;
using nlohmann::json;
using namespace test_gltf;

/// A scene.json looking straight at the unit quad (z = 0, corners (0, 0) to (1, 1)) from
/// (0.5, 0.5, 3) so that the quad fills the film: a pixel is `pixel` world units wide.
constexpr int kWidth = 40, kHeight = 40;
constexpr double kFovY = 16.0;
const double kPixel = 2.0 * 3.0 * std::tan(kFovY / 2.0 * std::numbers::pi / 180.0) / kHeight;

std::string lookingAtTheQuad(const std::string& asset) {
    return R"({"film": {"width": 40, "height": 40}, "environment": {"color": [1, 1, 1]},
               "camera": {"position": [0.5, 0.5, 3], "lookAt": [0.5, 0.5, 0], "fovY": 16},
               "shapes": [{"gltf": ")" +
           asset + "\"}]}";
}

/// The albedo feature buffer (first-hit base colour) of `scene.json` at 4 samples per pixel.
Image albedoOf(const fs::path& scene) {
    Renderer renderer(loadScene(scene));
    Settings settings = renderer.scene().settings();
    settings.spp = 4;
    settings.threads = 2;
    return renderer.render(settings).frame.layer(Layer::Albedo);
}

/// A 2×2 PNG: red, green / blue, white (top row first).
void writeFourTexels(const fs::path& dir) {
    Image im(2, 2, 4, 1.0f);
    const float colours[4][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}};
    for (int i = 0; i < 4; ++i)
        for (int c = 0; c < 3; ++c) im(i % 2, i / 2, c) = colours[i][c];
    writeImage(im, dir / "tex.png");
}

/// Adds attribute `name` (accessor `accessor`) to the quad mesh `mesh`'s one primitive.
void addAttribute(GltfBuilder& b, int mesh, const char* name, int accessor) {
    b.doc["meshes"][std::size_t(mesh)]["primitives"][0]["attributes"][name] = accessor;
}

TEST(GltfVertexAttributes, VertexColoursMultiplyTheBaseColourFactorAcrossTheTriangle) {
    // The quad's corners (0, 0), (1, 0), (1, 1), (0, 1) coloured red, green, blue, white; its
    // first triangle (corners 0, 1, 2; x ≥ y) has barycentrics b1 = x − y, b2 = y, so its base
    // colour is factor × (1 − x, x − y, y).
    test::TempDir dir("gltf_vertex_colours");
    GltfBuilder b;
    b.doc["materials"] =
        json::array({{{"pbrMetallicRoughness", {{"baseColorFactor", {0.5, 0.8, 1.0, 1}}}}}});
    const int mesh = b.quad(0);
    addAttribute(b, mesh, "COLOR_0", b.floats({1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1}, "VEC3", 3));
    b.scene({b.node({{"mesh", mesh}})});
    dir.write("c.gltf", b.gltf());
    const fs::path scene = dir.write("scene.json", lookingAtTheQuad("c.gltf"));
    {
        const Scene s = loadScene(scene);
        EXPECT_TRUE(s.warnings().empty()) << s.warnings()[0];
        const detail::SceneData& d = detail::sceneData(s);
        ASSERT_EQ(d.meshes[0].colors.size(), 4u);
        EXPECT_FLOAT_EQ(d.meshes[0].colors[3].w, 1.0f) << "VEC3: alpha 1";
        // The surface input at barycentrics (0.25, 0.5) of the first triangle.
        SurfacePoint at;
        at.id = {0, 0};
        at.b1 = 0.25f, at.b2 = 0.5f;
        at.hasUv = true;
        at.uv = {0.5f, 0.5f};
        const Vec3 albedo = evaluateInputs(d, d.materials[0], at).albedo;
        EXPECT_NEAR(albedo.x, 0.5f * 0.25f, 1e-6f);
        EXPECT_NEAR(albedo.y, 0.8f * 0.25f, 1e-6f);
        EXPECT_NEAR(albedo.z, 1.0f * 0.5f, 1e-6f);
    }
    // Rendered: each pixel's mean albedo is the colour at its centre (a linear function averaged
    // over the pixel's samples), within the pixel's own extent of about 0.009 — 0.02 allowed.
    const Image albedo = albedoOf(scene);
    int checked = 0;
    for (int py = 0; py < kHeight; ++py)
        for (int px = 0; px < kWidth; ++px) {
            const double x = 0.5 + (px + 0.5 - kWidth / 2.0) * kPixel;
            const double y = 0.5 - (py + 0.5 - kHeight / 2.0) * kPixel;
            if (x - y < 2.0 * kPixel) continue;  // the first triangle, clear of the diagonal
            const double expected[3] = {0.5 * (1 - x), 0.8 * (x - y), 1.0 * y};
            for (int c = 0; c < 3; ++c)
                ASSERT_NEAR(albedo(px, py, c), expected[c], 0.02)
                    << "pixel " << px << ", " << py << " channel " << c;
            ++checked;
        }
    EXPECT_GT(checked, 600);
}

TEST(GltfVertexAttributes, NormalizedIntegerColoursReadAsFractionsOfTheirRange) {
    test::TempDir dir("gltf_vertex_colours_ubyte");
    GltfBuilder b;
    const int mesh = b.quad(), other = b.quad();
    // Unsigned bytes, normalised, RGBA: /255.
    const std::vector<std::uint8_t> bytes = {255, 0, 0,   255, 0,   51,  0,   102,
                                             0,   0, 255, 0,   255, 255, 255, 255};
    const int ubyte = b.accessor(b.view(bytes.data(), bytes.size()), 5121, "VEC4", 4);
    b.doc["accessors"][std::size_t(ubyte)]["normalized"] = true;
    addAttribute(b, mesh, "COLOR_0", ubyte);
    // Unsigned shorts, normalised, RGB: /65535; alpha 1.
    const std::vector<std::uint16_t> shorts = {65535, 0, 0,     0,     13107, 0,
                                               0,     0, 65535, 65535, 65535, 65535};
    const int ushort = b.accessor(b.view(shorts.data(), shorts.size() * 2), 5123, "VEC3", 4);
    b.doc["accessors"][std::size_t(ushort)]["normalized"] = true;
    addAttribute(b, other, "COLOR_0", ushort);
    b.scene({b.node({{"mesh", mesh}}), b.node({{"mesh", other}})});
    dir.write("u.gltf", b.gltf());
    const Scene s = loadScene(dir.write("scene.json", sceneJson("u.gltf")));
    EXPECT_TRUE(s.warnings().empty()) << s.warnings()[0];
    const detail::SceneData& d = detail::sceneData(s);
    ASSERT_EQ(d.meshes.size(), 2u);
    const Vec4 c = d.meshes[0].colors[1];
    EXPECT_FLOAT_EQ(c.y, 51.0f / 255.0f);
    EXPECT_FLOAT_EQ(c.w, 102.0f / 255.0f);
    EXPECT_FLOAT_EQ(d.meshes[0].colors[2].w, 0.0f);
    EXPECT_FLOAT_EQ(d.meshes[1].colors[1].y, 0.2f);
    EXPECT_FLOAT_EQ(d.meshes[1].colors[1].w, 1.0f);
    // Not normalised: an error naming the accessor.
    b.doc["accessors"][std::size_t(ubyte)].erase("normalized");
    dir.write("u.gltf", b.gltf());
    try {
        loadScene(dir.write("scene.json", sceneJson("u.gltf")));
        ADD_FAILURE() << "an integer colour that is not normalised was accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("must be normalized"), std::string::npos) << e.what();
    }
    // A colour must be VEC3 or VEC4: an error naming the accessor and the attribute.
    b.doc["accessors"][std::size_t(ubyte)]["normalized"] = true;
    b.doc["accessors"][std::size_t(ubyte)]["type"] = "SCALAR";
    b.doc["accessors"][std::size_t(ubyte)]["count"] = 16;
    dir.write("u.gltf", b.gltf());
    try {
        loadScene(dir.write("scene.json", sceneJson("u.gltf")));
        ADD_FAILURE() << "a SCALAR colour was accepted";
    } catch (const Error& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("accessors[" + std::to_string(ubyte) + "]"), std::string::npos) << what;
        EXPECT_NE(what.find("COLOR_0 needs VEC3 or VEC4"), std::string::npos) << what;
    }
}

TEST(GltfVertexAttributes, APrimitiveWithoutColoursIsWhiteBesideOneWithThem) {
    test::TempDir dir("gltf_vertex_colours_mixed");
    GltfBuilder b;
    const int mesh = b.quad();
    addAttribute(b, mesh, "COLOR_0", b.floats(std::vector<float>(16, 0.25f), "VEC4", 4));
    json& prims = b.doc["meshes"][std::size_t(mesh)]["primitives"];
    json bare = prims[0];
    bare["attributes"].erase("COLOR_0");
    prims.insert(prims.begin(), bare);  // the bare primitive first: its vertices come first
    b.scene({b.node({{"mesh", mesh}})});
    dir.write("m.gltf", b.gltf());
    const Scene s = loadScene(dir.write("scene.json", sceneJson("m.gltf")));
    const detail::Mesh& m = detail::sceneData(s).meshes[0];
    ASSERT_EQ(m.colors.size(), 8u);
    EXPECT_FLOAT_EQ(m.colors[0].x, 1.0f);
    EXPECT_FLOAT_EQ(m.colors[0].w, 1.0f);
    EXPECT_FLOAT_EQ(m.colors[4].x, 0.25f);
    // A mesh without colours allocates none.
    GltfBuilder plain;
    plain.scene({plain.node({{"mesh", plain.quad()}})});
    dir.write("p.gltf", plain.gltf());
    const Scene p = loadScene(dir.write("scene.json", sceneJson("p.gltf")));
    EXPECT_TRUE(detail::sceneData(p).meshes[0].colors.empty());
    EXPECT_TRUE(detail::sceneData(p).meshes[0].uvs1.empty());
}

TEST(GltfVertexAttributes, ATextureOnTexCoordOneReadsTheSecondUvSet) {
    // TEXCOORD_0 sits on the red texel everywhere, TEXCOORD_1 on the green one (glTF uvs, origin
    // top-left): the base colour is green only if set 1 is read.
    test::TempDir dir("gltf_texcoord1");
    writeFourTexels(dir.path());
    auto asset = [&](const json& textureInfo) {
        GltfBuilder b;
        b.doc["images"] = json::array({{{"uri", "tex.png"}}});
        b.doc["textures"] = json::array({{{"source", 0}}});
        b.doc["materials"] =
            json::array({{{"pbrMetallicRoughness", {{"baseColorTexture", textureInfo}}}}});
        const int mesh = b.quad(0);
        b.doc["accessors"][2]["bufferView"] =
            b.view(std::vector<float>(8, 0.25f).data(), 8 * sizeof(float));
        std::vector<float> uv1(8, 0.25f);
        for (int v = 0; v < 4; ++v) uv1[std::size_t(2 * v)] = 0.75f;
        addAttribute(b, mesh, "TEXCOORD_1", b.floats(uv1, "VEC2", 2));
        b.scene({b.node({{"mesh", mesh}})});
        dir.write("t.gltf", b.gltf());
        return dir.write("scene.json", lookingAtTheQuad("t.gltf"));
    };
    auto expectColour = [&](const fs::path& scene, Vec3 rgb, const char* what) {
        const Image a = albedoOf(scene);
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(a(kWidth / 2, kHeight / 2, c), rgb[c], 1e-3) << what << " channel " << c;
    };
    const fs::path onSet1 = asset({{"index", 0}, {"texCoord", 1}});
    {
        const Scene s = loadScene(onSet1);
        EXPECT_TRUE(s.warnings().empty()) << s.warnings()[0];
        const detail::SceneData& d = detail::sceneData(s);
        ASSERT_EQ(d.meshes[0].uvs1.size(), 4u);
        EXPECT_FLOAT_EQ(d.meshes[0].uvs1[0].y, 0.75f) << "v flipped to Glint's bottom-left origin";
        EXPECT_EQ(d.materials[0].textureTransform.set, 1);
    }
    expectColour(onSet1, {0, 1, 0}, "texCoord 1");
    expectColour(asset({{"index", 0}}), {1, 0, 0}, "texCoord 0");
    // KHR_texture_transform's texCoord overrides the texture info's.
    expectColour(asset({{"index", 0},
                        {"texCoord", 0},
                        {"extensions", {{"KHR_texture_transform", {{"texCoord", 1}}}}}}),
                 {0, 1, 0}, "KHR_texture_transform texCoord 1");
}

TEST(GltfVertexAttributes, ANormalMapOnTexCoordOneGetsTangentsAlongThatSet) {
    // TEXCOORD_0 runs with x; TEXCOORD_1 is mirrored in u. Generated tangents follow the normal
    // map's set: along -x with w = -1 (a mirrored layout) for texCoord 1, along +x for 0.
    test::TempDir dir("gltf_tangents1");
    writeFourTexels(dir.path());
    auto tangents = [&](int texCoord) {
        GltfBuilder b;
        b.doc["images"] = json::array({{{"uri", "tex.png"}}});
        b.doc["textures"] = json::array({{{"source", 0}}});
        b.doc["materials"] =
            json::array({{{"normalTexture", {{"index", 0}, {"texCoord", texCoord}}}}});
        const int mesh = b.quad(0);
        // The quad's TEXCOORD_0 is accessor 2 (POSITION, NORMAL, TEXCOORD_0).
        const json& uv0 = b.doc["accessors"][2];
        const std::size_t at = b.doc["bufferViews"][int(uv0["bufferView"])]["byteOffset"];
        std::vector<float> uv1(reinterpret_cast<const float*>(b.bin.data() + at),
                               reinterpret_cast<const float*>(b.bin.data() + at) + 8);
        for (int v = 0; v < 4; ++v) uv1[std::size_t(2 * v)] = 1.0f - uv1[std::size_t(2 * v)];
        addAttribute(b, mesh, "TEXCOORD_1", b.floats(uv1, "VEC2", 2));
        b.scene({b.node({{"mesh", mesh}})});
        dir.write("n.gltf", b.gltf());
        const Scene s = loadScene(dir.write("scene.json", lookingAtTheQuad("n.gltf")));
        return detail::sceneData(s).meshes[0].tangents;
    };
    for (const int texCoord : {0, 1}) {
        const std::vector<Vec4> t = tangents(texCoord);
        ASSERT_EQ(t.size(), 4u) << "texCoord " << texCoord;
        const float along = texCoord == 1 ? -1.0f : 1.0f;
        for (const Vec4& v : t) {
            EXPECT_NEAR(v.x, along, 1e-5f) << "texCoord " << texCoord;
            EXPECT_NEAR(v.y, 0.0f, 1e-5f) << "texCoord " << texCoord;
            EXPECT_FLOAT_EQ(v.w, along) << "texCoord " << texCoord;
        }
    }
}

TEST(GltfVertexAttributes, ASlotOnTheSecondSetIsFilteredByThatSetsFootprint) {
    // A 64² checker of single texels (a tiled, MIP-mapped file: filtered by the footprint).
    // Set 1 tiles it 16 times across the quad, set 0 once: a pixel covers about 22 texels of
    // set 1 but about 1.4 of set 0. Read on set 1 with set 1's footprint, every sample reads
    // levels of uniform grey (no variance), exactly as the same tiling read on set 0 does; with
    // set 0's footprint, 16 times narrower, it reads single texels (a variance of the mean of
    // 0.0037 when tried).
    test::TempDir dir("gltf_texcoord1_footprint");
    test::writeCheckerTexture(dir.path() / "checker.exr", 64, 1);
    auto render = [&](const json& textureInfo, float tile0, float tile1) {
        GltfBuilder b;
        b.doc["images"] = json::array({{{"uri", "checker.exr"}}});
        b.doc["textures"] = json::array({{{"source", 0}}});
        b.doc["materials"] =
            json::array({{{"pbrMetallicRoughness", {{"baseColorTexture", textureInfo}}}}});
        const int mesh = b.quad(0);
        const std::vector<float> uv = {0, 1, 1, 1, 1, 0, 0, 0};
        std::vector<float> uv0 = uv, uv1 = uv;
        for (float& t : uv0) t *= tile0;
        for (float& t : uv1) t *= tile1;
        b.doc["accessors"][2]["bufferView"] = b.view(uv0.data(), uv0.size() * sizeof(float));
        if (tile1 > 0.0f) addAttribute(b, mesh, "TEXCOORD_1", b.floats(uv1, "VEC2", 2));
        b.scene({b.node({{"mesh", mesh}})});
        dir.write("f.gltf", b.gltf());
        Renderer renderer(loadScene(dir.write("scene.json", lookingAtTheQuad("f.gltf"))));
        Settings settings = renderer.scene().settings();
        settings.spp = 4;
        settings.threads = 2;
        return renderer.render(settings).frame;
    };
    auto meanOf = [](const Image& im) {
        double sum = 0.0;
        for (int y = 0; y < im.height(); ++y)
            for (int x = 0; x < im.width(); ++x) sum += im(x, y, 0);
        return sum / (im.width() * im.height());
    };
    const json onSet1 = {{"index", 0}, {"texCoord", 1}}, onSet0 = {{"index", 0}};
    const FrameBuffers set1 = render(onSet1, 1.0f, 16.0f);
    const FrameBuffers set0 = render(onSet0, 16.0f, 0.0f);
    const double mean1 = meanOf(set1.layer(Layer::Albedo));
    EXPECT_GT(mean1, 0.05) << "the checker is read";
    EXPECT_LT(mean1, 0.95) << "the checker is read";
    EXPECT_NEAR(mean1, meanOf(set0.layer(Layer::Albedo)), 1e-6);
    EXPECT_LT(meanOf(set1.layer(Layer::AlbedoVariance)), 1e-6);
    EXPECT_LT(meanOf(set0.layer(Layer::AlbedoVariance)), 1e-6);
}

TEST(GltfVertexAttributes, SetsPastOneStillWarnAndSetOneNeedsSetZero) {
    test::TempDir dir("gltf_texcoord2");
    writeFourTexels(dir.path());
    GltfBuilder b;
    b.doc["images"] = json::array({{{"uri", "tex.png"}}});
    b.doc["textures"] = json::array({{{"source", 0}}});
    b.doc["materials"] = json::array(
        {{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}, {"texCoord", 2}}}}}}});
    const int mesh = b.quad(0);
    b.scene({b.node({{"mesh", mesh}})});
    dir.write("t.gltf", b.gltf());
    {
        const Scene s = loadScene(dir.write("scene.json", sceneJson("t.gltf")));
        ASSERT_EQ(s.warnings().size(), 1u);
        EXPECT_NE(s.warnings()[0].find("uses TEXCOORD_2"), std::string::npos) << s.warnings()[0];
        EXPECT_EQ(detail::sceneData(s).materials[0].textureTransform.set, 0);
    }
    // TEXCOORD_1 without TEXCOORD_0 breaks the spec's numbering from 0: an error at its place.
    json& attributes = b.doc["meshes"][std::size_t(mesh)]["primitives"][0]["attributes"];
    attributes["TEXCOORD_1"] = attributes["TEXCOORD_0"];
    attributes.erase("TEXCOORD_0");
    dir.write("t.gltf", b.gltf());
    try {
        loadScene(dir.write("scene.json", sceneJson("t.gltf")));
        ADD_FAILURE() << "TEXCOORD_1 without TEXCOORD_0 was accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("meshes[0].primitives[0].attributes"),
                  std::string::npos)
            << e.what();
        EXPECT_NE(std::string(e.what()).find("no TEXCOORD_0"), std::string::npos) << e.what();
    }
}

}  // namespace vertex_attributes
}  // namespace glint::render

// Bad glTF input (renderer/src/scene/gltf_file.cpp, gltf_import.cpp, gltf_accessor.cpp): each
// asset is one glint::Error naming the file and the glTF place, through loadScene and through
// glint-render (one line, exit 2, nothing written).

#include <cstdint>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_fixture.h"
#include "glint/image/error.h"
#include "glint/image/io.h"
#include "glint/render/scene.h"
#include "gltf_builder.h"
#include "scene/scene_access.h"
#include "scene/scene_data.h"
#include "test_util.h"

namespace glint::render {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using namespace test_gltf;

struct BadAsset {
    std::string name;   ///< file name (its extension chooses .gltf text or .glb bytes)
    std::string place;  ///< expected in Error::where()
    std::vector<unsigned char> bytes;
};

std::vector<unsigned char> text(const std::string& s) {
    return {s.begin(), s.end()};
}

/// Assets tinygltf read without a word although glTF 2.0 does not allow them (reliability round
/// 3): each rendered wrongly (empty, as triangles, without its transform, on a 3 GB film) or
/// crashed (JSON 30,000 levels deep overflowed the stack).
std::vector<BadAsset> outOfSpecAssets() {
    std::vector<BadAsset> cases;
    auto good = [] {
        GltfBuilder b;
        b.scene({b.node({{"mesh", b.quad()}})});
        return b;
    };
    {
        // 30,000 levels under extras (60 KB): refused at level 257, before any parser.
        GltfBuilder b = good();
        const std::string open(30000, '['), close(30000, ']');
        std::string doc = b.gltf();
        doc.pop_back();
        doc += ",\"extras\":";
        const std::string column = std::to_string(doc.size() + 256);
        cases.push_back({"deep.gltf", "line 1, column " + column, text(doc + open + close + "}")});
        std::string chunk = json(b.doc).dump();
        chunk.pop_back();
        chunk += ",\"buffers\":[{\"byteLength\":" + std::to_string(b.bin.size()) +
                 "}],\"extras\":{\"a\":";
        cases.push_back(
            {"deep.glb",
             "line 1, column " + std::to_string(chunk.size() + 255) + " of the JSON chunk",
             b.glbOf(chunk + open + close + "}}")});
    }
    {
        // Offsets not a multiple of the float components' 4 bytes (rendered as empty sky).
        GltfBuilder b = good();
        b.doc["accessors"][0]["byteOffset"] = 2;
        b.doc["bufferViews"][0]["byteLength"] = 52;
        cases.push_back({"align.gltf", "accessors[0].byteOffset", text(b.gltf())});
        b = good();
        b.doc["bufferViews"][0]["byteOffset"] = 2;
        cases.push_back({"viewalign.glb", "accessors[0].byteOffset", b.glb()});
    }
    {
        GltfBuilder b = good();
        b.doc["meshes"][0]["primitives"][0]["mode"] = -1;  // was read as triangles
        cases.push_back({"modeminus.gltf", "meshes[0].primitives[0].mode", text(b.gltf())});
    }
    {
        GltfBuilder b = good();
        b.doc["nodes"][0]["translation"] = {"1", "2", "3"};  // was read as no translation
        cases.push_back({"translation.gltf", "nodes[0].translation", text(b.gltf())});
    }
    for (const double aspect : {0.0, 1e-9, -1.0, 1e4}) {
        // 0 was taken for none; 1e-9 made a 640x16384 film (20.7 s, 3.1 GB).
        GltfBuilder b = good();
        b.doc["cameras"] = json::array(
            {{{"type", "perspective"},
              {"perspective", {{"yfov", 0.8}, {"znear", 0.01}, {"aspectRatio", aspect}}}}});
        b.doc["nodes"].push_back({{"camera", 0}, {"translation", {0.5, 0.5, 3}}});
        b.doc["scenes"][0]["nodes"].push_back(1);
        cases.push_back({"aspect" + std::to_string(cases.size()) + ".gltf",
                         "cameras[0].perspective.aspectRatio", text(b.gltf())});
    }
    {
        GltfBuilder b;
        b.doc["materials"] = json::array({{{"alphaMode", "MASK"}, {"alphaCutoff", -1}}});
        b.scene({b.node({{"mesh", b.quad(0)}})});
        cases.push_back({"cutoff.gltf", "materials[0].alphaCutoff", text(b.gltf())});
    }
    {
        // A string: a Draco primitive then rendered empty with one warning.
        GltfBuilder b = good();
        b.doc["extensionsRequired"] = "KHR_draco_mesh_compression";
        cases.push_back({"requiredstring.gltf", "extensionsRequired", text(b.gltf())});
    }
    {
        // A raw json.exception without line or column.
        GltfBuilder b = good();
        b.doc["extras"] = 12345;
        std::string doc = b.gltf();
        const std::size_t at = doc.find("12345");
        doc.replace(at, 5, "1e400");
        cases.push_back({"overflow.gltf", "line 1, column " + std::to_string(at + 1), text(doc)});
    }
    {
        GltfBuilder b = good();
        b.doc["bufferViews"][0]["byteStride"] = 256;  // was "must be a multiple of 4"
        cases.push_back({"stride.gltf", "bufferViews[0].byteStride", text(b.gltf())});
    }
    return cases;
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
    {
        GltfBuilder b = good();
        const std::size_t binBytes = b.bin.size();
        cases.push_back({"binlength.glb", "buffers[0].byteLength", b.glb(binBytes + 64)});
        // tinygltf's "Invalid binary data in `Buffer', or GLB with empty BIN chunk", no place.
        cases.push_back({"nobin.glb", "buffers[0]", b.glb(0, false)});
    }
    {
        // Draco as google/draco's Box_Draco.glb has it: the indices accessor has no bufferView
        // (the data is in the primitive's extension), which tinygltf refuses; it was reported
        // as "accessors[0]: ... invalid bufferView" rather than by the extension.
        GltfBuilder b = good();
        b.doc["accessors"][3].erase("bufferView");
        b.doc["meshes"][0]["primitives"][0]["extensions"] = {
            {"KHR_draco_mesh_compression", {{"bufferView", 0}, {"attributes", {{"POSITION", 0}}}}}};
        b.doc["extensionsUsed"] = {"KHR_materials_clearcoat", "KHR_draco_mesh_compression"};
        b.doc["extensionsRequired"] = {"KHR_draco_mesh_compression"};
        cases.push_back({"draco.glb", "extensionsRequired[0]", b.glb()});
        cases.push_back({"draco.gltf", "extensionsRequired[0]", text(b.gltf())});
    }
    {
        GltfBuilder b = good();
        b.doc["meshes"][0]["primitives"][0]["mode"] = 9;
        cases.push_back({"mode.gltf", "meshes[0].primitives[0].mode", text(b.gltf())});
        b.doc["meshes"][0]["primitives"][0]["mode"] = 5;  // a strip of 2 vertices
        b.doc["accessors"][3]["count"] = 2;
        cases.push_back({"strip.gltf", "meshes[0].primitives[0].indices", text(b.gltf())});
        b.doc["meshes"][0]["primitives"][0]["mode"] = 1;  // lines only
        cases.push_back({"lines.gltf", "scenes[0]", text(b.gltf())});
    }
    cases.push_back({"garbage.gltf", "", text("{\"asset\": {\"version\": \"2.0\"}, \"nodes\": [")});
    // GitHub's page for an asset saved under the asset's name (neilgannon/Hosting's
    // BoxTextured.gltf): reported as an invalid literal followed by the page's bytes before.
    cases.push_back({"page.gltf", "line 3, column 1", text("\n\n<!DOCTYPE html>\n<html>")});
    {
        // A data URI that is not base64 (atteneder/glTF-test-models' EmbedBufferInvalid): it
        // was reported as a missing buffer file named by the whole URI.
        GltfBuilder b = good();
        json d = json::parse(b.gltf());
        d["buffers"][0]["uri"] = "data:application/gltf-buffer,1111";
        cases.push_back({"datauri.gltf", "buffers", text(d.dump())});
    }
    {
        GltfBuilder b;
        b.doc["images"] = json::array({{{"uri", "data:image/png,notbase64"}}});
        b.doc["textures"] = json::array({{{"source", 0}}});
        b.doc["materials"] =
            json::array({{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}});
        b.scene({b.node({{"mesh", b.quad(0)}})});
        cases.push_back({"imageuri.gltf", "images[0].uri", text(b.gltf())});
        // Base64 with characters outside the alphabet: it was blamed on "buffers".
        b.doc["images"][0]["uri"] = "data:image/png;base64,!!!!";
        cases.push_back({"imagebase64.gltf", "images[0].uri", text(b.gltf())});
    }
    for (const BadAsset& c : outOfSpecAssets()) cases.push_back(c);
    return cases;
}

TEST(GltfFile, AGlbReadsAsTheSameAssetAsAGltfWithItsBufferInAFile) {
    // The .glb's BIN chunk is handed to tinygltf without a copy (gltf_file.cpp); the asset must
    // be the one the .gltf of the same document and a buffer file give. Three u16 indices
    // leave buffer 0 two bytes short of its 4-byte padded chunk.
    test::TempDir dir("gltf_file");
    GltfBuilder b;
    const int p = b.floats({0, 0, 0, 1, 0, 0, 0, 1, 0}, "VEC3", 3);
    const int i = b.u16({0, 1, 2});
    b.doc["meshes"] =
        json::array({{{"primitives", {{{"attributes", {{"POSITION", p}}}, {"indices", i}}}}}});
    b.scene({b.node({{"mesh", 0}})});
    ASSERT_NE(b.bin.size() % 4, 0u);
    writeBytes(dir.path() / "asset.bin", b.bin);
    json d = b.doc;
    d["buffers"] = json::array({{{"byteLength", b.bin.size()}, {"uri", "asset.bin"}}});
    const Scene fromFiles = loadScene(dir.write("asset.gltf", d.dump()));
    const Scene fromGlb = loadScene(writeBytes(dir.path() / "asset.glb", b.glb()));
    const auto &a = detail::sceneData(fromFiles).meshes, &g = detail::sceneData(fromGlb).meshes;
    ASSERT_EQ(a.size(), 1u);
    ASSERT_EQ(g.size(), 1u);
    EXPECT_EQ(g[0].indices, a[0].indices);
    ASSERT_EQ(g[0].positions.size(), 3u);
    for (std::size_t v = 0; v < 3; ++v)
        for (int c = 0; c < 3; ++c) EXPECT_EQ(g[0].positions[v][c], a[0].positions[v][c]);
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

TEST(GltfHostile, WhatIsNotReadIsNamedOnceAtItsFirstPlace) {
    test::TempDir dir("gltf_unread");
    // Two primitives with vertex colours (read: no warning), two of points.
    GltfBuilder b;
    const int mesh = b.quad(), other = b.quad();
    json& prims = b.doc["meshes"][std::size_t(mesh)]["primitives"];
    const int colours = b.floats(std::vector<float>(16, 0.5f), "VEC4", 4);
    prims[0]["attributes"]["COLOR_0"] = colours;
    b.doc["meshes"][std::size_t(other)]["primitives"][0]["attributes"]["COLOR_0"] = colours;
    json points = prims[0];
    points["mode"] = 0;
    prims.push_back(points), prims.push_back(points);
    b.scene({b.node({{"mesh", mesh}}), b.node({{"mesh", other}})});
    dir.write("c.gltf", b.gltf());
    const Scene s = loadScene(dir.write("scene.json", sceneJson("c.gltf")));
    EXPECT_EQ(s.triangleCount(), 4u);
    ASSERT_EQ(s.warnings().size(), 1u);
    EXPECT_NE(s.warnings()[0].find("mode 0 (points or lines) are skipped"), std::string::npos);
    EXPECT_NE(s.warnings()[0].find("meshes[0].primitives[1].mode"), std::string::npos);
    // Only points and lines: the error says so instead of only that there is no mesh.
    prims.erase(0);
    prims.erase(0);
    b.doc["nodes"].erase(1);
    b.scene({0});
    dir.write("p.gltf", b.gltf());
    try {
        loadScene(dir.write("scene.json", sceneJson("p.gltf")));
        ADD_FAILURE() << "points only loaded";
    } catch (const Error& e) {
        EXPECT_NE(e.message().find("points or lines"), std::string::npos) << e.message();
    }
}

TEST(GltfHostile, AnUndecodedDataUriIsNamedByItsHeaderNotItsData) {
    // A base64 image of a media type tinygltf does not decode ("image/jpg", "image/webp") was
    // taken for a file name: the message held the whole URI, megabytes for a real texture.
    test::TempDir dir("gltf_datauri");
    GltfBuilder b;
    const std::string data(100000, 'A');
    b.doc["images"] = json::array({{{"uri", "data:image/jpg;base64," + data}}});
    b.doc["textures"] = json::array({{{"source", 0}}});
    b.doc["materials"] =
        json::array({{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}});
    b.scene({b.node({{"mesh", b.quad(0)}})});
    const fs::path asset = dir.write("jpg.gltf", b.gltf());
    try {
        loadScene(asset);
        ADD_FAILURE() << "accepted";
    } catch (const Error& e) {
        EXPECT_EQ(e.where(), "images[0].uri") << e.what();
        const std::string what = e.what();
        EXPECT_NE(what.find("'data:image/jpg;base64,'"), std::string::npos) << what;
        EXPECT_NE(what.find("media type"), std::string::npos) << what;
        EXPECT_LT(what.size(), 400u) << what.substr(0, 400);
    }
    // Upper-case schemes are data URIs too (RFC 3986: schemes are case-insensitive).
    GltfBuilder c;
    c.scene({c.node({{"mesh", c.quad()}})});
    json d = json::parse(c.gltf());
    d["buffers"][0]["uri"] = "DATA:application/octet-stream," + data;
    try {
        loadScene(dir.write("upper.gltf", d.dump()));
        ADD_FAILURE() << "accepted";
    } catch (const Error& e) {
        EXPECT_EQ(e.where(), "buffers") << e.what();
        EXPECT_NE(std::string(e.what()).find("not base64"), std::string::npos) << e.what();
        EXPECT_LT(std::string(e.what()).size(), 400u);
    }
}

TEST(GltfHostile, AWebPageSavedAsAGltfIsNamedAsOne) {
    test::TempDir dir("gltf_page");
    for (const std::string& start : {std::string("<html>"), std::string("\xEF\xBB\xBF  <?xml")}) {
        try {
            loadScene(dir.write("page.gltf", start + "<body></body></html>"));
            ADD_FAILURE() << "accepted";
        } catch (const Error& e) {
            EXPECT_EQ(e.where(), start[0] == '<' ? "line 1, column 1" : "line 1, column 3")
                << e.what();
            EXPECT_NE(std::string(e.what()).find("HTML or XML"), std::string::npos) << e.what();
        }
    }
    // A .glb: amoghgg/portfolio's facecap.glb is such a page, 8 blank lines first (it was a
    // "wrong magic").
    try {
        loadScene(dir.write("page.glb", "\n\n\n\n\n\n\n\n<!DOCTYPE html>\n<html>"));
        ADD_FAILURE() << "accepted";
    } catch (const Error& e) {
        EXPECT_EQ(e.where(), "line 9, column 1") << e.what();
        EXPECT_NE(std::string(e.what()).find("not a binary glTF: the file is HTML or XML"),
                  std::string::npos)
            << e.what();
    }
}

TEST(GltfHostile, AFolderOrADeviceIsSaidToBeOneNotMissing) {
    // A buffer file, an image, the asset itself and an MTL texture that exist but are not
    // regular files were reported as "not found" (or "is not a file").
    test::TempDir dir("gltf_folder");
    fs::create_directories(dir.path() / "folder");
    fs::create_symlink("/dev/zero", dir.path() / "device");
    struct Expect {
        fs::path scene;
        std::string file, place, text;
    };
    std::vector<Expect> cases;
    for (const std::string target : {"folder", "device"}) {
        const std::string said =
            target == "folder" ? "is a folder" : "is not a regular file (a device or a pipe)";
        GltfBuilder b;
        b.scene({b.node({{"mesh", b.quad()}})});
        json d = json::parse(b.gltf());
        d["buffers"][0]["uri"] = target;
        const fs::path bin = dir.write("bin-" + target + ".gltf", d.dump());
        cases.push_back({bin, bin.string(), "buffers[0].uri", said});
        GltfBuilder c;
        c.doc["images"] = json::array({{{"uri", target}}});
        c.doc["textures"] = json::array({{{"source", 0}}});
        c.doc["materials"] =
            json::array({{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}});
        c.scene({c.node({{"mesh", c.quad(0)}})});
        const fs::path image = dir.write("image-" + target + ".gltf", c.gltf());
        cases.push_back({image, image.string(), "images[0]", said});
        const fs::path scene = dir.write("scene-" + target + ".json", sceneJson(target));
        cases.push_back({scene, scene.string(), "/shapes/0/gltf", said});
        // map_Kd in an MTL (a regression: "not found").
        dir.write("mesh-" + target + ".obj", "mtllib m-" + target +
                                                 ".mtl\nusemtl a\nv 0 0 0\nv 1 0 0\nv 0 1 0\n"
                                                 "vt 0 0\nf 1/1 2/1 3/1\n");
        const fs::path mtl = dir.write("m-" + target + ".mtl", "newmtl a\nmap_Kd " + target + "\n");
        cases.push_back({dir.path() / ("mesh-" + target + ".obj"), mtl.string(), "line 2", said});
    }
    for (const Expect& c : cases) {
        try {
            loadScene(c.scene);
            ADD_FAILURE() << c.scene << " was accepted";
        } catch (const Error& e) {
            EXPECT_EQ(e.kind(), ErrorKind::Io) << e.what();
            EXPECT_EQ(e.file(), c.file) << e.what();
            EXPECT_EQ(e.where(), c.place) << e.what();
            EXPECT_NE(std::string(e.what()).find(c.text), std::string::npos) << e.what();
            EXPECT_EQ(std::string(e.what()).find("not found"), std::string::npos) << e.what();
        }
    }
}

TEST(GltfHostile, AnAssetTooSmallForFloatIsRefusedByTheRuleOfASceneCamera) {
    // A 1e-30 or 1e-45-sized asset rendered as an empty frame with exit 0; a scene.json at that
    // scale is refused by its camera's lookAt distance, with these words.
    test::TempDir dir("gltf_tiny");
    const std::string rule =
        "from position, too close to give a view direction in float; expected a distance of at "
        "least 1e-18";
    for (const float size : {1e-30f, 1e-45f}) {
        GltfBuilder b;
        const int p = b.floats({0, 0, 0, size, 0, 0, 0, size, 0}, "VEC3", 3);
        b.doc["meshes"] = json::array({{{"primitives", {{{"attributes", {{"POSITION", p}}}}}}}});
        b.scene({b.node({{"mesh", 0}})});
        const fs::path asset = writeBytes(dir.path() / "tiny.glb", b.glb());
        try {
            loadScene(asset);
            ADD_FAILURE() << size << " was accepted";
        } catch (const Error& e) {
            EXPECT_EQ(e.file(), asset.string());
            EXPECT_NE(std::string(e.what()).find(rule), std::string::npos) << e.what();
        }
    }
    try {
        loadScene(dir.write("scene.json", R"({"camera": {"position": [0, 0, 0], "lookAt": [0, 0,
            1e-30]}, "film": {"width": 8, "height": 8}, "shapes": [{"gltf": "tiny.glb"}]})"));
        ADD_FAILURE() << "the scene.json was accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find(rule), std::string::npos) << e.what();
    }
    // The smallest scale the renderer keeps (docs/reliability.md: 1e-6 ... 1e6) still loads.
    GltfBuilder b;
    const int p = b.floats({0, 0, 0, 1e-6f, 0, 0, 0, 1e-6f, 0}, "VEC3", 3);
    b.doc["meshes"] = json::array({{{"primitives", {{{"attributes", {{"POSITION", p}}}}}}}});
    b.scene({b.node({{"mesh", 0}})});
    EXPECT_EQ(loadScene(writeBytes(dir.path() / "small.glb", b.glb())).triangleCount(), 1u);
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

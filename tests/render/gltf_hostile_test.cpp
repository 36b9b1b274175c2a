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
        cases.push_back({"nobin.glb", "", b.glb(0, false)});
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
    }
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

// The memory limit holds during loading (docs/renderer.md, "Memory"): before an OBJ or glTF
// reader parses an asset, its load's peak is predicted from a scan of the file, and an asset
// that would exceed the limit is refused in one line naming the prediction. That the refusal
// comes before the reader is shown by assets whose last bytes the reader refuses: with the limit
// the error is the prediction's, without it the reader's. Inputs are generated here.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "cli_fixture.h"
#include "glint/image/error.h"
#include "glint/image/image.h"
#include "glint/image/io.h"
#include "glint/image/memory.h"
#include "glint/render/renderer.h"
#include "glint/render/scene.h"
#include "gltf_builder.h"
#include "scene/gltf_import.h"
#include "scene/load_memory.h"
#include "scene/obj_scan.h"
#include "test_util.h"

namespace glint::render {
namespace {

namespace fs = std::filesystem;
using test_gltf::GltfBuilder;
using test_gltf::writeBytes;

// A glTF document of `meshes` unit quads, each placed by a node of its own.
GltfBuilder manyQuads(int meshes) {
    GltfBuilder b;
    std::vector<int> roots;
    for (int i = 0; i < meshes; ++i)
        roots.push_back(b.node({{"mesh", b.quad()}, {"translation", {1.5 * i, 0, 0}}}));
    b.scene(roots);
    return b;
}

// OBJ text of an n × n grid of quads with a normal at each vertex (`f a//a ...`).
std::string gridObj(int n) {
    std::string s;
    for (int y = 0; y <= n; ++y)
        for (int x = 0; x <= n; ++x)
            s += "v " + std::to_string(x) + " " + std::to_string(y) + " 0\nvn 0 0 1\n";
    auto at = [n](int x, int y) {
        const std::string i = std::to_string(1 + y * (n + 1) + x);
        return i + "//" + i;
    };
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x)
            s += "f " + at(x, y) + " " + at(x + 1, y) + " " + at(x + 1, y + 1) + " " +
                 at(x, y + 1) + "\n";
    return s;
}

// The error loadScene(file, limit) throws, or an empty message when it loads.
Error loadError(const fs::path& file, std::uint64_t limit) {
    try {
        (void)loadScene(file, limit);
    } catch (const Error& e) {
        return e;
    }
    return Error(ErrorKind::InvalidArgument, "");
}

TEST(LoadMemory, AGlbOfManyMeshesIsRefusedFromItsJsonBeforeItIsParsed) {
    test::TempDir dir("load_memory_glb");
    const GltfBuilder b = manyQuads(400);
    // The document's last byte is one the JSON parser refuses; the scan does not read it.
    nlohmann::json doc = b.doc;
    doc["buffers"] = nlohmann::json::array({{{"byteLength", b.bin.size()}}});
    const fs::path file = writeBytes(dir.path() / "many.glb", b.glbOf(doc.dump() + "x"));
    const detail::LoadPrediction p = detail::predictGltfLoad(file);
    // 400 meshes and nodes, 4 accessors a quad; the quads' arrays at least.
    EXPECT_NE(p.counted.find("400 meshes (400 primitives), 400 nodes, 1600 accessors, 0 images"),
              std::string::npos)
        << p.counted;
    EXPECT_GE(p.meshes, 400u * (4 * (12 + 12 + 8) + 6 * 4));
    EXPECT_GT(p.reader, p.meshes);  // the reader's document is the larger part
    EXPECT_GE(p.bytes, p.meshes + p.reader);

    // Without a limit the reader is called and refuses the document.
    const Error parsed = loadError(file, 0);
    EXPECT_EQ(parsed.kind(), ErrorKind::Format) << parsed.message();
    EXPECT_NE(parsed.message().find("malformed JSON"), std::string::npos) << parsed.message();
    // Below the prediction the prediction refuses it first, naming itself and the limit.
    const Error refused = loadError(file, p.bytes - 1);
    EXPECT_EQ(refused.kind(), ErrorKind::OutOfMemory) << refused.message();
    EXPECT_EQ(fs::path(refused.file()), file);
    const std::string& m = refused.message();
    EXPECT_NE(m.find("loading it would take about " + formatBytes(p.bytes) +
                     " at its peak (predicted before reading it: 400 meshes"),
              std::string::npos)
        << m;
    EXPECT_NE(m.find("but only " + formatBytes(p.bytes - 1) + " is allowed (memory limit)"),
              std::string::npos)
        << m;
    EXPECT_NE(m.find("fewer, larger meshes"), std::string::npos) << m;
    EXPECT_EQ(m.find('\n'), std::string::npos);
}

TEST(LoadMemory, AnObjIsRefusedFromItsStatementCountsBeforeItIsRead) {
    test::TempDir dir("load_memory_obj");
    // The last line is one the OBJ check refuses (a vertex of two numbers).
    const fs::path file = dir.write("grid.obj", gridObj(60) + "v 1 2\n");
    const detail::LoadPrediction p = detail::predictObjLoad(file);
    EXPECT_NE(p.counted.find("3722 vertex statements, 0 texture coordinates, 3721 normals, 3600 "
                             "faces of 14400 corners"),
              std::string::npos)
        << p.counted;
    const Error checked = loadError(file, 0);
    EXPECT_EQ(checked.kind(), ErrorKind::Format) << checked.message();
    EXPECT_EQ(checked.where(), "line " + std::to_string(2 * 61 * 61 + 60 * 60 + 1));
    const Error refused = loadError(file, p.bytes / 2);
    EXPECT_EQ(refused.kind(), ErrorKind::OutOfMemory) << refused.message();
    EXPECT_NE(refused.message().find("would take about " + formatBytes(p.bytes)), std::string::npos)
        << refused.message();
    EXPECT_NE(refused.message().find("the same mesh as a .glb"), std::string::npos)
        << refused.message();
}

// An asset loads under a limit just above its prediction, which covers what the scene then
// holds; a scene.json names the asset by its shape and counts what earlier shapes hold.
TEST(LoadMemory, AssetsLoadUnderALimitAtTheirPredictionWhichCoversWhatTheSceneHolds) {
    test::TempDir dir("load_memory_fits");
    const fs::path glb = writeBytes(dir.path() / "many.glb", manyQuads(300).glb());
    const fs::path obj = dir.write("grid.obj", gridObj(80));
    for (const fs::path& file : {glb, obj}) {
        const detail::LoadPrediction p =
            file == glb ? detail::predictGltfLoad(glb) : detail::predictObjLoad(obj);
        const Scene scene = loadScene(file, p.bytes);
        EXPECT_GT(scene.triangleCount(), 0u);
        EXPECT_LE(estimateSceneMemory(scene, Accel::Clusters, 0).held(), p.meshes + p.images)
            << file;
        EXPECT_EQ(loadError(file, p.bytes - 1).kind(), ErrorKind::OutOfMemory) << file;
    }
    // Both in one scene: the second asset's prediction goes on top of what the first holds.
    const fs::path json = dir.write(
        "scene.json", R"({"film": {"width": 8, "height": 6}, "environment": {"color": [1, 1, 1]},
        "shapes": [{"obj": "grid.obj"}, {"gltf": "many.glb"}]})");
    const Scene first = loadScene(obj);
    const std::uint64_t held = estimateSceneMemory(first, Accel::Clusters, 0).meshes;
    const Error refused = loadError(json, held + detail::predictGltfLoad(glb).bytes / 2);
    EXPECT_EQ(refused.kind(), ErrorKind::OutOfMemory) << refused.message();
    EXPECT_EQ(fs::path(refused.file()), json);
    EXPECT_EQ(refused.where(), "/shapes/1/gltf");
    EXPECT_NE(refused.message().find("loading " + glb.string() + " would take"), std::string::npos)
        << refused.message();
    EXPECT_NE(refused.message().find("the scene already holds"), std::string::npos)
        << refused.message();
}

// An embedded image counts by the size its header gives (decoded to floats), not its bytes.
TEST(LoadMemory, AnEmbeddedImageCountsByTheSizeItsHeaderGives) {
    test::TempDir dir("load_memory_image");
    Image texture(300, 200, 3);  // flat: a few hundred bytes of PNG
    writeImage(texture, dir.path() / "flat.png");
    std::ifstream in(dir.path() / "flat.png", std::ios::binary);
    const std::vector<unsigned char> png((std::istreambuf_iterator<char>(in)),
                                         std::istreambuf_iterator<char>());
    ASSERT_LT(png.size(), 10000u);
    GltfBuilder b;
    b.doc["images"] = {{{"bufferView", b.view(png.data(), png.size())}, {"mimeType", "image/png"}}};
    b.doc["textures"] = {{{"source", 0}}};
    b.doc["materials"] = {{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}};
    b.scene({b.node({{"mesh", b.quad(0)}})});
    const fs::path file = writeBytes(dir.path() / "textured.glb", b.glb());
    const detail::LoadPrediction p = detail::predictGltfLoad(file);
    EXPECT_GE(p.images, 300u * 200u * 4u * sizeof(float));
    const Scene scene = loadScene(file, p.bytes);
    EXPECT_LE(estimateSceneMemory(scene, Accel::Clusters, 0).held(), p.meshes + p.images);
}

class LoadMemoryCli : public glint::testing::CliFixture {
  protected:
    LoadMemoryCli() : CliFixture("glint-render") {}
};

TEST_F(LoadMemoryCli, AnAssetOverTheLimitIsRefusedInOneLineBeforeItIsRead) {
    const GltfBuilder b = manyQuads(200);
    const fs::path file = writeBytes(path("many.glb"), b.glb());
    const std::uint64_t need = detail::predictGltfLoad(file).bytes;
    auto r = run(file.string() + " --spp 1 --memory-limit " + std::to_string(need - 1) + " --out " +
                 path("refused.exr"));
    EXPECT_EQ(r.exitCode, 2) << r.err;
    const std::string last = r.err.substr(r.err.rfind('\n', r.err.size() - 2) + 1);
    EXPECT_EQ(last.rfind("glint-render: " + file.string() + ": loading it would take about " +
                             formatBytes(need),
                         0),
              0u)
        << r.err;
    EXPECT_NE(last.find("nothing of it was read"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(path("refused.exr")));
    r = run(file.string() + " --spp 1 --memory-limit 2G --out " + path("loaded.exr"));
    EXPECT_EQ(r.exitCode, 0) << r.err;
}

}  // namespace
}  // namespace glint::render

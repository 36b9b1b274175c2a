// --memory-limit / Settings::memoryLimit covers the scene, not only the film (docs/renderer.md,
// "Memory"): the mesh arrays, the BVH over Embree's triangles or clusters and the texture cache
// are estimated before anything is built; a scene that does not fit is refused in one line saying
// what it needs, the limit and what would help, and `auto` takes clusters when they fit. Small
// scenes and limits set between the estimates, so that no big file is needed.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "cli_fixture.h"
#include "glint/image/error.h"
#include "glint/image/memory.h"
#include "glint/render/renderer.h"
#include "glint/render/scene.h"
#include "test_util.h"

namespace glint::render {
namespace {

namespace fs = std::filesystem;

// OBJ text of an n × n grid of quads (2n² triangles) in the plane z = 0.
std::string gridObj(int n) {
    std::string s;
    for (int y = 0; y <= n; ++y)
        for (int x = 0; x <= n; ++x)
            s += "v " + std::to_string(x) + " " + std::to_string(y) + " 0\n";
    auto at = [n](int x, int y) { return std::to_string(1 + y * (n + 1) + x); };
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x)
            s += "f " + at(x, y) + " " + at(x + 1, y) + " " + at(x + 1, y + 1) + " " +
                 at(x, y + 1) + "\n";
    return s;
}

const char* kGridScene = R"({"camera": {"position": [50, 50, 150], "lookAt": [50, 50, 0]},
  "film": {"width": 16, "height": 16}, "shapes": [{"obj": "grid.obj"}],
  "environment": {"color": [1, 1, 1]}})";

// A 100 × 100 grid: 20000 triangles, far below auto's cluster threshold.
fs::path writeGridScene(const test::TempDir& dir) {
    dir.write("grid.obj", gridObj(100));
    return dir.write("scene.json", kGridScene);
}

// The film of a render with `settings` (estimateMemory of a renderer of the same scene).
std::uint64_t filmBytes(const fs::path& scene, const Settings& settings) {
    return Renderer(loadScene(scene), Accel::Clusters).estimateMemory(settings);
}

TEST(MemoryLimit, TheSceneEstimateCountsTheMeshesAndTheBvhOfEitherKind) {
    test::TempDir dir("memory_estimate");
    const Scene scene = loadScene(writeGridScene(dir));
    ASSERT_EQ(scene.triangleCount(), 20000u);
    const SceneMemory triangles = estimateSceneMemory(scene, Accel::Auto, 1024);
    const SceneMemory clusters = estimateSceneMemory(scene, Accel::Clusters, 1024);
    EXPECT_EQ(triangles.accel, Accel::Triangles);  // auto below the threshold
    EXPECT_EQ(clusters.accel, Accel::Clusters);
    // 101² positions and 20000 triangles' indices at least; the same arrays either way.
    EXPECT_GE(triangles.meshes, 101u * 101u * 12u + 20000u * 12u);
    EXPECT_EQ(triangles.meshes, clusters.meshes);
    // Clusters hold the triangles in a fraction of Embree's memory (docs/renderer.md).
    EXPECT_GT(clusters.structures, 0u);
    EXPECT_LT(3 * clusters.structures, triangles.structures);
    EXPECT_EQ(triangles.textureCache, 0u);  // no texture
    EXPECT_EQ(triangles.total(), triangles.meshes + triangles.images + triangles.structures);
}

TEST(MemoryLimit, AutoTakesClustersWhenOnlyTheyFitAndTrianglesAreRefusedSayingSo) {
    test::TempDir dir("memory_limit");
    const fs::path file = writeGridScene(dir);
    Settings s = loadScene(file).settings();
    s.spp = 1;
    const std::uint64_t film = filmBytes(file, s);
    const std::uint64_t withTriangles =
        film + estimateSceneMemory(loadScene(file), Accel::Triangles, s.textureCacheMb).total();
    const std::uint64_t withClusters =
        film + estimateSceneMemory(loadScene(file), Accel::Clusters, s.textureCacheMb).total();
    ASSERT_LT(withClusters, withTriangles);
    // Between the two: auto builds clusters and renders.
    s.memoryLimit = (withClusters + withTriangles) / 2;
    s.accel = Accel::Auto;
    Renderer fits(loadScene(file), s);
    EXPECT_EQ(fits.accel(), Accel::Clusters);
    EXPECT_EQ(fits.render(s).stats.completedSpp, 1);
    // Asked for triangles: refused before building, naming the need, the limit and the way out.
    s.accel = Accel::Triangles;
    try {
        Renderer refused(loadScene(file), s);
        ADD_FAILURE() << "built over triangles beyond the limit";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::OutOfMemory);
        EXPECT_EQ(fs::path(e.file()), file);
        const std::string m = e.message();
        EXPECT_NE(m.find("need " + formatBytes(withTriangles)), std::string::npos) << m;
        EXPECT_NE(m.find(formatBytes(s.memoryLimit) + " is allowed"), std::string::npos) << m;
        EXPECT_NE(m.find("--set accel=clusters) it would need " + formatBytes(withClusters) +
                         ", which fits"),
                  std::string::npos)
            << m;
    }
    // Below what clusters need, auto is refused too, and clusters are not offered as the cure.
    s.accel = Accel::Auto;
    s.memoryLimit = withClusters - 1;
    try {
        Renderer refused(loadScene(file), s);
        ADD_FAILURE() << "built beyond the limit";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::OutOfMemory);
        EXPECT_NE(e.message().find("would still need"), std::string::npos) << e.message();
    }
}

// A renderer made without the limit still counts the scene when a render is given one.
TEST(MemoryLimit, ARenderWithALimitCountsTheSceneNotOnlyTheFilm) {
    test::TempDir dir("memory_render");
    const fs::path file = writeGridScene(dir);
    Renderer renderer(loadScene(file), Accel::Triangles);
    Settings s = renderer.scene().settings();
    s.spp = 1;
    s.memoryLimit = renderer.estimateMemory(s) + 1024;  // the film fits, the scene does not
    try {
        renderer.render(s);
        ADD_FAILURE() << "rendered a scene beyond the limit";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::OutOfMemory);
        EXPECT_EQ(e.where(), "/shapes");
        EXPECT_NE(e.message().find("the scene (20000 triangles)"), std::string::npos)
            << e.message();
    }
}

class MemoryLimitCli : public glint::testing::CliFixture {
  protected:
    MemoryLimitCli() : CliFixture("glint-render") {}
};

TEST_F(MemoryLimitCli, TheLimitCoversTheSceneAndAutoFallsBackToClusters) {
    test::TempDir dir("memory_cli");
    const fs::path file = writeGridScene(dir);
    Settings s = loadScene(file).settings();
    s.spp = 1;
    const std::uint64_t film = filmBytes(file, s);
    const std::uint64_t withTriangles =
        film + estimateSceneMemory(loadScene(file), Accel::Triangles, s.textureCacheMb).total();
    const std::uint64_t withClusters =
        film + estimateSceneMemory(loadScene(file), Accel::Clusters, s.textureCacheMb).total();
    const std::string limit =
        " --memory-limit " + std::to_string((withClusters + withTriangles) / 2);
    const std::string args = file.string() + " --spp 1 --json" + limit + " --out ";
    auto r = run(args + path("auto.exr"));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find(R"("bvh":"clusters")"), std::string::npos) << r.out;
    EXPECT_NE(r.err.find("the BVH is built over clusters"), std::string::npos) << r.err;
    r = run(args + path("triangles.exr") + " --set accel=triangles");
    EXPECT_EQ(r.exitCode, 2) << r.err;
    EXPECT_EQ(r.err.find("glint-render: " + file.string() + ": /shapes: the scene"),
              r.err.rfind('\n', r.err.size() - 2) + 1)
        << r.err;
    EXPECT_NE(r.err.find("(--set accel=clusters) it would need"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(path("triangles.exr")));
}

}  // namespace
}  // namespace glint::render

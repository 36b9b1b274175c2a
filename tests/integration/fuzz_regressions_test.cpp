// Every input the fuzzers found that once crashed, hung or slipped past a check, replayed
// through the same harnesses (tests/fuzz/fuzz_targets.h): each must now end as a clean
// glint::Error (or load), never a crash (docs/reliability.md).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

#include "fuzz_targets.h"

namespace glint::fuzz {
namespace {

void replay(const char* target, void (*run)(const std::uint8_t*, std::size_t)) {
    const fs::path dir = fs::path(GLINT_SOURCE_DIR) / "tests/data/fuzz-regressions" / target;
    ASSERT_TRUE(fs::is_directory(dir)) << dir;
    int files = 0;
    for (const auto& entry : fs::directory_iterator(dir)) {
        if (!entry.is_regular_file() || entry.path().filename() == "README.md") continue;
        std::ifstream in(entry.path(), std::ios::binary);
        const std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)),
                                              std::istreambuf_iterator<char>());
        SCOPED_TRACE(entry.path().string());
        run(bytes.data(), bytes.size());  // aborts the test binary on a bug
        ++files;
    }
    EXPECT_GT(files, 0) << "no regression inputs in " << dir;
}

TEST(FuzzRegressions, SceneJson) {
    replay("scene_json", runSceneJson);
}
TEST(FuzzRegressions, Obj) {
    replay("obj", runObj);
}
TEST(FuzzRegressions, Texture) {
    replay("texture", runTexture);
}
TEST(FuzzRegressions, Exr) {
    replay("exr", runExr);
}

TEST(FuzzSeeds, GltfSeedsLoadAndRender) {
    // The glTF target's seeds (tests/fuzz/seeds/gltf) through its harness, and each must load:
    // a seed the reader refused would leave the fuzzer at the parser.
    const fs::path dir = fs::path(GLINT_SOURCE_DIR) / "tests/fuzz/seeds/gltf";
    int files = 0;
    for (const auto& entry : fs::directory_iterator(dir)) {
        std::ifstream in(entry.path(), std::ios::binary);
        const std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)),
                                              std::istreambuf_iterator<char>());
        SCOPED_TRACE(entry.path().string());
        runGltf(bytes.data(), bytes.size());
        EXPECT_NO_THROW(render::loadScene(entry.path()));
        ++files;
    }
    EXPECT_GE(files, 2);
}

}  // namespace
}  // namespace glint::fuzz

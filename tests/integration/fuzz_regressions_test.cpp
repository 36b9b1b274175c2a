// Every input the fuzzers found that once crashed, hung or slipped past a check, replayed
// through the same harnesses (tests/fuzz/fuzz_targets.h): each must now end as a clean
// glint::Error (or load), never a crash (docs/reliability.md).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

#include "fuzz_replay.h"
#include "fuzz_targets.h"

namespace glint::fuzz {
namespace {

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

TEST(FuzzSeeds, TheAdaptiveSceneSeedRunsItsPasses) {
    // The scene target's adaptive seed, loaded in the harness's workspace and rendered as the
    // harness renders it, leaves pixels at different counts: the fuzzer starts inside the
    // adaptive passes.
    std::ifstream in(fs::path(GLINT_SOURCE_DIR) / "tests/fuzz/seeds/scene_json/adaptive.json");
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    runSceneJson(reinterpret_cast<const std::uint8_t*>(text.data()), text.size());
    render::Renderer renderer(render::parseScene(text, workspace() / "fuzz.json"));
    render::Settings s = renderer.scene().settings();
    ASSERT_TRUE(s.adaptive);
    s.threads = 1;
    const render::RenderResult result = renderer.render(s);
    const Image& counts = result.frame.layer(Layer::SampleCount);
    const auto [lo, hi] = std::minmax_element(counts.data().begin(), counts.data().end());
    EXPECT_LT(*lo, *hi);
    EXPECT_LE(*hi, float(s.spp));
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

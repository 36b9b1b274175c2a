// Every input the fuzzers found that once crashed, hung or slipped past a check, replayed
// through the same harnesses (tests/fuzz/fuzz_targets.h): each must now end as a clean
// glint::Error (or load), never a crash (docs/reliability.md).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <string>
#include <utility>
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

TEST(FuzzSeeds, TevStreamsArePacketsTheStudioAcceptsEveryOne) {
    // The tev target's seeds (tests/fuzz/seeds/tev: Glint's own stream of a render with
    // features, pbrt-v4's one channel a packet, every other packet type and Cycles' names):
    // every packet decodes and applies, and the images end as their streams leave them. A seed
    // the listener dropped would leave the fuzzer at the first check.
    std::map<std::string, std::pair<int, bool>> images;  // name: (width, complete)
    int files = 0;
    for (const fs::path& file : seedFiles("tev")) {
        const std::vector<std::uint8_t> bytes = readBytes(file);
        SCOPED_TRACE(file.string());
        ASSERT_GT(bytes.size(), 1u);
        runTevStream(bytes.data(), bytes.size());
        tev::PacketStream stream;
        stream.append({bytes.data() + 1, bytes.size() - 1});
        tev::ReceivedImages received;
        int packets = 0;
        while (const auto packet = stream.next()) {
            ASSERT_NO_THROW(received.apply(tev::decode(*packet), kTevMemory));
            ++packets;
        }
        EXPECT_EQ(stream.buffered(), 0u);
        EXPECT_GE(packets, 4);
        for (const char* name : {"glint", "pbrt", "grey", "cycles"})
            if (received.has(name))
                images[name] = {received.frame(name).width(), received.complete(name)};
        ++files;
    }
    EXPECT_EQ(files, 3);
    const std::map<std::string, std::pair<int, bool>> expected{
        {"glint", {6, true}}, {"pbrt", {4, true}}, {"grey", {3, false}}, {"cycles", {2, false}}};
    EXPECT_EQ(images, expected);
}

TEST(FuzzSeeds, GltfSeedsLoadAndRender) {
    // The glTF target's seeds (tests/fuzz/seeds/gltf) through its harness, and each must load:
    // a seed the reader refused would leave the fuzzer at the parser.
    int files = 0;
    for (const fs::path& file : seedFiles("gltf")) {
        const std::vector<std::uint8_t> bytes = readBytes(file);
        SCOPED_TRACE(file.string());
        runGltf(bytes.data(), bytes.size());
        EXPECT_NO_THROW(render::loadScene(file));
        ++files;
    }
    EXPECT_GE(files, 2);
}

}  // namespace
}  // namespace glint::fuzz

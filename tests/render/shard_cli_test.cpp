// glint-render --shard i/N and glint-image merge as a user runs them: the merged file equals the
// whole render within the stated tolerance (docs/distributed.md), and a bad set exits 2 with one
// line naming the shards and writes nothing; the merge reads one file at a time with the bits of
// the in-memory merge, and partial merges (--partial) merge again like shards.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_fixture.h"
#include "glint/image/error.h"
#include "glint/image/io.h"
#include "glint/image/shard.h"
#include "test_util.h"

namespace glint::render {
namespace {

namespace fs = std::filesystem;
using glint::testing::RunResult;

class ShardCli : public glint::testing::CliFixture {
  protected:
    ShardCli() : CliFixture("glint-render") {}
    void SetUp() override {
        CliFixture::SetUp();
        if (HasFatalFailure()) return;
        m_merge = m_binary.parent_path() / "glint-image";
        ASSERT_TRUE(fs::exists(m_merge)) << m_merge;
        const std::string obj = std::string(GLINT_RENDER_TEST_DATA) + "/cornell_box.obj";
        std::ofstream(m_dir / "scene.json") << R"({
          "camera": {"position": [278, 273, -800], "lookAt": [278, 273, 0], "fovY": 39.3},
          "film": {"width": 24, "height": 16},
          "shapes": [{"obj": ")" << obj << R"("}],
          "render": {"spp": 4, "maxDepth": 6}
        })";
    }
    /// glint-image with `args`, stdout and stderr captured.
    RunResult image(const std::string& args) const {
        const fs::path out = m_dir / "image_out.txt", err = m_dir / "image_err.txt";
        const std::string cmd =
            m_merge.string() + " " + args + " >" + out.string() + " 2>" + err.string();
        const int status = std::system(cmd.c_str());
        RunResult r;
        r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
        r.out = glint::testing::slurp(out);
        r.err = glint::testing::slurp(err);
        return r;
    }
    fs::path m_merge;
};

std::string lastLine(std::string t) {
    while (!t.empty() && t.back() == '\n') t.pop_back();
    const std::size_t nl = t.rfind('\n');
    return nl == std::string::npos ? t : t.substr(nl + 1);
}

TEST_F(ShardCli, ShardsMergeIntoTheWholeRender) {
    const std::string common = path("scene.json") + " --spp 7 --seed 5";
    ASSERT_EQ(run(common + " --threads 2 --out " + path("whole.exr")).exitCode, 0);
    for (int i = 0; i < 3; ++i) {
        const RunResult r = run(common + " --shard " + std::to_string(i) + "/3 --threads " +
                                std::to_string(1 + i % 2) + " --json --out " +
                                path("s" + std::to_string(i) + ".exr"));
        ASSERT_EQ(r.exitCode, 0) << r.err;
        const nlohmann::json j = nlohmann::json::parse(r.out);
        EXPECT_EQ(j["shard"]["index"], i);
        EXPECT_EQ(j["shard"]["count"], 3);
        EXPECT_EQ(j["spp"],
                  j["shard"]["samples"][1].get<int>() - j["shard"]["samples"][0].get<int>());
    }
    const RunResult m = image("merge " + path("s2.exr") + " " + path("s0.exr") + " " +
                              path("s1.exr") + " --out " + path("merged.exr") + " --json");
    ASSERT_EQ(m.exitCode, 0) << m.err;
    EXPECT_EQ(nlohmann::json::parse(m.out)["spp"], 7);

    const FrameBuffers whole = readExr(path("whole.exr"));
    const FrameBuffers merged = readExr(path("merged.exr"));
    EXPECT_EQ(merged.metadata().spp, 7);
    EXPECT_EQ(merged.metadata().seed, 5u);
    EXPECT_FALSE(shardInfo(merged.metadata(), "merged.exr"));
    const Image &a = whole.color(), &b = merged.color();
    for (std::size_t i = 0; i < a.data().size(); ++i)
        EXPECT_LE(std::abs(a.data()[i] - b.data()[i]),
                  4.0f * 0x1p-24f * std::abs(a.data()[i]) + 1e-6f * 0x1p-24f)
            << i;
}

TEST_F(ShardCli, MergesOneFileAtATimeAndPartialMergesMergeAgain) {
    const std::string common = path("scene.json") + " --spp 8 --seed 3 --threads 1";
    std::vector<ShardFrame> shards;
    for (int i = 0; i < 4; ++i) {
        const std::string file = path("s" + std::to_string(i) + ".exr");
        ASSERT_EQ(run(common + " --shard " + std::to_string(i) + "/4 --out " + file).exitCode, 0);
        shards.push_back({file, readExr(file)});
    }
    // The streaming merge of the CLI gives the bits of the in-memory merge of the same files.
    RunResult m = image("merge " + path("s3.exr") + " " + path("s1.exr") + " " + path("s0.exr") +
                        " " + path("s2.exr") + " --out " + path("flat.exr"));
    ASSERT_EQ(m.exitCode, 0) << m.err;
    const FrameBuffers flat = readExr(path("flat.exr"));
    const FrameBuffers inMemory = mergeShards(shards);
    test::expectSameFrames(flat, inMemory);
    EXPECT_EQ(flat.metadata().extra, inMemory.metadata().extra);
    EXPECT_EQ(flat.metadata().spp, 8);

    // The library's file merge reports each file folded and stops when told to.
    std::vector<std::string> files;
    for (const ShardFrame& sf : shards) files.push_back(sf.file);
    int calls = 0;
    test::expectSameFrames(mergeShardFiles(files, MergeKind::Whole,
                                           [&](int done, int total) {
                                               EXPECT_EQ(done, ++calls);
                                               EXPECT_EQ(total, 4);
                                               return true;
                                           }),
                           inMemory);
    EXPECT_EQ(calls, 4);
    try {
        mergeShardFiles(files, MergeKind::Whole, [](int done, int) { return done < 2; });
        ADD_FAILURE() << "a merge told to stop went on";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::Cancelled);
    }

    // Partial merges record their range and merge again, alone or with plain shards.
    m = image("merge " + path("s1.exr") + " " + path("s0.exr") + " --partial --json --out " +
              path("p01.exr"));
    ASSERT_EQ(m.exitCode, 0) << m.err;
    const nlohmann::json j = nlohmann::json::parse(m.out);
    EXPECT_EQ(j["partial"], true);
    EXPECT_EQ(j["range"], nlohmann::json({0, 1, 4}));
    const FrameBuffers p01 = readExr(path("p01.exr"));
    EXPECT_EQ(p01.metadata().extra.at("shard"), "0-1/4");
    EXPECT_EQ(p01.metadata().extra.at("shardSamples"), "0 4");
    EXPECT_EQ(p01.metadata().spp, 4);
    ASSERT_EQ(image("merge " + path("s2.exr") + " " + path("s3.exr") + " --partial --out " +
                    path("p23.exr"))
                  .exitCode,
              0);
    for (const std::string& set : {path("p23.exr") + " " + path("p01.exr"),
                                   path("p01.exr") + " " + path("s2.exr") + " " + path("s3.exr")}) {
        m = image("merge " + set + " --out " + path("tree.exr"));
        ASSERT_EQ(m.exitCode, 0) << m.err;
        const FrameBuffers tree = readExr(path("tree.exr"));
        EXPECT_FALSE(shardInfo(tree.metadata(), "tree.exr"));
        EXPECT_EQ(tree.metadata().spp, 8);
        EXPECT_TRUE(test::sameLayer(tree, flat, Layer::SampleCount));
        // Means within 4·2^-24·M of the flat merge (docs/distributed.md, "Tree merge").
        const Image &a = flat.color(), &b = tree.color();
        for (std::size_t i = 0; i < a.data().size(); ++i) {
            float big = 0.0f;
            for (const ShardFrame& s : shards)
                big = std::max(big, std::abs(s.frame.color().data()[i]));
            EXPECT_LE(std::abs(a.data()[i] - b.data()[i]), 4.0f * 0x1p-24f * big) << i;
        }
    }

    // Gaps and overlaps name the files, exit 2 and write nothing.
    struct Case {
        std::string args, expected;
    };
    const Case cases[] = {
        {path("p01.exr") + " " + path("s1.exr") + " " + path("p23.exr"),
         "s1.exr: shard 1/4 overlaps shards 0-1/4 of " + path("p01.exr")},
        {path("p01.exr") + " " + path("s3.exr"),
         "missing 2/4; given " + path("p01.exr") + " (0-1/4), " + path("s3.exr") + " (3/4)"},
        {path("p01.exr"), "missing 2-3/4"},
        {path("s0.exr") + " " + path("s2.exr") + " --partial", "contiguous range: missing 1/4"},
        {path("p01.exr") + " " + path("scene.json"), "scene.json"},
    };
    for (const Case& c : cases) {
        const RunResult r = image("merge " + c.args + " --out " + path("out.exr"));
        EXPECT_EQ(r.exitCode, 2) << c.args;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
        EXPECT_NE(lastLine(r.err).find(c.expected), std::string::npos) << r.err;
        EXPECT_FALSE(fs::exists(path("out.exr"))) << c.args;
    }
}

TEST_F(ShardCli, BadSetsExitTwoNamingTheShardsAndWriteNothing) {
    const std::string common = path("scene.json") + " --spp 4 --seed 5 --threads 1";
    for (int i = 0; i < 2; ++i)
        ASSERT_EQ(run(common + " --shard " + std::to_string(i) + "/2 --out " +
                      path("s" + std::to_string(i) + ".exr"))
                      .exitCode,
                  0);
    ASSERT_EQ(run(path("scene.json") + " --spp 4 --seed 6 --shard 1/2 --out " + path("seed6.exr"))
                  .exitCode,
              0);
    struct Case {
        std::string args, expected;
    };
    const Case cases[] = {
        {path("s0.exr"), "missing 1/2"},
        {path("s0.exr") + " " + path("s1.exr") + " " + path("s1.exr"), "given twice"},
        {path("s0.exr") + " " + path("seed6.exr"), "seed6.exr: shard 1/2 is foreign"},
        {path("s0.exr") + " " + path("absent.exr"), "absent.exr"},
    };
    for (const Case& c : cases) {
        const RunResult r = image("merge " + c.args + " --out " + path("out.exr"));
        EXPECT_EQ(r.exitCode, 2) << c.args;
        EXPECT_NE(lastLine(r.err).find(c.expected), std::string::npos) << r.err;
        EXPECT_FALSE(fs::exists(path("out.exr"))) << c.args;
    }
    // Shard options that cannot be honoured are refused before rendering.
    for (const std::string& bad :
         {std::string("--shard 4/4"), std::string("--shard 0/5"), std::string("--shard 1of2"),
          std::string("--shard 0/2 --time-limit 1")}) {
        const RunResult r = run(common + " " + bad + " --out " + path("x.exr"));
        EXPECT_EQ(r.exitCode, 2) << bad;
        EXPECT_NE(lastLine(r.err).find("--shard"), std::string::npos) << r.err;
        EXPECT_FALSE(fs::exists(path("x.exr"))) << bad;
    }
}

}  // namespace
}  // namespace glint::render

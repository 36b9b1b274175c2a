// glint-final as a user runs it: the built binary (next to this test binary) on a tiny Cornell
// box. It writes the denoised EXR with the render's layers; a time limit shorter than one pass
// says so and writes that pass; bad targets, thresholds, spp and maps of the settings exit 2 with
// one line naming the flag and write nothing.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "glint/image/io.h"
#include "glint/pipeline/final_render.h"
#include "scene_cli_fixture.h"

namespace glint::pipeline {
namespace {

namespace fs = std::filesystem;
using glint::testing::RunResult;

class FinalCli : public glint::testing::SceneCliFixture {
  protected:
    FinalCli() : SceneCliFixture("glint-final", {24, 24, 4}) {}
    // The scene with these arguments, writing out.exr.
    RunResult final(const std::string& args) const {
        return run(path("scene.json") + " --out " + path("out.exr") + " " + args);
    }
};

TEST_F(FinalCli, WritesTheDenoisedColourWithTheRendersLayers) {
    const RunResult r = final("--set spp=32 --set minSpp=8 --threads 2");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find("estimated relMSE"), std::string::npos) << r.out;
    const FrameBuffers f = readExr(path("out.exr"));
    EXPECT_EQ(f.metadata().extra.at("denoiseFilter"), "auto");
    for (Layer l : {Layer::Variance, Layer::HalfColor, Layer::SampleCount, Layer::Albedo})
        EXPECT_TRUE(f.has(l)) << layerDisplayName(l);
}

TEST_F(FinalCli, ATimeLimitShorterThanOnePassSaysSoAndWritesThatPass) {
    const RunResult r = final("--time-limit 1e-6 --threads 1");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.err.find("shorter than one pass"), std::string::npos) << r.err;
    const FrameBuffers f = readExr(path("out.exr"));
    for (float n : f.layer(Layer::SampleCount).data()) ASSERT_EQ(n, 1.0f);
}

TEST_F(FinalCli, ATimeLimitCountsTheProcesssStartAndKeepsTheWritingsShare) {
    // The limit is shared out before the render: what the process's start (from its exec) and
    // the scene took, what the writing keeps (0.1 s + 0.35 µs for each of the 576 pixels), and
    // the rest for the render and auto; the three add up to the limit.
    const RunResult r = final("--time-limit 30 --set spp=8 --threads 1");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    double taken = -1.0, writing = -1.0, loop = -1.0;
    const std::size_t at = r.err.find("time limit: ");
    ASSERT_NE(at, std::string::npos) << r.err;
    ASSERT_EQ(std::sscanf(r.err.c_str() + at,
                          "time limit: %lf s taken by the start and the scene, %lf s kept for "
                          "writing, %lf s for the render and auto",
                          &taken, &writing, &loop),
              3)
        << r.err;
    EXPECT_GT(taken, 0.0);
    EXPECT_DOUBLE_EQ(writing, 0.10);
    EXPECT_NEAR(taken + writing + loop, 30.0, 0.02);  // three values rounded to 0.01
}

TEST_F(FinalCli, UnderATimeLimitAloneTheRendersVarianceSteersAndAutoRunsOnlyAtTheEnd) {
    // A time limit the spp bound ends well before: the variance schedule runs no refresh; with
    // an error target (never reached here) auto runs at each refresh and its map steers. (No
    // time limit there: whether a refresh fits one depends on the machine's speed.)
    const RunResult timed = final("--time-limit 30 --set spp=64 --set minSpp=8 --threads 1");
    ASSERT_EQ(timed.exitCode, 0) << timed.err;
    EXPECT_NE(timed.out.find(" 0 refreshes)"), std::string::npos) << timed.out;
    const RunResult target = final("--target-error 1e-12 --set spp=64 --set minSpp=8 --threads 1");
    ASSERT_EQ(target.exitCode, 0) << target.err;
    EXPECT_EQ(target.out.find(" 0 refreshes)"), std::string::npos) << target.out;
    EXPECT_EQ(defaultSteering(30.0, 0.0), Steering::Variance);
    EXPECT_EQ(defaultSteering(30.0, 1e-3), Steering::Denoiser);
    EXPECT_EQ(defaultSteering(0.0, 0.0), Steering::Denoiser);
}

TEST_F(FinalCli, BadInputExitsTwoWithOneLineNamingTheFlagAndWritesNothing) {
    struct Case {
        std::string args, expected;
    };
    const Case cases[] = {
        {"--target-error 0", "--target-error: the error target must be > 0"},
        {"--target-error -1", "--target-error: the error target must be > 0, got -1"},
        {"--target-error nan", "--target-error"},
        {"--target-error 2e6 --set spp=64", "--target-error: the error target must be"},
        {"--time-limit 0", "--time-limit: the time limit must be > 0, got 0"},
        {"--time-limit 2e7",
         "--time-limit: the time limit must be a number of seconds in [0, "
         "1e7], got 2e+07"},
        {"--set noiseThreshold=0", "--set noiseThreshold"},
        {"--set noiseThreshold=nan", "--set noiseThreshold"},
        {"--set noiseThreshold=2e6", "--set noiseThreshold"},
        {"--set spp=4 --set minSpp=8", "minSpp"},
        {"--set nosuch=1", "--set: 'nosuch=1': expected name=value"},
        {"--set spp=0 --target-error 0.01", "--set spp: expected an integer in [1, 16777216]"},
    };
    for (const Case& c : cases) {
        const RunResult r = final(c.args);
        EXPECT_EQ(r.exitCode, 2) << c.args << "\n" << r.err;
        std::string err = r.err;
        while (!err.empty() && err.back() == '\n') err.pop_back();
        const std::string last =
            err.substr(err.rfind('\n') == std::string::npos ? 0 : err.rfind('\n') + 1);
        EXPECT_EQ(last.rfind("glint-final: ", 0), 0u) << c.args << ": " << last;
        EXPECT_NE(last.find(c.expected), std::string::npos) << c.args << ": " << last;
        EXPECT_FALSE(fs::exists(path("out.exr"))) << c.args;
    }
}

}  // namespace
}  // namespace glint::pipeline

// glint-denoise auto on another renderer's EXR: the committed Cycles frame (Combined and the
// denoising data passes, no variance, no half buffers; tests/data/cycles/README.md) runs with the
// image-only noise estimator and says so; its bad input (docs/auto.md, "Bad input").
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cli_fixture.h"
#include "glint/image/io.h"
#include "synthetic_frames.h"

namespace glint::denoise {
namespace {

namespace fs = std::filesystem;
using glint::testing::RunResult;

const std::string kCycles = (fs::path(GLINT_SOURCE_DIR) / "tests/data/cycles").string();

class AutoImageCli : public glint::testing::CliFixture {
  protected:
    AutoImageCli() : CliFixture("glint-denoise") {}
};

TEST_F(AutoImageCli, ACyclesExrFallsBackToTheImageEstimatorAndSaysSoOnce) {
    const std::string in = kCycles + "/cornell_8spp_seed1.exr";
    RunResult r = runEither("auto " + in + " --out " + path("auto.exr") + " --size 8 --json");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(nlohmann::json::parse(r.out)["estimator"], "image");
    // One line on stderr, naming the file and the estimator it falls back to.
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_NE(r.err.find("cornell_8spp_seed1.exr"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("falls back to the image-only noise estimator"), std::string::npos)
        << r.err;
    const FrameBuffers out = readExr(path("auto.exr"));
    EXPECT_EQ(out.width(), 128);
    EXPECT_EQ(out.color().countNonFinite(), 0u);
    // The text output names it too.
    r = runEither("auto " + in + " --out " + path("auto2.exr") + " --size 8");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find("SURE with the image-only noise estimate"), std::string::npos) << r.out;
}

TEST_F(AutoImageCli, OnTheCyclesExrAutoDenoisesAgainstTheCyclesReference) {
    // The default bank (70 members, bank seed 1) and SURE seed 1: deterministic. Measured 0.9609
    // (docs/auto.md); the bound leaves 0.01 for float differences between machines.
    const RunResult r =
        runEither("auto " + kCycles + "/cornell_8spp_seed1.exr --out " + path("a.exr") +
                  " --reference " + kCycles + "/cornell_reference.exr --json");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const nlohmann::json j = nlohmann::json::parse(r.out);
    EXPECT_GT(j["metrics"]["ssim"].get<double>(), 0.95);
    EXPECT_GT(j["metrics"]["ssim"].get<double>(), j["metricsInput"]["ssim"].get<double>() + 0.3);
}

TEST_F(AutoImageCli, OneTileAndManyAgreeWithTheImageEstimator) {
    // The pipeline's SURE estimator makes the same estimate from the frame in one tile (a large
    // --memory-limit) and in many (a tiny one): the same composite, bit for bit.
    int height = 0;
    for (const char* limit : {"64G", "1K"}) {
        const RunResult r = runEither("auto " + kCycles + "/cornell_8spp_seed2.exr --out " +
                                      path(limit) + ".exr --size 8 --json --memory-limit " + limit);
        ASSERT_EQ(r.exitCode, 0) << r.err;
        const nlohmann::json j = nlohmann::json::parse(r.out);
        EXPECT_EQ(j["estimator"], "image");
        if (height == 0) {
            height = j["tileRows"].get<int>();  // one tile: the region's height
            EXPECT_GT(height, 64);              // taller than the lowest tile height
        } else {
            EXPECT_LT(j["tileRows"].get<int>(), height);
        }
    }
    EXPECT_EQ(
        testing::maxAbsDiff(readExr(path("64G.exr")).color(), readExr(path("1K.exr")).color()),
        0.0);
}

TEST_F(AutoImageCli, ForcedOnAGlintRenderItSaysTheVarianceLayerIsNotUsedAndWritesItsEstimate) {
    writeExr(testing::syntheticFrame(48, 40, 0.1f), m_dir / "noisy.exr");
    const RunResult r =
        runEither("auto " + path("noisy.exr") + " --out " + path("a.exr") +
                  " --size 6 --estimator image --noise-out " + path("noise.exr") + " --json");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(nlohmann::json::parse(r.out)["estimator"], "image");
    EXPECT_NE(r.err.find("the variance layer of"), std::string::npos) << r.err;
    // The estimate of noise 0.1 (variance 0.01) is of that order: within a factor 2 on average.
    const Image noise = readExr(path("noise.exr")).color();
    double mean = 0.0;
    for (float v : noise.data()) mean += v;
    mean /= double(noise.data().size());
    EXPECT_GT(mean, 0.005);
    EXPECT_LT(mean, 0.02);
}

TEST_F(AutoImageCli, BadInputExitsTwoWithOneLineNamingTheFileAndThePlace) {
    // An EXR with the colour only: NFOR lacks its features; auto with its default bank falls
    // back to the image estimator and runs; a NaN is named by pixel.
    FrameBuffers bare = testing::syntheticFrame(40, 32, 0.1f);
    for (Layer l : {Layer::Variance, Layer::Albedo, Layer::Normal, Layer::Depth,
                    Layer::AlbedoVariance, Layer::NormalVariance, Layer::DepthVariance})
        bare.remove(l);
    writeExr(bare, m_dir / "bare.exr");
    bare.color()(3, 2, 0) = std::nanf("");
    writeExr(bare, m_dir / "nan.exr");
    struct Case {
        std::string args;
        std::vector<std::string> mentions;
    };
    const Case cases[] = {
        {"apply " + path("bare.exr") + " --filter nfor --out " + path("o.exr"),
         {"bare.exr", "nfor", "albedo"}},
        {"auto " + path("bare.exr") + " --filters nfor --out " + path("o.exr"),
         {"bare.exr", "layer 'albedo'", "nfor"}},
        {"auto " + path("nan.exr") + " --out " + path("o.exr"),
         {"nan.exr", "pixel (3, 2), channel R", "NaN", "image-only"}},
        {"auto " + path("bare.exr") + " --out " + path("o.exr") + " --noise-window 0",
         {"--noise-window"}},
        {"auto " + path("bare.exr") + " --out " + path("o.exr") + " --noise-out " + path("n.png"),
         {"--noise-out", ".exr"}},
    };
    for (const Case& c : cases) {
        const RunResult r = runEither(c.args);
        EXPECT_EQ(r.exitCode, 2) << c.args << "\n" << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << c.args << "\n" << r.err;
        for (const std::string& m : c.mentions)
            EXPECT_NE(r.err.find(m), std::string::npos) << c.args << ": " << m << "\n" << r.err;
        EXPECT_FALSE(fs::exists(path("o.exr"))) << c.args;
    }
    const RunResult ok =
        runEither("auto " + path("bare.exr") + " --out " + path("o.exr") + " --size 6");
    EXPECT_EQ(ok.exitCode, 0) << ok.err;
    EXPECT_NE(ok.err.find("falls back to the image-only noise estimator"), std::string::npos);
}

}  // namespace
}  // namespace glint::denoise

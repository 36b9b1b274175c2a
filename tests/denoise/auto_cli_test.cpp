// glint-denoise auto end to end (its tuning through glint-lab auto, the same run with every
// tuning flag), its qualities, and the oracle's auto column: good and bad input.
#include <gtest/gtest.h>

#include <algorithm>
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

// The classical filters, for the tests of auto's options that need no learned member (unet adds
// about a second to every run; the other tests run it through the default bank).
const std::string kClassicalFilters =
    " --filters gaussian,bilateral,bilateral-mc,cross-bilateral,guided,nlmeans";

class AutoCli : public glint::testing::CliFixture {
  protected:
    AutoCli() : CliFixture("glint-denoise") {}
    void SetUp() override {
        CliFixture::SetUp();
        if (HasFatalFailure()) return;
        writeExr(testing::syntheticFrame(48, 40, 0.1f), m_dir / "noisy.exr");
        writeExr(testing::syntheticFrame(48, 40, 0.0f), m_dir / "ref.exr");
        FrameBuffers bare = testing::syntheticFrame(48, 40, 0.1f);
        bare.remove(Layer::Variance);
        writeExr(bare, m_dir / "novariance.exr");
        FrameBuffers nan = testing::syntheticFrame(48, 40, 0.1f);
        nan.color()(7, 4, 2) = std::nanf("");
        writeExr(nan, m_dir / "nan.exr");
        // Half buffers: half B another noisy draw, one sample per half.
        FrameBuffers halves = testing::syntheticFrame(48, 40, 0.1f);
        halves.set(Layer::HalfColor, testing::syntheticFrame(48, 40, 0.1f, 2).color());
        for (Layer l : {Layer::Albedo, Layer::Normal, Layer::Depth, Layer::AlbedoVariance,
                        Layer::NormalVariance, Layer::DepthVariance})
            if (halves.has(l)) halves.set(*halfLayer(l), halves.layer(l));
        halves.ensure(Layer::HalfVariance);
        for (float& v : halves.ensure(Layer::SampleCount).data()) v = 2.0f;
        for (float& v : halves.ensure(Layer::HalfSampleCount).data()) v = 1.0f;
        writeExr(halves, m_dir / "halves.exr");
        halves.remove(Layer::Albedo);
        halves.remove(Layer::HalfAlbedo);
        writeExr(halves, m_dir / "noalbedo.exr");
    }
};

TEST_F(AutoCli, HalfBuffersSelectTheHalvesEstimatorAndItsDefaults) {
    RunResult r = runEither("auto " + path("halves.exr") + " --out " + path("auto.exr") +
                            " --size 6 --json" + kClassicalFilters);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    nlohmann::json j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["estimator"], "halves");
    EXPECT_EQ(j["oneSided"], 0);
    EXPECT_EQ(j["window"], 8);
    EXPECT_EQ(j["confidence"], 1.0);
    EXPECT_EQ(j["finer"], 1);
    EXPECT_EQ(j["feather"], 5);
    EXPECT_EQ(j["featherGate"], 0.2);
    // Stacking: up to 6 members (those with weight), over radius 6, ridge 0.5, floor 0.1,
    // coefficients averaged over radius 8.
    EXPECT_GE(j["stack"].get<int>(), 1);
    EXPECT_LE(j["stack"].get<int>(), 6);
    EXPECT_EQ(j["stackWindow"], 6);
    EXPECT_EQ(j["stackRidge"], 0.5);
    EXPECT_EQ(j["stackFloor"], 0.1);
    EXPECT_EQ(j["stackSmooth"], 8);
    // And the features the input has: the albedo's regressor and the normal's three.
    EXPECT_EQ(j["stackFeatures"], 4);
    EXPECT_EQ(j["stackFeatureWindow"], 3);
    for (const auto& [flags, count] :
         {std::pair{"--stack-albedo off --stack-normal off", 0}, std::pair{"--stack-albedo off", 3},
          std::pair{"--stack-normal off", 1}}) {
        r = runEither("auto " + path("halves.exr") + " --out " + path("auto.exr") +
                      " --size 6 --json " + flags + kClassicalFilters);
        ASSERT_EQ(r.exitCode, 0) << r.err;
        EXPECT_EQ(nlohmann::json::parse(r.out)["stackFeatures"], count) << flags;
    }
    // A file without an albedo stacks on the normal alone unless the albedo is asked for.
    r = runEither("auto " + path("noalbedo.exr") + " --out " + path("auto.exr") +
                  " --size 6 --json" + kClassicalFilters);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(nlohmann::json::parse(r.out)["stackFeatures"], 3);
    r = runEither("auto " + path("halves.exr") + " --out " + path("auto.exr") +
                  " --size 6 --json --estimator sure --one-sided" + kClassicalFilters);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["estimator"], "sure");
    EXPECT_EQ(j["window"], 4);
    EXPECT_EQ(j["confidence"], 3.0);
    EXPECT_EQ(j["finer"], 0);
    EXPECT_EQ(j["feather"], 4);
    EXPECT_EQ(j["stack"], 0);
    r = runEither("auto " + path("halves.exr") + " --out " + path("auto.exr") + " --size 6" +
                  kClassicalFilters);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find("cross-validation on the halves"), std::string::npos) << r.out;
}

// A bank folder built on prefiltered features: `auto --bank`, the oracle's auto column and the
// local artist's auto start all read its prefiltering (autoOptionsOfBank) and reach one SSIM.
TEST_F(AutoCli, EveryAutoOfAPrefilteredBankFolderIsTheSameComposite) {
    RunResult r = run("bank " + path("noisy.exr") + " --out " + path("pbank") +
                      " --size 6 --prefilter --filter-param prefilter.radius=2");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const std::string inputs =
        path("noisy.exr") + " --reference " + path("ref.exr") + " --bank " + path("pbank");
    r = runEither("auto " + inputs + " --out " + path("pauto.exr") + " --json");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const double autoSsim = nlohmann::json::parse(r.out)["metrics"]["ssim"].get<double>();
    r = runTool("glint-lab", "oracle " + inputs + " --json");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const nlohmann::json column = nlohmann::json::parse(r.out)["auto"];
    ASSERT_TRUE(column["ssim"].is_number()) << r.out;
    EXPECT_NEAR(column["ssim"].get<double>(), autoSsim, 1e-12);
    r = runTool("glint-lab",
                "navigate " + inputs + " --simulate --local --strokes 1 --brush-size 12 --json");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const nlohmann::json start = nlohmann::json::parse(r.out)["start"];
    EXPECT_EQ(start["kind"], "auto");
    EXPECT_NEAR(start["ssim"].get<double>(), autoSsim, 1e-12);
    // Without the bank's prefiltering the composite differs: the agreement above is not chance.
    r = runEither("auto " + path("noisy.exr") + " --reference " + path("ref.exr") + " --out " +
                  path("plain.exr") + " --size 6 --json");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(nlohmann::json::parse(r.out)["metrics"]["ssim"].get<double>(), autoSsim);
}

TEST_F(AutoCli, AutoWithAndWithoutABankFolderAndTheOracleColumn) {
    RunResult r =
        runEither("auto " + path("noisy.exr") + " --out " + path("auto.exr") + " --size 10" +
                  " --reference " + path("ref.exr") + " --choice-map " + path("c.png") + " --json");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    nlohmann::json j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["members"], 10 + defaultBankFilters().size());  // 10 + the defaults
    EXPECT_GE(j["membersUsed"].get<int>(), 1);
    EXPECT_GE(j["analyticDivergence"].get<int>(), 1);  // the gaussians
    EXPECT_GT(j["metrics"]["ssim"].get<double>(), j["metricsInput"]["ssim"].get<double>());
    EXPECT_TRUE(fs::exists(path("auto.exr")));
    EXPECT_TRUE(fs::exists(path("c.png")));
    // The output keeps the input's layers.
    const FrameBuffers out = readExr(path("auto.exr"));
    EXPECT_TRUE(out.has(Layer::Variance));
    EXPECT_TRUE(out.has(Layer::Albedo));

    // From a bank folder: the same bank, the same composite, bit for bit.
    r = run("bank " + path("noisy.exr") + " --out " + path("bank") + " --size 10");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    r = runEither("auto " + path("noisy.exr") + " --bank " + path("bank") + " --out " +
                  path("auto2.exr"));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find("members used"), std::string::npos) << r.out;
    EXPECT_EQ(
        testing::maxAbsDiff(readExr(path("auto.exr")).color(), readExr(path("auto2.exr")).color()),
        0.0);

    r = runTool("glint-lab", "oracle " + path("noisy.exr") + " --reference " + path("ref.exr") +
                                 " --bank " + path("bank") + " --json");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    j = nlohmann::json::parse(r.out);
    ASSERT_TRUE(j["auto"]["ssim"].is_number()) << r.out;
    EXPECT_GT(j["auto"]["ssim"].get<double>(), j["noisy"].get<double>());
    r = runTool("glint-lab", "oracle " + path("noisy.exr") + " --reference " + path("ref.exr") +
                                 " --bank " + path("bank"));
    EXPECT_NE(r.out.find("auto (sure)"), std::string::npos) << r.out;

    // The expected-error oracle: with IN itself as the other render, the expected error is the
    // realised one, so at radius 0 it is the per-pixel oracle.
    r = runTool("glint-lab", "oracle " + path("noisy.exr") + " --reference " + path("ref.exr") +
                                 " --bank " + path("bank") + " --json --expected " +
                                 path("noisy.exr"));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["expected"]["renders"], 2);
    EXPECT_EQ(j["expected"]["radii"], nlohmann::json::parse("[0, 2, 4, 8]"));
    EXPECT_NEAR(j["expected"]["ssim"][0].get<double>(), j["perPixel"].get<double>(), 1e-12);
    EXPECT_NEAR(j["expected"]["share"][0].get<double>(), 1.0, 1e-9);
    // Another render of another size is refused naming it.
    writeExr(testing::syntheticFrame(40, 40, 0.1f, 3), m_dir / "small.exr");
    r = runTool("glint-lab", "oracle " + path("noisy.exr") + " --reference " + path("ref.exr") +
                                 " --bank " + path("bank") + " --expected " + path("noisy.exr") +
                                 "," + path("small.exr"));
    EXPECT_EQ(r.exitCode, 2) << r.err;
    EXPECT_NE(r.err.find("small.exr"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("40x40"), std::string::npos) << r.err;
    r = runTool("glint-lab", "oracle " + path("noisy.exr") + " --reference " + path("ref.exr") +
                                 " --bank " + path("bank") + " --expected " + path("gone.exr"));
    EXPECT_EQ(r.exitCode, 2) << r.err;
    EXPECT_NE(r.err.find("gone.exr"), std::string::npos) << r.err;
}

TEST_F(AutoCli, AnOutputKeepsItsRenderAndIsDenoisedAgainFromIt) {
    // auto's output keeps the render's colour as its noisy layer beside the denoised one
    // (denoiseFilter: auto). auto on that output denoises the render it keeps, says so in one
    // line, and gives the first output bit for bit (the same render, the same seed); apply's
    // output keeps it likewise.
    RunResult r = runEither("auto " + path("halves.exr") + " --out " + path("once.exr") +
                            " --size 4" + kClassicalFilters);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const FrameBuffers render = readExr(path("halves.exr"));
    const FrameBuffers once = readExr(path("once.exr"));
    ASSERT_EQ(once.metadata().extra.at("denoiseFilter"), "auto");
    ASSERT_TRUE(once.has(Layer::Noisy));
    EXPECT_TRUE(std::equal(once.layer(Layer::Noisy).data().begin(),
                           once.layer(Layer::Noisy).data().end(), render.color().data().begin()));
    EXPECT_FALSE(std::equal(once.color().data().begin(), once.color().data().end(),
                            render.color().data().begin()));

    r = runEither("auto " + path("once.exr") + " --out " + path("twice.exr") + " --size 4" +
                  kClassicalFilters);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.err.find("once.exr keeps its render (layer noisy): denoising that"),
              std::string::npos)
        << r.err;
    const FrameBuffers twice = readExr(path("twice.exr"));
    EXPECT_TRUE(std::equal(twice.color().data().begin(), twice.color().data().end(),
                           once.color().data().begin()));
    EXPECT_TRUE(std::equal(twice.layer(Layer::Noisy).data().begin(),
                           twice.layer(Layer::Noisy).data().end(), render.color().data().begin()));

    r = run("apply " + path("once.exr") + " --filter gaussian" + " --out " + path("blurred.exr"));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const FrameBuffers blurred = readExr(path("blurred.exr"));
    EXPECT_EQ(blurred.metadata().extra.at("denoiseFilter"), "gaussian");
    EXPECT_TRUE(std::equal(blurred.layer(Layer::Noisy).data().begin(),
                           blurred.layer(Layer::Noisy).data().end(),
                           render.color().data().begin()));
    // Bad values in the render it keeps: one line naming the layer noisy and the pixel, whichever
    // estimator checks them (each has its own check).
    FrameBuffers bad = once;
    bad.layer(Layer::Noisy)(20, 10, 1) = std::nanf("");
    writeExr(bad, path("bad.exr"));
    for (const char* estimator : {"halves", "sure", "image"}) {
        r = runEither("auto " + path("bad.exr") + " --estimator " + estimator + " --out " +
                      path("never.exr") + " --size 4" + kClassicalFilters);
        EXPECT_EQ(r.exitCode, 2) << estimator << ": " << r.err;
        EXPECT_NE(r.err.find("bad.exr: pixel (20, 10), channel noisy.G: NaN in the noisy layer "
                             "(the render the file keeps)"),
                  std::string::npos)
            << estimator << ": " << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << estimator << ": " << r.err;
        EXPECT_FALSE(fs::exists(path("never.exr"))) << estimator;
    }

    // In a region the render is filtered again; around it the file's own colour stays.
    r = run("apply " + path("once.exr") + " --filter gaussian --roi 8,20,4,16 --out " +
            path("region.exr"));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const FrameBuffers region = readExr(path("region.exr"));
    for (int y = 0; y < region.height(); ++y)
        for (int x = 0; x < region.width(); ++x)
            for (int c = 0; c < 3; ++c) {
                const bool inside = x >= 8 && x < 20 && y >= 4 && y < 16;
                ASSERT_EQ(region.color()(x, y, c),
                          inside ? blurred.color()(x, y, c) : once.color()(x, y, c))
                    << x << "," << y << "," << c;
            }
}

TEST_F(AutoCli, AnInputWhoseColourIsDenoisedWithoutItsRenderIsRefusedUnlessTheImageAloneEstimates) {
    // A denoised file that does not keep its render (no noisy layer: written before Glint kept
    // it, or stripped) still has the render's half buffers and variance beside its denoised
    // colour: auto would estimate from statistics that describe another image. One line naming
    // the file and the metadata, exit 2, nothing written; SURE's variance likewise; the
    // image-only estimate runs.
    RunResult r = runEither("auto " + path("halves.exr") + " --out " + path("full.exr") +
                            " --size 4" + kClassicalFilters);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    FrameBuffers stripped = readExr(path("full.exr"));
    stripped.remove(Layer::Noisy);
    writeExr(stripped, path("once.exr"));
    for (const std::string estimator : {"auto", "halves", "sure"}) {
        r = runEither("auto " + path("once.exr") + " --out " + path("twice.exr") + " --size 4" +
                      kClassicalFilters + " --estimator " + estimator);
        EXPECT_EQ(r.exitCode, 2) << estimator << "\n" << r.err;
        EXPECT_NE(r.err.find("once.exr"), std::string::npos) << r.err;
        EXPECT_NE(r.err.find("already denoised (denoiseFilter: auto)"), std::string::npos) << r.err;
        EXPECT_NE(r.err.find("--estimator image"), std::string::npos) << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
        EXPECT_FALSE(fs::exists(path("twice.exr")));
    }
    r = runEither("auto " + path("once.exr") + " --out " + path("twice.exr") + " --size 4" +
                  kClassicalFilters + " --estimator image");
    EXPECT_EQ(r.exitCode, 0) << r.err;
    EXPECT_TRUE(fs::exists(path("twice.exr")));
    EXPECT_FALSE(readExr(path("twice.exr")).has(Layer::Noisy));  // no render left to keep
}

TEST_F(AutoCli, OracleOfAnInputWithoutVarianceRunsAutoOnTheImageEstimate) {
    RunResult r = run("bank " + path("novariance.exr") + " --out " + path("bank") + " --size 4");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    r = runTool("glint-lab", "oracle " + path("novariance.exr") + " --reference " +
                                 path("ref.exr") + " --bank " + path("bank") + " --json");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const nlohmann::json j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["auto"]["estimator"], "image");
    EXPECT_GT(j["auto"]["ssim"].get<double>(), 0.0);
}

// --memory-limit sets the height of the selection's tiles (docs/auto-memory.md): one tile
// when the frame fits, many in a small limit, the same floats; it is parsed as every tool's
// size. --stream and --spill are gone (the one pipeline decides).
TEST_F(AutoCli, TheMemoryLimitTilesTheFrameWithTheSameResult) {
    // Taller than the lowest tile height, so that a small limit cuts it.
    FrameBuffers tall = testing::syntheticFrame(48, 160, 0.1f);
    tall.set(Layer::HalfColor, testing::syntheticFrame(48, 160, 0.1f, 2).color());
    for (Layer l : {Layer::Albedo, Layer::Normal, Layer::Depth, Layer::AlbedoVariance,
                    Layer::NormalVariance, Layer::DepthVariance})
        if (tall.has(l)) tall.set(*halfLayer(l), tall.layer(l));
    tall.ensure(Layer::HalfVariance);
    for (float& v : tall.ensure(Layer::SampleCount).data()) v = 2.0f;
    for (float& v : tall.ensure(Layer::HalfSampleCount).data()) v = 1.0f;
    writeExr(tall, path("tall.exr"));
    const std::string in = path("tall.exr") + " --size 6 --json" + kClassicalFilters;
    RunResult r = runEither("auto " + in + " --out " + path("whole.exr") + " --memory-limit 64G");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(nlohmann::json::parse(r.out)["tileRows"], 160);
    r = runEither("auto " + in + " --out " + path("tiled.exr") + " --memory-limit 1K");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_LT(nlohmann::json::parse(r.out)["tileRows"].get<int>(), 160);
    EXPECT_EQ(
        testing::maxAbsDiff(readExr(path("whole.exr")).color(), readExr(path("tiled.exr")).color()),
        0.0);
    for (const char* bad : {"0", "12Q", "-1"}) {
        r = runEither("auto " + in + " --out " + path("bad.exr") + " --memory-limit " + bad);
        EXPECT_EQ(r.exitCode, 2) << bad << "\n" << r.err;
        EXPECT_NE(r.err.find("--memory-limit"), std::string::npos) << r.err;
        EXPECT_FALSE(fs::exists(path("bad.exr")));
    }
    for (const char* gone : {"--stream on", "--spill off"}) {
        r = runEither("auto " + in + " --out " + path("gone.exr") + " " + gone);
        EXPECT_EQ(r.exitCode, 2) << gone << "\n" << r.err;
        EXPECT_FALSE(fs::exists(path("gone.exr")));
    }
}

// A bank folder's results are read when they fit in memory, else its members are applied again
// tile by tile (said on stderr): the same floats either way.
TEST_F(AutoCli, ABankFolderIsReadOrAppliedAgainWithTheSameResult) {
    RunResult r = run("bank " + path("halves.exr") + " --out " + path("bank") + " --size 6" +
                      kClassicalFilters);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const std::string bank = path("halves.exr") + " --bank " + path("bank") + " --json";
    r = runEither("auto " + bank + " --out " + path("read.exr"));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(r.err.find("applied again"), std::string::npos) << r.err;
    r = runEither("auto " + bank + " --out " + path("again.exr") + " --memory-limit 1K");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.err.find("applied again tile by tile"), std::string::npos) << r.err;
    EXPECT_EQ(
        testing::maxAbsDiff(readExr(path("read.exr")).color(), readExr(path("again.exr")).color()),
        0.0);
}

TEST_F(AutoCli, AChoiceOfTwoNamesTakesOneOfThem) {
    // `--margin` has two names (each, family): an option with a value, not a switch.
    const RunResult r = runEither("auto " + path("halves.exr") + " --out " + path("auto.exr") +
                                  " --size 6 --margin family --json" + kClassicalFilters);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_TRUE(nlohmann::json::accept(r.out)) << r.out;
    EXPECT_EQ(runEither("auto " + path("halves.exr") + " --out " + path("auto.exr") +
                        " --size 6 --margin" + kClassicalFilters)
                  .exitCode,
              2);
}

// The colour of an EXR auto wrote.
std::vector<float> colourOf(const fs::path& file) {
    const FrameBuffers frame = readExr(file);
    return {frame.color().data().begin(), frame.color().data().end()};
}

TEST_F(AutoCli, TheBalancedQualityIsTheDefaultBitForBit) {
    // The product's default, --quality balanced, and the lab's explicit former defaults (64
    // members, bank seed 1, no tuning) give the same floats.
    const std::string in = "auto " + path("halves.exr") + " --json" + kClassicalFilters;
    RunResult r = run(in + " --out " + path("default.exr"));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const nlohmann::json j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["quality"], "balanced");
    r = run(in + " --out " + path("balanced.exr") + " --quality balanced");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(nlohmann::json::parse(r.out)["members"], j["members"]);
    r = runTool("glint-lab", in + " --out " + path("lab.exr") + " --size 64 --bank-seed 1");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(nlohmann::json::parse(r.out)["members"], j["members"]);
    const std::vector<float> byDefault = colourOf(path("default.exr"));
    EXPECT_EQ(colourOf(path("balanced.exr")), byDefault);
    EXPECT_EQ(colourOf(path("lab.exr")), byDefault);
}

TEST_F(AutoCli, FastAndBestSetTheirBankSizeAndTuning) {
    const std::string in = "auto " + path("halves.exr") + " --json" + kClassicalFilters;
    RunResult r = run(in + " --out " + path("balanced.exr"));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const int balanced = nlohmann::json::parse(r.out)["members"].get<int>();
    // fast: 32 members fewer, half A filtered alone (no shortlist, no stacking).
    r = run(in + " --out " + path("fast.exr") + " --quality fast");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    nlohmann::json j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["quality"], "fast");
    EXPECT_EQ(j["members"].get<int>(), balanced - 32);
    EXPECT_EQ(j["oneSided"], 1);
    EXPECT_EQ(j["stack"], 0);
    // best: 64 members more, the tuning's defaults (the shortlist, the stacking).
    r = run(in + " --out " + path("best.exr") + " --quality best");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["members"].get<int>(), balanced + 64);
    EXPECT_EQ(j["quality"], "best");
    EXPECT_EQ(j["shortlist"], 16);
    EXPECT_EQ(j["oneSided"], 0);
    EXPECT_GE(j["stack"].get<int>(), 1);
    EXPECT_NE(colourOf(path("fast.exr")), colourOf(path("balanced.exr")));
    EXPECT_NE(colourOf(path("best.exr")), colourOf(path("balanced.exr")));
    // A lab flag over a quality: the lab's --stack cannot stack one-sided halves.
    r = runTool("glint-lab", in + " --out " + path("o.exr") + " --quality fast --stack 2");
    EXPECT_EQ(r.exitCode, 2) << r.err;
    EXPECT_NE(r.err.find("one-sided"), std::string::npos) << r.err;
}

TEST_F(AutoCli, TheProductsAutoHasNoTuningFlags) {
    const RunResult help = run("auto --help");
    ASSERT_EQ(help.exitCode, 0) << help.err;
    EXPECT_NE(help.out.find("--quality"), std::string::npos) << help.out;
    for (const char* lab : {"--window", "--stack", "--size", "--one-sided", "--tuning-table",
                            "--choice-map", "--noise-out", "--bank-seed"})
        EXPECT_EQ(help.out.find(lab), std::string::npos) << lab << "\n" << help.out;
    // Given anyway, it is refused in one line naming it; glint-lab takes it.
    const RunResult r =
        run("auto " + path("noisy.exr") + " --out " + path("o.exr") + " --window 4");
    EXPECT_EQ(r.exitCode, 2) << r.err;
    EXPECT_NE(r.err.find("--window"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(path("o.exr")));
}

TEST_F(AutoCli, BadInputExitsTwoWithOneClearLineAndWritesNothing) {
    struct Case {
        std::string args;
        std::vector<std::string> mentions;
    };
    const std::string out = " --out " + path("out.exr");
    const Case cases[] = {
        {"auto " + path("novariance.exr") + out + " --estimator sure",
         {"novariance.exr", "layer 'variance'", "variance.R", "SURE"}},
        {"auto " + path("nan.exr") + out, {"nan.exr", "pixel (7, 4), channel B", "NaN"}},
        {"auto " + path("noisy.exr") + out + " --estimator halves",
         {"noisy.exr", "layer 'halfColor'", "halfBuffers=true"}},
        {"auto " + path("noisy.exr") + out + " --estimator stein",
         {"--estimator", "auto, sure, halves or image"}},
        {"auto " + path("noisy.exr") + out + " --quality great",
         {"--quality", "fast, balanced or best"}},
        {"auto " + path("noisy.exr") + " --out " + path("out.png"), {"--out", ".exr"}},
        {"auto " + path("noisy.exr") + out + " --window -1", {"--window"}},
        {"auto " + path("noisy.exr") + out + " --temperature -2", {"--temperature"}},
        {"auto " + path("noisy.exr") + out + " --epsilon 0", {"--epsilon"}},
        {"auto " + path("noisy.exr") + out + " --shortlist -1", {"--shortlist", "0 … 4096"}},
        {"auto " + path("noisy.exr") + out + " --finer 9", {"--finer", "0 … 6"}},
        {"auto " + path("noisy.exr") + out + " --feather 33", {"--feather", "0 … 32"}},
        {"auto " + path("noisy.exr") + out + " --feather-gate 0",
         {"--feather-gate", "1e-06 … 1000000"}},
        {"auto " + path("noisy.exr") + out + " --stack 17", {"--stack", "0 … 16"}},
        {"auto " + path("noisy.exr") + out + " --stack 2", {"--stack", "halves estimator"}},
        {"auto " + path("halves.exr") + out + " --stack 2 --one-sided", {"--stack", "one-sided"}},
        {"auto " + path("noisy.exr") + out + " --stack-window 0", {"--stack-window", "1 … 64"}},
        {"auto " + path("noisy.exr") + out + " --stack-ridge -1", {"--stack-ridge", "0 … 1000000"}},
        {"auto " + path("noisy.exr") + out + " --stack-smooth 65", {"--stack-smooth", "0 … 64"}},
        {"auto " + path("noisy.exr") + out + " --stack-floor -0.1", {"--stack-floor", "0 … 100"}},
        {"auto " + path("noisy.exr") + out + " --stack-albedo depth",
         {"--stack-albedo", "auto, on, off"}},
        {"auto " + path("noisy.exr") + out + " --stack-feature-window 0",
         {"--stack-feature-window", "1 … 64"}},
        {"auto " + path("noalbedo.exr") + out + " --stack-albedo on",
         {"noalbedo.exr", "layer 'albedo'", "--stack-albedo"}},
        {"auto " + path("noisy.exr") + out + " --space gamma",
         {"--space", "display, display-tangent, display-exact, linear"}},
        {"auto " + path("noisy.exr") + out + " --space display-exact",
         {"--space", "halves estimator"}},
        {"auto " + path("noisy.exr") + out + " --bank " + path("nobank"), {"nobank", "--bank"}},
        {"auto " + path("noisy.exr") + out + " --size 0", {"--size"}},
        {"auto " + path("nope.exr") + out, {"nope.exr"}},
        {"auto " + path("noisy.exr") + out + " --reference " + path("nope.exr"), {"nope.exr"}},
        {"auto " + path("noisy.exr") + out + " --choice-map " + path("c.jpg"), {"--choice-map"}},
    };
    for (const Case& c : cases) {
        const RunResult r = runEither(c.args);
        EXPECT_EQ(r.exitCode, 2) << c.args << "\n" << r.err;
        for (const std::string& m : c.mentions)
            EXPECT_NE(r.err.find(m), std::string::npos) << c.args << "\n" << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
        EXPECT_FALSE(fs::exists(path("out.exr"))) << c.args;
        EXPECT_FALSE(fs::exists(path("out.png"))) << c.args;
        // No temporary file either.
        for (const auto& e : fs::directory_iterator(m_dir))
            EXPECT_EQ(e.path().filename().string().find(".tmp-"), std::string::npos) << e.path();
    }
}

}  // namespace
}  // namespace glint::denoise

// glint-denoise end to end: runs the binary built beside this test (build/bin/) on small EXRs.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>

#include "cli_fixture.h"
#include "glint/denoise/filter.h"
#include "glint/denoise/prefilter.h"
#include "glint/denoise/registry.h"
#include "glint/image/io.h"
#include "synthetic_frames.h"

namespace glint::denoise {
namespace {

namespace fs = std::filesystem;

using glint::testing::RunResult;

class DenoiseCli : public glint::testing::CliFixture {
  protected:
    DenoiseCli() : CliFixture("glint-denoise") {}
    void SetUp() override {
        CliFixture::SetUp();
        if (HasFatalFailure()) return;
        // A noisy frame with every layer, its clean reference, and a colour-only frame.
        writeExr(testing::syntheticFrame(40, 32, 0.1f), m_dir / "noisy.exr");
        writeExr(testing::syntheticFrame(40, 32, 0.0f), m_dir / "ref.exr");
        FrameBuffers bare(40, 32);
        bare.color() = testing::syntheticFrame(40, 32, 0.1f).color();
        writeExr(bare, m_dir / "bare.exr");
    }
};

TEST_F(DenoiseCli, ListPrintsEveryFilterAndItsParameters) {
    const RunResult r = run("list");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    for (const Filter* f : allFilters()) {
        EXPECT_NE(r.out.find(std::string(f->name())), std::string::npos) << f->name();
        for (const ParamSpec& s : f->params())
            EXPECT_NE(r.out.find(s.name), std::string::npos) << f->name() << "." << s.name;
    }
    // The prefilter's parameters are listed too.
    for (const ParamSpec& s : prefilterParams()) EXPECT_NE(r.out.find(s.name), std::string::npos);
    const RunResult j = run("list --json");
    ASSERT_EQ(j.exitCode, 0);
    const nlohmann::json list = nlohmann::json::parse(j.out);
    EXPECT_EQ(list["filters"].size(), allFilters().size());
    EXPECT_EQ(list["prefilter"]["params"].size(), prefilterParams().size());
    // A choice parameter lists its options.
    bool sawChoice = false;
    for (const auto& f : list["filters"])
        for (const auto& p : f["params"])
            if (p.contains("choices")) {
                sawChoice = true;
                EXPECT_GE(p["choices"].size(), 2u);
            }
    EXPECT_TRUE(sawChoice);
}

TEST_F(DenoiseCli, ChoiceParametersTakeTheirOptionNames) {
    const RunResult r =
        run("apply " + path("noisy.exr") +
            " --filter guided --param guide=albedo --param radius=3 --out " + path("guided.exr"));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const FrameBuffers in = readExr(path("noisy.exr"));
    const Image expect = applyFilter(findFilter("guided"), in, {{"guide", 1}, {"radius", 3}});
    EXPECT_LT(testing::maxAbsDiff(readExr(path("guided.exr")).color(), expect), 1e-6);
}

TEST_F(DenoiseCli, ApplyWritesTheFilteredColourAndKeepsTheOtherLayers) {
    const RunResult r =
        run("apply " + path("noisy.exr") +
            " --filter bilateral --param sigmaS=2 --param sigmaR=0.3 --out " + path("out.exr"));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const FrameBuffers in = readExr(path("noisy.exr"));
    const FrameBuffers out = readExr(path("out.exr"));
    const Image expect =
        applyFilter(findFilter("bilateral"), in, {{"sigmaS", 2.0}, {"sigmaR", 0.3}});
    EXPECT_LT(testing::maxAbsDiff(out.color(), expect), 1e-6);
    ASSERT_TRUE(out.has(Layer::Albedo));
    EXPECT_EQ(testing::maxAbsDiff(out.layer(Layer::Albedo), in.layer(Layer::Albedo)), 0.0);
    EXPECT_TRUE(out.has(Layer::DepthVariance));
}

TEST_F(DenoiseCli, ReferenceMetricsInJsonAndRoiKeepsTheRest) {
    const RunResult r = run("apply " + path("noisy.exr") +
                            " --filter gaussian --param sigma=1.5 --roi 4,30,2,28 --out " +
                            path("out.exr") + " --reference " + path("ref.exr") + " --json");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const nlohmann::json j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["filter"], "gaussian");
    EXPECT_GT(j["metrics"]["ssim"].get<double>(), j["metricsInput"]["ssim"].get<double>());
    EXPECT_GT(j["metrics"]["psnr"].get<double>(), j["metricsInput"]["psnr"].get<double>());
    const FrameBuffers in = readExr(path("noisy.exr"));
    const FrameBuffers out = readExr(path("out.exr"));
    EXPECT_EQ(out.color()(0, 0, 0), in.color()(0, 0, 0));      // outside the roi
    EXPECT_NE(out.color()(10, 10, 0), in.color()(10, 10, 0));  // inside
}

TEST_F(DenoiseCli, ReferenceWithARegionSmallerThanTheSsimWindowStillWorks) {
    // SSIM needs 11x11 pixels; a smaller --roi with --reference used to fail (exit 2) after
    // OUT had already been written. Now SSIM is reported as null and the rest as usual.
    for (const std::string json : {" --json", ""}) {
        const RunResult r =
            run("apply " + path("noisy.exr") + " --filter gaussian --roi 4,10,2,8 --out " +
                path("small.exr") + " --reference " + path("ref.exr") + json);
        ASSERT_EQ(r.exitCode, 0) << r.err;
        EXPECT_TRUE(fs::exists(path("small.exr")));
        if (json.empty()) continue;
        const nlohmann::json j = nlohmann::json::parse(r.out);
        EXPECT_TRUE(j["metrics"]["ssim"].is_null());
        EXPECT_TRUE(j["metrics"]["psnr"].is_number());
    }
}

TEST_F(DenoiseCli, BadInputExitsTwoWithAClearMessage) {
    const std::string in = path("noisy.exr"), out = path("bad.exr");
    struct Case {
        std::string args, mention;
    };
    const Case cases[] = {
        {"apply " + in + " --filter gausian --out " + out, "bilateral-mc"},
        {"apply " + in + " --filter gaussian --param sigm=2 --out " + out, "sigma"},
        {"apply " + in + " --filter gaussian --param sigma=-1 --out " + out, "range"},
        {"apply " + in + " --filter gaussian --param sigma --out " + out, "name=value"},
        {"apply " + in + " --filter guided --param guide=albedos --out " + out, "normal"},
        {"apply " + in + " --filter gaussian --param sigma=abc --out " + out, "not a number"},
        {"apply " + in + " --filter gaussian --roi 0,50,0,5 --out " + out, "outside"},
        {"apply " + in + " --filter gaussian --roi 4294967301,6,0,5 --out " + out, "four integers"},
        {"apply " + path("nope.exr") + " --filter gaussian --out " + out, "nope.exr"},
        {"apply " + in + " --filter gaussian --reference " + path("nope.exr") + " --out " + out,
         "nope.exr"},
        {"apply " + in + " --filter gaussian --prefilter --param prefilter.foo=1 --out " + out,
         "varianceScale"},
        {"apply " + in + " --filter gaussian --param prefilter.radius=2 --out " + out,
         "without --prefilter"},
    };
    for (const Case& c : cases) {
        const RunResult r = run(c.args);
        EXPECT_EQ(r.exitCode, 2) << c.args;
        EXPECT_NE(r.err.find(c.mention), std::string::npos) << c.args << "\n" << r.err;
        EXPECT_FALSE(fs::exists(out)) << c.args;
    }
    // A metric that cannot be computed (a reference that is NaN everywhere) names both files.
    {
        FrameBuffers nan = testing::syntheticFrame(40, 32, 0.0f);
        nan.color().fill(std::numeric_limits<float>::quiet_NaN());
        writeExr(nan, path("nan.exr"));
        const RunResult r = run("apply " + in + " --filter gaussian --reference " +
                                path("nan.exr") + " --out " + out);
        EXPECT_EQ(r.exitCode, 2) << r.err;
        EXPECT_NE(r.err.find("noisy.exr"), std::string::npos) << r.err;
        EXPECT_NE(r.err.find("nan.exr"), std::string::npos) << r.err;
        EXPECT_FALSE(fs::exists(out));
    }
    // A filter that needs feature layers names the missing ones and the file.
    for (const Filter* f : allFilters()) {
        if (f->requiredLayers(resolveParams(*f, {})).empty()) continue;
        const RunResult r = run("apply " + path("bare.exr") + " --filter " +
                                std::string(f->name()) + " --out " + out);
        EXPECT_EQ(r.exitCode, 2) << f->name();
        EXPECT_NE(r.err.find("missing"), std::string::npos) << r.err;
        EXPECT_NE(r.err.find("bare.exr"), std::string::npos) << r.err;
    }
}

}  // namespace
}  // namespace glint::denoise

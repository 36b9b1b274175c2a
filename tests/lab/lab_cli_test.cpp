// glint-lab oracle | navigate end to end over a bank glint-denoise built, good and bad input.
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "cli_fixture.h"
#include "glint/image/io.h"
#include "synthetic_frames.h"

namespace glint::lab {
namespace {

namespace fs = std::filesystem;
using glint::testing::RunResult;
namespace testing = glint::denoise::testing;

class LabCli : public glint::testing::CliFixture {
  protected:
    LabCli() : CliFixture("glint-lab") {}
    void SetUp() override {
        CliFixture::SetUp();
        if (HasFatalFailure()) return;
        writeExr(testing::syntheticFrame(48, 40, 0.1f), m_dir / "noisy.exr");
        writeExr(testing::syntheticFrame(48, 40, 0.0f), m_dir / "ref.exr");
        writeExr(testing::syntheticFrame(48, 40, 0.1f, 99), m_dir / "other.exr");
    }
    std::string bank() const { return path("bank"); }
    RunResult build(const std::string& extra = "") const {
        return runTool("glint-denoise", "bank " + path("noisy.exr") + " --out " + bank() +
                                            " --size 10 --json" + extra);
    }
};

TEST_F(LabCli, OracleAndNavigateOverABank) {
    RunResult r = build();
    ASSERT_EQ(r.exitCode, 0) << r.err;
    nlohmann::json j;
    r = run("oracle " + path("noisy.exr") + " --reference " + path("ref.exr") + " --bank " +
            bank() + " --choice-map " + path("choice.png") + " --json");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    j = nlohmann::json::parse(r.out);
    EXPECT_GT(j["bestSingle"].get<double>(), j["noisy"].get<double>());
    EXPECT_GE(j["perPixel"].get<double>(), j["bestSingle"].get<double>() - 0.02);
    EXPECT_EQ(j["best3Members"].size(), 3u);
    EXPECT_TRUE(fs::exists(path("choice.png")));

    r = run("navigate " + path("noisy.exr") + " --reference " + path("ref.exr") + " --bank " +
            bank() + " --simulate --json");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    j = nlohmann::json::parse(r.out);
    ASSERT_FALSE(j["choices"].empty());
    EXPECT_GT(j["choices"].back()["ssim"].get<double>(), j["noisy"].get<double>());
    EXPECT_EQ(j["region"], nlohmann::json::parse("[0, 48, 0, 40]"));  // the bank's
    // Text output names the choices.
    r = run("navigate " + path("noisy.exr") + " --reference " + path("ref.exr") + " --bank " +
            bank() + " --simulate --roi 0,30,0,30");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find("choice 1"), std::string::npos) << r.out;
}

TEST_F(LabCli, BadInputExitsTwoNamingTheFlagAndWritesNothing) {
    struct Case {
        std::string args, mention;
    };
    const std::string in = path("noisy.exr");
    ASSERT_EQ(build().exitCode, 0);
    const std::string ref = " --reference " + path("ref.exr");
    const Case using_[] = {
        {"navigate " + in + ref + " --bank " + bank() + " --simulate --k 1", "--k"},
        {"navigate " + in + ref + " --bank " + bank() + " --simulate --p 1.5", "--p"},
        {"navigate " + in + ref + " --bank " + bank() + " --simulate --p 0", "--p"},
        {"navigate " + in + ref + " --bank " + bank() + " --simulate --roi 0,60,0,10", "outside"},
        {"navigate " + in + ref + " --bank " + bank() + " --simulate --distance l1", "mse"},
        {"navigate " + path("other.exr") + ref + " --bank " + bank() + " --simulate",
         "another image"},
        {"oracle " + path("other.exr") + ref + " --bank " + bank(), "another image"},
        {"oracle " + in + ref + " --bank " + path("nobank"), "nobank"},
        {"oracle " + in + ref + " --bank " + bank() + " --choice-map " + path("c.jpg"), ".png"},
    };
    for (const Case& c : using_) {
        const RunResult r = run(c.args);
        EXPECT_EQ(r.exitCode, 2) << c.args;
        EXPECT_NE(r.err.find(c.mention), std::string::npos) << c.args << "\n" << r.err;
    }
    EXPECT_FALSE(fs::exists(path("c.jpg")));
}

}  // namespace
}  // namespace glint::lab

// glint-denoise bank end to end, good and bad input (oracle and navigate: tests/lab/).
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "cli_fixture.h"
#include "glint/denoise/registry.h"
#include "glint/image/io.h"
#include "synthetic_frames.h"

namespace glint::denoise {
namespace {

namespace fs = std::filesystem;
using glint::testing::RunResult;

class BankCli : public glint::testing::CliFixture {
  protected:
    BankCli() : CliFixture("glint-denoise") {}
    void SetUp() override {
        CliFixture::SetUp();
        if (HasFatalFailure()) return;
        writeExr(testing::syntheticFrame(48, 40, 0.1f), m_dir / "noisy.exr");
        writeExr(testing::syntheticFrame(48, 40, 0.0f), m_dir / "ref.exr");
        writeExr(testing::syntheticFrame(48, 40, 0.1f, 99), m_dir / "other.exr");
    }
    std::string bank() const { return path("bank"); }
    RunResult build(const std::string& extra = "") const {
        return run("bank " + path("noisy.exr") + " --out " + bank() + " --size 10 --json" + extra);
    }
};

TEST_F(BankCli, BankThenReopenFromTheCache) {
    RunResult r = build();
    ASSERT_EQ(r.exitCode, 0) << r.err;
    nlohmann::json j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["members"], 10 + defaultBankFilters().size());  // 10 + the defaults
    EXPECT_EQ(j["cached"], 0);
    EXPECT_EQ(j["region"], nlohmann::json::parse("[0, 48, 0, 40]"));  // x0, x1, y0, y1
    EXPECT_TRUE(fs::exists(fs::path(bank()) / "index.json"));
    r = build();
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(nlohmann::json::parse(r.out)["cached"], j["members"]);  // every member
}

TEST_F(BankCli, BadInputExitsTwoNamingTheFlagAndWritesNothing) {
    struct Case {
        std::string args, mention;
    };
    const std::string in = path("noisy.exr");
    const Case building[] = {
        {"bank " + in + " --out " + bank() + " --size 0", "--size"},
        {"bank " + in + " --out " + bank() + " --size 5000", "4096"},
        {"bank " + in + " --out " + bank() + " --filters gaussian,gausian", "bilateral-mc"},
        {"bank " + in + " --out " + bank() + " --roi 0,100,0,10", "outside"},
        {"bank " + in + " --out " + bank() + " --roi 5,5,0,10", "empty"},
        {"bank " + path("nope.exr") + " --out " + bank(), "nope.exr"},
    };
    for (const Case& c : building) {
        const RunResult r = run(c.args);
        EXPECT_EQ(r.exitCode, 2) << c.args;
        EXPECT_NE(r.err.find(c.mention), std::string::npos) << c.args << "\n" << r.err;
        EXPECT_FALSE(fs::exists(bank())) << c.args;
    }
}

}  // namespace
}  // namespace glint::denoise

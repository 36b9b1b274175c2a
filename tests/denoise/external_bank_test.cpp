// A bank with fixed parameters of a filter (BankOptions::filterParams, glint-denoise
// --filter-param): an external member given its command, the members of a bank that cannot run
// here (an external program not allowed) left out without running, whether the bank is built or
// a folder opened, from the library and the CLI (docs/external-denoiser.md, "In a bank").
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <set>
#include <string>

#include "bank/bank_detail.h"
#include "cli_fixture.h"
#include "external_stub.h"
#include "glint/denoise/bank.h"
#include "glint/denoise/registry.h"
#include "glint/image/error.h"
#include "glint/image/io.h"
#include "synthetic_frames.h"

namespace glint::denoise {
namespace {

namespace fs = std::filesystem;
using testing::stubCommand;
using testing::stubParams;
using testing::stubPath;

// A bank of gaussian members and the stub as its external member (creating `marker` if given).
BankOptions externalBank(const std::string& marker = {}) {
    BankOptions o;
    o.size = 3;
    o.filters = {"gaussian", "external"};
    o.filterParams["external"] = stubParams("good", "exr", marker);
    return o;
}

// The external members of a bank.
std::size_t externalMembers(const FilterBank& bank) {
    return std::size_t(std::count_if(bank.members().begin(), bank.members().end(),
                                     [](const BankMember& m) { return m.filter == "external"; }));
}

class ExternalBank : public testing::ExternalSandbox {};

TEST_F(ExternalBank, HoldsTheExternalFilterWithItsFixedCommandAsOneMember) {
    const FrameBuffers frame = testing::syntheticFrame(12, 9);
    const FilterBank bank = buildBank(frame, externalBank());
    ASSERT_EQ(externalMembers(bank), 1u);
    EXPECT_TRUE(bank.unavailable().empty());
    for (std::size_t i = 0; i < bank.size(); ++i) {
        if (bank.members()[i].filter != "external") continue;
        EXPECT_EQ(bank.members()[i].params.strings.at("command"), stubCommand("good"));
        EXPECT_EQ(bank.result(i)(5, 4, 1), frame.color()(5, 4, 1) * 0.5f);
    }
    EXPECT_TRUE(temporaryFolderEmpty());
}

TEST(FixedBankParams, HoldInEveryMemberOfTheirFilterWhileTheOthersAreSampled) {
    ParamValues fixed{{"sigmaS", 2.0}};
    const std::vector<BankMember> members =
        detail::sampleBank({&findFilter("bilateral")}, 16, 5, {{"bilateral", fixed}});
    std::set<double> ranges;
    for (const BankMember& m : members) {
        EXPECT_EQ(m.params.at("sigmaS"), 2.0);
        ranges.insert(m.params.at("sigmaR"));
    }
    EXPECT_GT(ranges.size(), 8u) << "sigmaR is no longer sampled";
    EXPECT_EQ(members.size(), 17u);
}

TEST(FixedBankParams, AreRefusedForAFilterNotInTheBankOrUnknownToIt) {
    BankOptions o = externalBank();
    o.filters = {"gaussian"};
    try {
        validate(o);
        ADD_FAILURE() << "parameters of a filter the bank does not hold were accepted";
    } catch (const Error& e) {
        EXPECT_EQ(e.where(), "--filter-param");
        EXPECT_NE(std::string(e.what()).find("'external'"), std::string::npos) << e.what();
    }
    o = externalBank();
    o.filterParams["gaussian"] = ParamValues{{"nosuch", 1.0}};
    try {
        validate(o);
        ADD_FAILURE() << "an unknown parameter was accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("nosuch"), std::string::npos) << e.what();
    }
}

TEST_F(ExternalBank, AMemberWhoseProgramIsNotAllowedIsLeftOutWithoutRunning) {
    const fs::path marker = m_dir / "ran";
    clearAllowedCommands();
    BankOptions o = externalBank(marker.string());
    o.cacheDir = m_dir / "bank";
    fs::create_directories(o.cacheDir);
    const FilterBank bank = buildBank(testing::syntheticFrame(12, 9), o);
    EXPECT_FALSE(fs::exists(marker));
    EXPECT_EQ(externalMembers(bank), 0u);
    EXPECT_GT(bank.size(), 0u);
    ASSERT_EQ(bank.unavailable().size(), 1u);
    EXPECT_EQ(bank.unavailable()[0].member.filter, "external");
    EXPECT_NE(bank.unavailable()[0].reason.find("--allow-command " + stubPath().string()),
              std::string::npos)
        << bank.unavailable()[0].reason;
    // The folder's index says so and keeps the command for a reader who allows it.
    const nlohmann::json index =
        nlohmann::json::parse(glint::testing::slurp(o.cacheDir / "index.json"));
    ASSERT_EQ(index["unavailable"].size(), 1u);
    EXPECT_EQ(index["unavailable"][0]["filter"], "external");
    EXPECT_EQ(readBankOptions(o.cacheDir).filterParams.at("external").strings.at("command"),
              stubCommand("good", "exr", marker.string()));
    // A bank of that member alone cannot run at all: one error saying how to allow it.
    o.filters = {"external"};
    o.cacheDir.clear();
    try {
        buildBank(testing::syntheticFrame(12, 9), o);
        ADD_FAILURE() << "a bank of no runnable member was built";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::InvalidArgument);
        EXPECT_NE(std::string(e.what()).find("--allow-command"), std::string::npos) << e.what();
    }
    EXPECT_FALSE(fs::exists(marker));
    EXPECT_TRUE(temporaryFolderEmpty());
}

TEST_F(ExternalBank, AFolderNamingAProgramOpensWithoutRunningItUnlessAllowed) {
    const fs::path marker = m_dir / "ran";
    const FrameBuffers frame = testing::syntheticFrame(12, 9);
    BankOptions o = externalBank(marker.string());
    o.cacheDir = m_dir / "bank";
    fs::create_directories(o.cacheDir);
    buildBank(frame, o);
    ASSERT_TRUE(fs::exists(marker));
    fs::remove(marker);
    // The member's result is in the folder, but opening it without the allowance reads nothing
    // of it and runs nothing.
    clearAllowedCommands();
    const FilterBank closed = openBank(frame, o.cacheDir);
    EXPECT_FALSE(fs::exists(marker));
    EXPECT_EQ(externalMembers(closed), 0u);
    ASSERT_EQ(closed.unavailable().size(), 1u);
    EXPECT_NE(closed.unavailable()[0].reason.find("not allowed"), std::string::npos);
    allowCommand(stubPath());
    const FilterBank open = openBank(frame, o.cacheDir);
    EXPECT_EQ(externalMembers(open), 1u);
    EXPECT_TRUE(open.unavailable().empty());
    EXPECT_EQ(open.cacheHits(), open.size()) << "the allowed member is read from the folder";
    EXPECT_TRUE(temporaryFolderEmpty());
}

// ---- the CLI ---------------------------------------------------------------------------------

class ExternalBankCli : public glint::testing::CliFixture {
  protected:
    ExternalBankCli() : CliFixture("glint-denoise") {}
    void SetUp() override {
        CliFixture::SetUp();
        writeExr(testing::syntheticFrame(16, 12), m_dir / "in.exr");
    }
    // Runs glint-denoise (glint-lab for auto, whose --size it takes) with no allowed-commands
    // file of the user's (XDG_CONFIG_HOME here).
    glint::testing::RunResult denoise(const std::string& args) const {
        return runEither("XDG_CONFIG_HOME=" + m_dir.string(), args);
    }
    // --filter-param giving the external member the stub, creating `marker`.
    std::string externalParam(const fs::path& marker) const {
        return "--filters gaussian,external --filter-param 'external.command=" +
               nlohmann::json(stubCommand("good", "exr", marker.string())).dump() + "'";
    }
    std::string allow() const { return " --allow-command " + stubPath().string(); }
};

// One line on stderr saying that the external member is unavailable and how to allow it.
void expectOneUnavailableWarning(const std::string& err) {
    const std::string allow = "--allow-command " + stubPath().string();
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
    EXPECT_NE(err.find("external"), std::string::npos) << err;
    EXPECT_NE(err.find("unavailable"), std::string::npos) << err;
    EXPECT_NE(err.find(allow), std::string::npos) << err;
}

TEST_F(ExternalBankCli, BankTakesTheCommandByFilterParamAndRunsItOnlyWhenAllowed) {
    const fs::path marker = m_dir / "ran";
    const std::string bank = "bank " + path("in.exr") + " --size 3 --json " + externalParam(marker);
    const glint::testing::RunResult refused = denoise(bank + " --out " + path("closed"));
    ASSERT_EQ(refused.exitCode, 0) << refused.err;
    EXPECT_FALSE(fs::exists(marker));
    expectOneUnavailableWarning(refused.err);
    const nlohmann::json closed = nlohmann::json::parse(refused.out);
    EXPECT_EQ(closed["unavailable"][0]["params"]["command"][0], stubPath().string());

    const glint::testing::RunResult allowed = denoise(bank + " --out " + path("open") + allow());
    ASSERT_EQ(allowed.exitCode, 0) << allowed.err;
    EXPECT_TRUE(fs::exists(marker));
    EXPECT_TRUE(allowed.err.empty()) << allowed.err;
    const nlohmann::json open = nlohmann::json::parse(allowed.out);
    EXPECT_FALSE(open.contains("unavailable"));
    int external = 0;
    for (const nlohmann::json& m : open["list"])
        if (m["filter"] == "external") {
            ++external;
            EXPECT_EQ(m["params"]["command"][0], stubPath().string());
        }
    EXPECT_EQ(external, 1);
}

TEST_F(ExternalBankCli, NavigateAndAutoOpenAFolderWithoutRunningAProgramNotAllowed) {
    const fs::path marker = m_dir / "ran";
    const glint::testing::RunResult built =
        denoise("bank " + path("in.exr") + " --size 3 --out " + path("bank") + " " +
                externalParam(marker) + allow());
    ASSERT_EQ(built.exitCode, 0) << built.err;
    fs::remove(marker);
    writeExr(testing::syntheticFrame(16, 12, 0.0f), m_dir / "ref.exr");
    const glint::testing::RunResult navigated =
        denoise("navigate " + path("in.exr") + " --bank " + path("bank") + " --reference " +
                path("ref.exr") + " --simulate --json");
    ASSERT_EQ(navigated.exitCode, 0) << navigated.err;
    EXPECT_FALSE(fs::exists(marker));
    expectOneUnavailableWarning(navigated.err);
    EXPECT_EQ(nlohmann::json::parse(navigated.out)["unavailable"].size(), 1u);

    const glint::testing::RunResult automatic =
        denoise("auto " + path("in.exr") + " --bank " + path("bank") + " --estimator sure --out " +
                path("auto.exr") + " --json");
    ASSERT_EQ(automatic.exitCode, 0) << automatic.err;
    EXPECT_FALSE(fs::exists(marker));
    expectOneUnavailableWarning(automatic.err);
    EXPECT_EQ(nlohmann::json::parse(automatic.out)["unavailable"].size(), 1u);
}

TEST_F(ExternalBankCli, AutoBuildsItsBankWithTheFilterParamAsBankDoes) {
    const fs::path marker = m_dir / "ran";
    const std::string args = "auto " + path("in.exr") + " --size 3 --estimator sure --json " +
                             externalParam(marker) + " --out " + path("auto.exr");
    const glint::testing::RunResult refused = denoise(args);
    ASSERT_EQ(refused.exitCode, 0) << refused.err;
    EXPECT_FALSE(fs::exists(marker));
    expectOneUnavailableWarning(refused.err);
    const glint::testing::RunResult allowed = denoise(args + allow());
    ASSERT_EQ(allowed.exitCode, 0) << allowed.err;
    EXPECT_TRUE(fs::exists(marker));
    EXPECT_FALSE(nlohmann::json::parse(allowed.out).contains("unavailable"));
}

TEST_F(ExternalBankCli, ABadFilterParamIsOneLineAndExit2BeforeAnyWork) {
    for (const std::string& bad :
         {std::string("--filter-param nodot=1"), std::string("--filter-param external.nosuch=1"),
          std::string("--filter-param nosuchfilter.x=1"),
          std::string("--filter-param gaussian.sigma=-3")}) {
        SCOPED_TRACE(bad);
        const glint::testing::RunResult r =
            denoise("bank " + path("in.exr") + " --out " + path("bank") +
                    " --filters gaussian,external " + bad);
        EXPECT_EQ(r.exitCode, 2) << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
        EXPECT_NE(r.err.find("--filter-param"), std::string::npos) << r.err;
        EXPECT_FALSE(fs::exists(m_dir / "bank"));
    }
}

}  // namespace
}  // namespace glint::denoise

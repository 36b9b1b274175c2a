// glint-denoise bank --members a:b as glint-farm runs it (docs/distributed.md, "Sharded banks"):
// two ranges computed into one folder complete index.json, byte for byte that of one build; a
// range past the end computes nothing; a malformed or reversed range exits 2 with one line
// naming --members and writes nothing.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "cli_fixture.h"
#include "glint/image/io.h"
#include "synthetic_frames.h"

namespace glint::denoise {
namespace {

namespace fs = std::filesystem;
using glint::testing::RunResult;

std::string bytes(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

/// Partial indices (index.members-a-b.json) left in a bank folder.
int partialIndices(const fs::path& dir) {
    int count = 0;
    for (const fs::directory_entry& e : fs::directory_iterator(dir))
        count += e.path().filename().string().rfind("index.members-", 0) == 0;
    return count;
}

class BankMembersCli : public glint::testing::CliFixture {
  protected:
    BankMembersCli() : CliFixture("glint-denoise") {}
    void SetUp() override {
        CliFixture::SetUp();
        if (HasFatalFailure()) return;
        writeExr(testing::syntheticFrame(24, 20, 0.1f), m_dir / "noisy.exr");
    }
    /// A bank of 7 Latin-hypercube members over 3 filters (10 members) into `folder`.
    RunResult bank(const std::string& folder, const std::string& extra = "") const {
        return run("bank " + path("noisy.exr") + " --size 7 --seed 3 --filters " +
                   "gaussian,bilateral,cross-bilateral --json --out " + path(folder) + extra);
    }
};

TEST_F(BankMembersCli, TwoRangesCompleteTheIndexOfOneBuild) {
    RunResult r = bank("whole");
    ASSERT_EQ(r.exitCode, 0) << r.err;

    // The first range: its members and a partial index, no index.json yet.
    r = bank("parts", " --members 0:4");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    nlohmann::json j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["members"], 4);
    EXPECT_EQ(j["firstMember"], 0);
    EXPECT_EQ(j["bankMembers"], 10);
    EXPECT_EQ(j["indexWritten"], false);
    EXPECT_FALSE(fs::exists(fs::path(path("parts")) / "index.json"));
    EXPECT_EQ(partialIndices(path("parts")), 1);

    // The second range (its end past the bank's, clamped) completes the bank.
    r = bank("parts", " --members 4:100");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["members"], 6);
    EXPECT_EQ(j["firstMember"], 4);
    EXPECT_EQ(j["indexWritten"], true);
    const std::string index = bytes(fs::path(path("parts")) / "index.json");
    EXPECT_EQ(index, bytes(fs::path(path("whole")) / "index.json"));
    EXPECT_EQ(partialIndices(path("parts")), 0);

    // A range past the end computes nothing and leaves index.json as it is.
    r = bank("parts", " --members 50:60");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["members"], 0);
    EXPECT_EQ(j["computed"], 0);
    EXPECT_EQ(bytes(fs::path(path("parts")) / "index.json"), index);
    // ... and, as the cache already holds every member, completes it again: no partial index
    // is left behind.
    EXPECT_EQ(j["indexWritten"], true);
    EXPECT_EQ(partialIndices(path("parts")), 0);

    // The folder opens as the whole bank, every member from the cache.
    r = bank("parts");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["members"], 10);
    EXPECT_EQ(j["cached"], 10);
}

TEST_F(BankMembersCli, BadRangesExitTwoNamingMembersAndWriteNothing) {
    for (const std::string range : {"5:3", "-1:2", "3", "a:4", "2:", ":2", "1:2:3", "0x1:4"}) {
        const RunResult r = bank("bad", " --members=" + range);
        EXPECT_EQ(r.exitCode, 2) << range;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << range << "\n" << r.err;
        EXPECT_NE(r.err.find("--members"), std::string::npos) << range << "\n" << r.err;
        EXPECT_NE(r.err.find(range), std::string::npos) << range << "\n" << r.err;
        EXPECT_TRUE(r.out.empty()) << range << "\n" << r.out;
        EXPECT_FALSE(fs::exists(path("bad"))) << range;
    }
}

}  // namespace
}  // namespace glint::denoise

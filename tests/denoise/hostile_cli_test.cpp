// glint-denoise and bad input, by class (docs/reliability.md): outputs that are inputs, loosely
// parsed integers, exposure, paint scripts, read-only banks, unwritable bank folders, region
// messages. Each case: exit 2, one line naming the place, nothing written, inputs untouched.
#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <tuple>
#include <vector>

#include "cli_fixture.h"
#include "glint/image/io.h"
#include "synthetic_frames.h"

namespace glint::denoise {
namespace {

namespace fs = std::filesystem;
using glint::testing::RunResult;
using glint::testing::slurp;

class HostileCli : public glint::testing::CliFixture {
  protected:
    HostileCli() : CliFixture("glint-denoise") {}
    void SetUp() override {
        CliFixture::SetUp();
        if (HasFatalFailure()) return;
        writeExr(testing::syntheticFrame(48, 40, 0.1f), m_dir / "noisy.exr");
        writeExr(testing::syntheticFrame(48, 40, 0.0f), m_dir / "ref.exr");
        std::ofstream(m_dir / "script.json") << R"({"layers": [{"filter": "gaussian"}],
                   "edits": [{"weights": {"layer": 0, "value": 1}}]})";
    }
    // Exit 2, one line on stderr holding every mention.
    void expectRefused(const std::string& args, const std::vector<std::string>& mentions) const {
        const RunResult r = runEither(args);
        EXPECT_EQ(r.exitCode, 2) << args << "\n" << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << args << "\n" << r.err;
        for (const std::string& m : mentions)
            EXPECT_NE(r.err.find(m), std::string::npos) << args << "\n" << r.err;
    }
};

TEST_F(HostileCli, EveryCommandRefusesAnOutputThatIsOneOfItsInputs) {
    ASSERT_EQ(run("paint " + path("noisy.exr") + " --script " + path("script.json") + " --save " +
                  path("s.glint-session.json"))
                  .exitCode,
              0);
    ASSERT_EQ(run("bank " + path("noisy.exr") + " --out " + path("bank") + " --size 3").exitCode,
              0);
    // The same files under other names: "./", a symlink, a hard link (.png names too, as the
    // PNG outputs check their extension first).
    const std::string in = path("noisy.exr"), ref = path("ref.exr");
    const std::string dotIn = (m_dir / "." / "noisy.exr").string();
    fs::create_symlink(m_dir / "noisy.exr", m_dir / "link.exr");
    fs::create_hard_link(m_dir / "ref.exr", m_dir / "hard.exr");
    fs::create_hard_link(m_dir / "ref.exr", m_dir / "hard.png");
    fs::create_hard_link(m_dir / "script.json", m_dir / "script-link.json");
    const std::string session = path("s.glint-session.json");
    const std::string sideInput = path("s.glint-session/input.exr");
    const std::string member = fs::directory_iterator(m_dir / "bank")->path().string();
    fs::create_hard_link(member, m_dir / "member.png");
    struct Case {
        std::string args, flag;
    };
    const Case cases[] = {
        {"apply " + in + " --filter gaussian --out " + dotIn, "--out"},
        {"apply " + in + " --filter gaussian --out " + path("link.exr"), "--out"},
        {"apply " + in + " --filter gaussian --reference " + ref + " --out " + path("hard.exr"),
         "--reference"},
        {"auto " + in + " --size 3 --out " + path("link.exr"), "IN"},
        {"auto " + in + " --size 3 --reference " + ref + " --out " + path("hard.exr"),
         "--reference"},
        {"auto " + in + " --size 3 --reference " + ref + " --out " + path("o.exr") +
             " --choice-map " + path("hard.png"),
         "--reference"},
        {"auto " + in + " --bank " + path("bank") + " --out " + path("o.exr") + " --choice-map " +
             path("member.png"),
         "--bank"},
        {"paint " + in + " --script " + path("script.json") + " --save " + path("script-link.json"),
         "--script"},
        {"paint " + in + " --script " + path("script.json") + " --save " +
             path("x.glint-session.json") + " --out " + path("link.exr"),
         "IN"},
        {"paint " + in + " --script " + path("script.json") + " --save " + session + " --out " +
             sideInput,
         "side folder"},
        {"composite " + session + " --input " + in + " --out " + dotIn, "--input"},
        {"composite " + session + " --input " + in + " --reference " + ref + " --out " +
             path("hard.exr"),
         "--reference"},
        {"composite " + session + " --input " + in + " --out " + sideInput, "side folder"},
        {"bank " + in + " --out " + dotIn, "IN"},
        {"oracle " + in + " --reference " + ref + " --bank " + path("bank") + " --choice-map " +
             path("hard.png"),
         "--reference"},
        {"oracle " + in + " --reference " + path("ref.exr") + " --bank " + path("bank") +
             " --choice-map " + path("member.png"),
         "--bank"},
    };
    const std::string inBytes = slurp(m_dir / "noisy.exr"), refBytes = slurp(m_dir / "ref.exr");
    const std::string scriptBytes = slurp(m_dir / "script.json");
    const std::string sideBytes = slurp(sideInput), memberBytes = slurp(member);
    for (const Case& c : cases) expectRefused(c.args, {c.flag});
    EXPECT_EQ(slurp(m_dir / "noisy.exr"), inBytes);
    EXPECT_EQ(slurp(m_dir / "ref.exr"), refBytes);
    EXPECT_EQ(slurp(m_dir / "script.json"), scriptBytes);
    EXPECT_EQ(slurp(sideInput), sideBytes);
    EXPECT_EQ(slurp(member), memberBytes);
    EXPECT_FALSE(fs::exists(path("o.exr")));
    EXPECT_FALSE(fs::exists(path("x.glint-session.json")));
}

TEST_F(HostileCli, IntegersAndSeedsAreParsedStrictly) {
    const std::string in = path("noisy.exr"), bank = " --out " + path("bank");
    const std::pair<std::string, std::string> cases[] = {
        // --seed -1 used to become 2^64 - 1, a 20-digit seed to saturate.
        {"bank " + in + bank + " --seed -1", "--seed"},
        {"bank " + in + bank + " --seed 99999999999999999999", "--seed"},
        {"bank " + in + bank + " --seed 9223372036854775808", "--seed"},
        {"bank " + in + bank + " --seed +5", "--seed"},
        {"bank " + in + bank + " --seed 0x10", "--seed"},
        {"bank " + in + bank + " --size 0x3", "--size"},
        {"bank " + in + bank + " --size +3", "--size"},
        {"bank " + in + bank + " --size ' 3'", "--size"},
        {"auto " + in + " --out " + path("o.exr") + " --seed -1", "--seed"},
        {"auto " + in + " --out " + path("o.exr") + " --bank-seed 18446744073709551615",
         "--bank-seed"},
        {"auto " + in + " --out " + path("o.exr") + " --window 0x4", "--window"},
        {"auto " + in + " --out " + path("o.exr") + " --stack 99999999999", "--stack"},
        {"auto " + in + " --out " + path("o.exr") + " --size +3", "--size"},
    };
    for (const auto& [args, flag] : cases) expectRefused(args, {flag});
    EXPECT_FALSE(fs::exists(path("bank")));
    EXPECT_FALSE(fs::exists(path("o.exr")));
    // The largest seed is taken.
    const RunResult r = run("bank " + in + bank + " --size 2 --seed 9223372036854775807 --json");
    EXPECT_EQ(r.exitCode, 0) << r.err;
}

TEST_F(HostileCli, ExposureIsLimitedToSixtyFourStopsAndNaNIsNamed) {
    const std::string base = "auto " + path("noisy.exr") + " --out " + path("o.exr") + " --size 3";
    for (const char* e : {"1e30", "65", "-64.5", "nan", "inf"})
        expectRefused(base + " --exposure " + e, {"--exposure", "[-64, 64]"});
    expectRefused(base + " --temperature inf", {"--temperature", "finite"});
    expectRefused(base + " --feather-gate nan", {"--feather-gate", "finite"});
    EXPECT_FALSE(fs::exists(path("o.exr")));
    EXPECT_EQ(runEither(base + " --exposure -64").exitCode, 0);
}

TEST_F(HostileCli, PaintScriptsWithUnknownKeysFoldersOrDevicesWriteNoSession) {
    std::ofstream(m_dir / "edit.json")
        << R"({"layers": [{"filter": "gaussian"}], "edit": [{"weights": {"layer": 0, "value": 1}}]})";
    std::ofstream(m_dir / "parms.json") << R"({"layers": [{"filter": "gaussian", "parms": {}}]})";
    std::ofstream(m_dir / "big.json") << "{\"layers\": [{\"filter\": \"gaussian\",\n"
                                         "  \"params\": {\"sigma\": 1e400}}]}";
    fs::create_directories(m_dir / "folder.json");
    const std::string base =
        "paint " + path("noisy.exr") + " --save " + path("x.glint-session.json") + " --script ";
    expectRefused(base + path("edit.json"), {"edit.json", "/edit", "unknown key 'edit'"});
    expectRefused(base + path("parms.json"), {"parms.json", "/layers/0/parms"});
    expectRefused(base + path("big.json"), {"big.json", "line 2, column 23", "number overflow"});
    expectRefused(base + path("folder.json"), {"folder.json", "is a folder"});
    expectRefused(base + "/dev/zero", {"/dev/zero", "not a regular file"});
    EXPECT_FALSE(fs::exists(path("x.glint-session.json")));
    EXPECT_FALSE(fs::exists(path("x.glint-session")));
    // A folder given as the session to composite.
    expectRefused("composite " + path("folder.json") + " --input " + path("noisy.exr") + " --out " +
                      path("o.exr"),
                  {"folder.json", "is a folder"});
}

// Every file of a folder: name → (inode, modification time in ns, size).
std::map<std::string, std::tuple<ino_t, long long, long>> snapshot(const fs::path& dir) {
    std::map<std::string, std::tuple<ino_t, long long, long>> files;
    for (const auto& entry : fs::directory_iterator(dir)) {
        struct stat st {};
        ::stat(entry.path().c_str(), &st);
        files[entry.path().filename().string()] = {
            st.st_ino, st.st_mtim.tv_sec * 1000000000LL + st.st_mtim.tv_nsec, long(st.st_size)};
    }
    return files;
}

TEST_F(HostileCli, OracleNavigateAndAutoReadABankWithoutWritingIt) {
    ASSERT_EQ(run("bank " + path("noisy.exr") + " --out " + path("bank") + " --size 4").exitCode,
              0);
    // Every file an hour older: a rewrite (the same bytes, as index.json used to be) shows.
    for (const auto& entry : fs::directory_iterator(m_dir / "bank"))
        fs::last_write_time(entry.path(),
                            fs::last_write_time(entry.path()) - std::chrono::hours(1));
    const auto before = snapshot(m_dir / "bank");
    const std::string in = path("noisy.exr"), bank = " --bank " + path("bank");
    for (const std::string& args :
         {"oracle " + in + " --reference " + path("ref.exr") + bank,
          "navigate " + in + " --reference " + path("ref.exr") + bank + " --simulate",
          "auto " + in + bank + " --out " + path("o.exr")}) {
        const RunResult r = runEither(args);
        EXPECT_EQ(r.exitCode, 0) << args << "\n" << r.err;
        EXPECT_EQ(snapshot(m_dir / "bank"), before) << args;
    }
}

TEST_F(HostileCli, ABankFolderThatCannotBeWrittenIsSaidToBeOne) {
    // Root writes into any folder: it runs the tool as nobody (65534), for whom a folder of
    // root's with mode 755 is read-only.
    std::string as;
    if (::geteuid() == 0) {
        if (!fs::exists("/usr/bin/setpriv")) GTEST_SKIP() << "root, and no setpriv to drop it";
        as = "/usr/bin/setpriv --reuid=65534 --regid=65534 --clear-groups";
        fs::permissions(m_dir, fs::perms(0755));
    }
    fs::create_directories(m_dir / "locked");
    fs::permissions(m_dir / "locked", fs::perms(0555));
    for (const std::string& out : {path("locked"), path("locked/bank")}) {
        // Used to end in the library's "filesystem error: ... Permission denied".
        const RunResult r = run(as, "bank " + path("noisy.exr") + " --out " + out);
        EXPECT_EQ(r.exitCode, 2) << r.err;
        EXPECT_NE(r.err.find("not writable"), std::string::npos) << r.err;
        EXPECT_NE(r.err.find("--out"), std::string::npos) << r.err;
        EXPECT_EQ(r.err.find("filesystem error"), std::string::npos) << r.err;
    }
    EXPECT_TRUE(fs::is_empty(m_dir / "locked"));
    fs::permissions(m_dir / "locked", fs::perms(0755));
}

TEST_F(HostileCli, RegionErrorsSayWhichBoundIsWrongAndWhoseRegion) {
    const std::string in = path("noisy.exr");
    expectRefused("bank " + in + " --out " + path("bank") + " --roi 5,5,0,10",
                  {"--roi", "x1 = 5 is not greater than x0 = 5", "empty"});
    expectRefused("bank " + in + " --out " + path("bank") + " --roi 0,10,0,41",
                  {"--roi", "y1 = 41 is past the height 40", "outside"});
    // A bank smaller than SSIM's window: the bank is at fault, not a --roi never given.
    ASSERT_EQ(run("bank " + in + " --out " + path("bank") + " --size 3 --roi 0,8,0,8").exitCode, 0);
    expectRefused("navigate " + in + " --reference " + path("ref.exr") + " --bank " + path("bank") +
                      " --simulate",
                  {"--bank", "8x8", "11x11"});
    expectRefused("oracle " + in + " --reference " + path("ref.exr") + " --bank " + path("bank"),
                  {"--bank", "8x8", "11x11"});
}

}  // namespace
}  // namespace glint::denoise

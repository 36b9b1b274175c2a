// glint-denoise auto --session: the session auto writes is its output bit for bit, reopened and
// re-applied, in one tile or many; bad session outputs write nothing.
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "cli_fixture.h"
#include "glint/denoise/session.h"
#include "glint/image/io.h"
#include "halves_frames.h"
#include "synthetic_frames.h"

namespace glint::denoise {
namespace {

namespace fs = std::filesystem;
using glint::testing::RunResult;

// A small bank of classical filters: auto's defaults otherwise (the halves, stacking on).
const std::string kBank = " --size 6 --filters gaussian,bilateral,guided";

class AutoSessionCli : public glint::testing::CliFixture {
  protected:
    AutoSessionCli() : CliFixture("glint-denoise") {}
    void SetUp() override {
        CliFixture::SetUp();
        if (HasFatalFailure()) return;
        const Image clean = halves_test::cleanImage(48, 40);
        writeExr(halves_test::halvesFrame(clean, 0.08, halves_test::Noise::Gaussian, 5),
                 m_dir / "halves.exr");
    }
};

TEST_F(AutoSessionCli, TheSessionAutoWritesIsItsOutputBitForBit) {
    // One tile (a large --memory-limit) and many (a tiny one): the same bits either way.
    for (const std::string& limit : {std::string("64G"), std::string("1K")}) {
        SCOPED_TRACE("--memory-limit " + limit);
        const std::string session = path("s-" + limit + ".glint-session.json");
        const std::string out = path("out-" + limit + ".exr");
        RunResult r = runEither("auto " + path("halves.exr") + " --out " + out + " --session " +
                                session + " --memory-limit " + limit + " --json" + kBank);
        ASSERT_EQ(r.exitCode, 0) << r.err;
        const nlohmann::json j = nlohmann::json::parse(r.out);
        EXPECT_EQ(j["estimator"], "halves");
        EXPECT_GE(j["stack"].get<int>(), 1);  // the default result: the blend, stacked
        EXPECT_EQ(j["session"], session);
        const Image colour = readExr(out).color();
        // Reopened (every member re-run on the session's input), the composite is OUT's colour.
        const Session s = Session::load(session);
        ASSERT_EQ(s.layerCount(), j["membersUsed"].get<std::size_t>() + 1);
        EXPECT_EQ(j["sessionLayers"], s.layerCount());
        ASSERT_TRUE(s.layer(s.layerCount() - 1).correction);
        EXPECT_EQ(s.layer(s.layerCount() - 1).filter, kAutoCorrection);
        EXPECT_TRUE(testing::sameBits(s.composite(), colour));
        // And re-applied to the same render by `composite`: the same bits again.
        r = run("composite " + session + " --input " + path("halves.exr") + " --out " +
                path("again.exr"));
        ASSERT_EQ(r.exitCode, 0) << r.err;
        EXPECT_TRUE(testing::sameBits(readExr(path("again.exr")).color(), colour));
    }
}

TEST_F(AutoSessionCli, ASessionThatCannotBeWrittenIsRefusedBeforeAnyWork) {
    ASSERT_EQ(run("bank " + path("halves.exr") + " --out " + path("roi") +
                  " --roi 0,24,0,20 --size 2 --filters gaussian")
                  .exitCode,
              0);
    ASSERT_EQ(run("bank " + path("halves.exr") + " --out " + path("b.glint-session") +
                  " --size 2 --filters gaussian")
                  .exitCode,
              0);
    fs::create_directories(m_dir / "s.glint-session");
    for (const std::string& args :
         {" --session " + path("s.txt"), " --session " + path("missing/s.glint-session.json"),
          " --session " + path("s.glint-session.json") + " --choice-map " +
              path("s.glint-session/map.png"),
          " --session " + path("b.glint-session.json") + " --bank " + path("b.glint-session"),
          " --session " + path("r.glint-session.json") + " --bank " + path("roi")}) {
        SCOPED_TRACE(args);
        const RunResult r =
            runEither("auto " + path("halves.exr") + " --out " + path("o.exr") + args + kBank);
        EXPECT_EQ(r.exitCode, 2) << r.err;
        EXPECT_NE(r.err.find("--session"), std::string::npos) << r.err;
        EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << r.err;  // one line
        EXPECT_FALSE(fs::exists(m_dir / "o.exr"));
        for (const char* name : {"s.txt", "s.glint-session.json", "b.glint-session.json",
                                 "r.glint-session.json", "r.glint-session"})
            EXPECT_FALSE(fs::exists(m_dir / name)) << name;
    }
}

}  // namespace
}  // namespace glint::denoise

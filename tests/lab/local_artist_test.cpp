// The local artist (glint/lab/local_artist.h) and glint-lab navigate --simulate --local: strokes
// that only stay when they help never lower the SSIM, the strokes beat the start, the run is
// deterministic, bad flags exit 2 with one line.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "cli_fixture.h"
#include "glint/denoise/bank.h"
#include "glint/image/error.h"
#include "glint/image/io.h"
#include "glint/image/metrics.h"
#include "glint/lab/local_artist.h"
#include "synthetic_frames.h"

namespace glint::lab {
namespace {

using denoise::BankOptions;
using denoise::buildBank;
using denoise::FilterBank;
namespace testing = glint::denoise::testing;

namespace fs = std::filesystem;
using glint::testing::RunResult;

// A 64×48 frame with noise 0.1 (seed 7), its noiseless reference and a 16-member bank (seed 1),
// built once: the start is the noisiest member there is, the input itself, so that local choices
// have room to help.
struct Fixture {
    FrameBuffers noisy = testing::syntheticFrame(64, 48, 0.1f);
    FrameBuffers clean = testing::syntheticFrame(64, 48, 0.0f);
    FilterBank bank;
    Fixture() {
        BankOptions o;
        o.size = 10;
        bank = buildBank(noisy, o);
    }
};
const Fixture& fixture() {
    static const Fixture f;
    return f;
}

LocalArtistOptions smallBrush(int strokes) {
    LocalArtistOptions o;
    o.strokes = strokes;
    o.brush.size = 16.0;
    return o;
}

TEST(LocalArtist, KeptStrokesNeverLowerTheSsimAndBeatTheStart) {
    const Fixture& f = fixture();
    for (ArtistPick pick : {ArtistPick::Variance, ArtistPick::Error}) {
        LocalArtistOptions o = smallBrush(12);
        o.pick = pick;
        const LocalArtistResult r = localArtist(f.bank, f.noisy.color(), f.clean.color(), o);
        ASSERT_EQ(r.strokes.size(), 12u);
        double previous = r.startSsim;
        int kept = 0;
        for (const ArtistStroke& s : r.strokes) {
            // The rule: a stroke stays only if the whole composite's SSIM does not drop.
            EXPECT_GE(s.ssim, previous) << "stroke " << s.stroke;
            if (s.kept)
                EXPECT_EQ(s.ssim, s.ssimIfKept);
            else
                EXPECT_LT(s.ssimIfKept, previous);
            kept += s.kept ? 1 : 0;
            previous = s.ssim;
            EXPECT_GE(s.member, 0);
            EXPECT_LT(s.member, int(f.bank.size()));
            EXPECT_GE(s.choices, 1);
            EXPECT_EQ(s.region.width(), 16);
        }
        EXPECT_GT(kept, 0);
        // The composite after the strokes is the one measured last.
        EXPECT_NEAR(ssim(r.composite, f.clean.color()).value, r.strokes.back().ssim, 1e-12);
        // From the noisy input, a dozen 16-px strokes over a 64×48 frame gain clearly (the
        // noise's SSIM is about 0.5, the bank's members about 0.9: 0.05 is a fraction of that).
        EXPECT_GT(r.strokes.back().ssim, r.startSsim + 0.05) << artistPickName(pick);
    }
}

TEST(LocalArtist, StrokesGoToDifferentRegionsAndTheRunIsDeterministic) {
    const Fixture& f = fixture();
    const LocalArtistOptions o = smallBrush(6);
    const LocalArtistResult a = localArtist(f.bank, f.noisy.color(), f.clean.color(), o);
    const LocalArtistResult b = localArtist(f.bank, f.noisy.color(), f.clean.color(), o);
    ASSERT_EQ(a.strokes.size(), b.strokes.size());
    for (std::size_t i = 0; i < a.strokes.size(); ++i) {
        EXPECT_EQ(a.strokes[i].member, b.strokes[i].member);
        EXPECT_EQ(a.strokes[i].ssim, b.strokes[i].ssim);
        for (std::size_t j = 0; j < i; ++j)
            EXPECT_FALSE(a.strokes[i].x == a.strokes[j].x && a.strokes[i].y == a.strokes[j].y)
                << "strokes " << j + 1 << " and " << i + 1 << " at the same place";
    }
    EXPECT_TRUE(std::equal(a.composite.data().begin(), a.composite.data().end(),
                           b.composite.data().begin(), b.composite.data().end()));
}

TEST(LocalArtist, KeepingEveryStrokeCanLowerTheSsimButPaintsEveryOne) {
    const Fixture& f = fixture();
    // Starting from the clean image itself, any stroke can only make it worse.
    LocalArtistOptions o = smallBrush(4);
    o.keepOnlyHelping = false;
    const LocalArtistResult all = localArtist(f.bank, f.clean.color(), f.clean.color(), o);
    for (const ArtistStroke& s : all.strokes) EXPECT_TRUE(s.kept);
    EXPECT_LT(all.strokes.back().ssim, all.startSsim);
    o.keepOnlyHelping = true;
    const LocalArtistResult helping = localArtist(f.bank, f.clean.color(), f.clean.color(), o);
    EXPECT_EQ(helping.strokes.back().ssim, helping.startSsim);
}

TEST(LocalArtist, BadOptionsAndSizesThrow) {
    const Fixture& f = fixture();
    auto throwsNaming = [&](LocalArtistOptions o, const Image& start, const std::string& mention) {
        try {
            localArtist(f.bank, start, f.clean.color(), o);
            ADD_FAILURE() << "no error for " << mention;
        } catch (const Error& e) {
            EXPECT_EQ(e.kind(), ErrorKind::InvalidArgument);
            EXPECT_NE((e.where() + " " + e.message()).find(mention), std::string::npos)
                << e.message();
        }
    };
    LocalArtistOptions o = smallBrush(0);
    throwsNaming(o, f.noisy.color(), "--strokes");
    o = smallBrush(3);
    o.brush.size = 8.0;
    throwsNaming(o, f.noisy.color(), "11");
    o.brush.size = 60.0;  // wider than the 48-px-high frame
    throwsNaming(o, f.noisy.color(), "does not fit");
    throwsNaming(smallBrush(3), Image(10, 10, 3), "region");
    EXPECT_THROW(parseArtistPick("random"), Error);
}

class LocalArtistCli : public glint::testing::CliFixture {
  protected:
    LocalArtistCli() : CliFixture("glint-lab") {}
    void SetUp() override {
        CliFixture::SetUp();
        if (HasFatalFailure()) return;
        writeExr(testing::syntheticFrame(48, 40, 0.1f), m_dir / "noisy.exr");
        writeExr(testing::syntheticFrame(48, 40, 0.0f), m_dir / "ref.exr");
        ASSERT_EQ(runTool("glint-denoise",
                          "bank " + path("noisy.exr") + " --out " + path("bank") + " --size 6")
                      .exitCode,
                  0);
    }
    std::string navigate(const std::string& extra) const {
        return "navigate " + path("noisy.exr") + " --reference " + path("ref.exr") + " --bank " +
               path("bank") + " --simulate " + extra;
    }
};

TEST_F(LocalArtistCli, ReportsEveryStrokeFromTheBestMember) {
    // The synthetic frame has no half buffers but a variance layer: auto would run SURE; the
    // best member is the start every input allows.
    const RunResult r = run(navigate("--local --start best --strokes 5 --brush-size 12 --json"));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const nlohmann::json j = nlohmann::json::parse(r.out);
    ASSERT_EQ(j["strokes"].size(), 5u);
    EXPECT_EQ(j["start"]["kind"], "best");
    double previous = j["start"]["ssim"].get<double>();
    for (const nlohmann::json& s : j["strokes"]) {
        EXPECT_GE(s["ssim"].get<double>(), previous);
        previous = s["ssim"].get<double>();
    }
    EXPECT_EQ(j["ssim"].get<double>(), previous);
    const RunResult text = run(navigate("--local --strokes 3 --brush-size 12"));
    ASSERT_EQ(text.exitCode, 0) << text.err;
    EXPECT_NE(text.out.find("stroke  3"), std::string::npos) << text.out;
    EXPECT_NE(text.out.find("local artist from auto"), std::string::npos) << text.out;
}

TEST_F(LocalArtistCli, BadFlagsExitTwoWithOneLine) {
    const std::pair<std::string, std::string> cases[] = {
        {"--local --strokes 0", "--strokes"},
        {"--local --strokes 3x", "--strokes"},
        {"--local --start middle", "--start"},
        {"--local --pick random", "--pick"},
        {"--local --brush-size 5", "--brush-size"},
        {"--local --brush-size big", "--brush-size"},
        {"--local --brush-size 100", "does not fit"},
        {"--local --brush-softness 2", "softness"},
        {"--local --roi 0,20,0,20", "--roi"},
        {"--strokes 5", "--local"},
        {"--keep-all", "--local"},
    };
    for (const auto& [args, mention] : cases) {
        const RunResult r = run(navigate(args));
        EXPECT_EQ(r.exitCode, 2) << args;
        EXPECT_NE(r.err.find(mention), std::string::npos) << args << "\n" << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << args << "\n" << r.err;
    }
}

}  // namespace
}  // namespace glint::lab

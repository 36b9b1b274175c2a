// Auto's correction layer of the painting session (SessionCorrection, docs/painting.md, "Auto's
// correction"): the composite it makes, painting under and over it, undo, reapply, and its
// session files — old ones open, bad ones are one error with the place.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <string>

#include "glint/denoise/session.h"
#include "glint/image/composite.h"
#include "glint/image/error.h"
#include "glint/image/io.h"
#include "synthetic_frames.h"

namespace glint::denoise {
namespace {

namespace fs = std::filesystem;

// An auto's result for `blend`: brighter, with a pixel clamped to 0 and one a billionth of the
// blend (the case a float difference added back cannot reach).
Image resultFor(const Image& blend) {
    Image t = blend;
    for (float& v : t.data()) v = v * 1.1f + 0.01f;
    t(3, 2, 0) = 0.0f;
    t(5, 4, 1) = blend(5, 4, 1) * 1e-9f;
    return t;
}

// The composite built from scratch: filter layers blended, the correction added in double.
Image correctedFromScratch(const Session& s) {
    Image c = s.input().color();
    for (std::size_t i = 0; i < s.layerCount(); ++i) {
        const SessionLayer& l = s.layer(i);
        if (!l.correction) {
            c = blend(c, *l.output, l.weights);
            continue;
        }
        for (int y = 0; y < c.height(); ++y)
            for (int x = 0; x < c.width(); ++x)
                for (int ch = 0; ch < 3; ++ch) {
                    const float w = l.weights(x, y, 0), t = l.correction->result(x, y, ch),
                                b = l.correction->blend(x, y, ch);
                    float& v = c(x, y, ch);
                    if (w == 0.0f || t == b) continue;
                    v = w == 1.0f && v == b
                            ? t
                            : float(std::max(0.0, double(v) + double(w) * (double(t) - double(b))));
                }
    }
    return c;
}

class SessionCorrectionTest : public ::testing::Test {
  protected:
    void SetUp() override {
        m_dir = fs::temp_directory_path() /
                ("glint_correction_" + std::to_string(::getpid()) + "_" +
                 ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(m_dir);
        fs::create_directories(m_dir);
    }
    void TearDown() override { fs::remove_all(m_dir); }

    // A session of a gaussian layer (weight 0.6) with auto's correction on top (weight 1).
    static Session corrected() {
        Session s(testing::syntheticFrame(24, 20, 0.05f, 1));
        const std::size_t g = s.addLayer("gaussian", {{"sigma", 1.5}});
        s.setWeights(g, Image(24, 20, 1, 0.6f));
        const std::size_t c = s.addCorrection(resultFor(s.composite()));
        s.setWeights(c, Image(24, 20, 1, 1.0f));
        return s;
    }
    fs::path m_dir;
};

TEST_F(SessionCorrectionTest, TheCompositeIsAutosResultBitForBitAndPaintingStillBlends) {
    Session s = corrected();
    ASSERT_EQ(s.layerCount(), 2u);
    const SessionLayer& layer = s.layer(1);
    ASSERT_TRUE(layer.correction);
    EXPECT_EQ(layer.filter, kAutoCorrection);
    EXPECT_TRUE(testing::sameBits(*layer.output, layer.correction->result));
    // Auto's result itself, the clamped and the tiny values included.
    EXPECT_TRUE(testing::sameBits(s.composite(), layer.correction->result));
    EXPECT_EQ(s.composite()(3, 2, 0), 0.0f);
    EXPECT_EQ(s.composite()(5, 4, 1), layer.correction->result(5, 4, 1));
    // A stroke on the member beneath blends it there, and the correction is added to it.
    s.beginStroke(0, Brush{6.0, 0.5}, BrushMode::Add);
    s.dab(12.0, 10.0);
    s.endStroke();
    EXPECT_TRUE(testing::sameBits(s.composite(), correctedFromScratch(s)));
    EXPECT_NE(s.composite()(12, 10, 0), layer.correction->result(12, 10, 0));
    EXPECT_EQ(s.composite()(0, 0, 0), layer.correction->result(0, 0, 0));  // outside the dab
    // Painting the correction away shows the blend beneath; a layer on top blends over it.
    s.beginStroke(1, Brush{4.0, 1.0}, BrushMode::Subtract);
    s.dab(2.0, 2.0);
    s.endStroke();
    EXPECT_EQ(s.composite()(2, 2, 0), layer.correction->blend(2, 2, 0));
    const std::size_t top = s.addLayer("bilateral", {});
    s.setWeights(top, Image(24, 20, 1, 0.5f));
    EXPECT_TRUE(testing::sameBits(s.composite(), correctedFromScratch(s)));
    // Every edit undone and redone, bit for bit.
    const Image painted = s.composite();
    for (int i = 0; i < 4; ++i) s.undo();
    EXPECT_TRUE(testing::sameBits(s.composite(), s.layer(1).correction->result));
    for (int i = 0; i < 4; ++i) s.redo();
    EXPECT_TRUE(testing::sameBits(s.composite(), painted));
    // Back before the correction: the blend it corrected.
    Session t = corrected();
    t.undo();
    t.undo();
    EXPECT_EQ(t.layerCount(), 1u);
    EXPECT_TRUE(testing::sameBits(t.composite(), s.layer(1).correction->blend));
}

TEST_F(SessionCorrectionTest, ItIsSavedReopenedAndCarriedOverToANewRender) {
    Session s = corrected();
    const fs::path file = m_dir / "auto.glint-session.json";
    s.save(file);
    EXPECT_TRUE(fs::exists(m_dir / "auto.glint-session" / "correction-1.exr"));
    std::ifstream in(file);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_NE(text.find("\"format\": 2"), std::string::npos);
    EXPECT_NE(text.find("\"kind\": \"auto-correction\""), std::string::npos);
    const Session back = Session::load(file);
    ASSERT_EQ(back.layerCount(), 2u);
    ASSERT_TRUE(back.layer(1).correction);
    EXPECT_TRUE(testing::sameBits(back.layer(1).correction->result, s.layer(1).correction->result));
    EXPECT_TRUE(testing::sameBits(back.layer(1).correction->blend, s.layer(1).correction->blend));
    EXPECT_TRUE(testing::sameBits(back.composite(), s.composite()));
    // A new render: the member runs on it and the correction is added to its blend; the
    // re-application prepared elsewhere is the same bits.
    const FrameBuffers next = testing::syntheticFrame(24, 20, 0.05f, 2);
    Session direct = corrected();
    EXPECT_EQ(direct.layerSpecs().size(), 1u);  // the correction has no filter to run
    direct.reapply(next);
    EXPECT_TRUE(testing::sameBits(direct.composite(), correctedFromScratch(direct)));
    EXPECT_FALSE(testing::sameBits(direct.composite(), s.composite()));
    Session prepared = corrected();
    const Session::Snapshot snap = prepared.snapshot();
    prepared.reapply(Session::prepareReapply(
        next, Session::computeOutputs(next, snap.options, snap.specs), snap));
    EXPECT_TRUE(testing::sameBits(prepared.composite(), direct.composite()));
}

TEST_F(SessionCorrectionTest, OldFilesOpenAndABadCorrectionIsOneErrorWithItsPlace) {
    // A session without a correction is written as format 1, which older Glints read.
    Session plain(testing::syntheticFrame(24, 20));
    plain.addLayer("gaussian", {});
    const fs::path old = m_dir / "old.glint-session.json";
    plain.save(old);
    std::ifstream oldIn(old);
    const std::string oldText((std::istreambuf_iterator<char>(oldIn)),
                              std::istreambuf_iterator<char>());
    EXPECT_NE(oldText.find("\"format\": 1"), std::string::npos);
    EXPECT_EQ(Session::load(old).layerCount(), 1u);

    const fs::path good = m_dir / "good.glint-session.json";
    corrected().save(good);
    std::ifstream in(good);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    auto expectRefused = [&](const std::string& name, const std::string& json,
                             const std::string& mention,
                             const std::function<void(const fs::path&)>& damage) {
        std::ofstream(m_dir / (name + ".json")) << json;
        fs::copy(m_dir / "good.glint-session", m_dir / name);
        damage(m_dir / name);
        try {
            Session::load(m_dir / (name + ".json"));
            ADD_FAILURE() << name << " loaded";
        } catch (const Error& e) {
            EXPECT_NE(e.kind(), ErrorKind::Internal);
            EXPECT_EQ(fs::path(e.file()).filename(), name + ".json") << e.what();
            EXPECT_NE(std::string(e.what()).find(mention), std::string::npos) << e.what();
        }
    };
    auto none = [](const fs::path&) {};
    expectRefused("missing.glint-session", text, "/layers/1/correction: side file",
                  [](const fs::path& f) { fs::remove(f / "correction-1.exr"); });
    expectRefused("channels.glint-session", text, "x6", [](const fs::path& f) {
        writeImage(Image(24, 20, 3, 0.5f), f / "correction-1.exr");
    });
    expectRefused("nan.glint-session", text, "non-finite", [](const fs::path& f) {
        Image both(24, 20, 6, 0.5f);
        both(7, 3, 4) = std::nanf("");
        writeImage(both, f / "correction-1.exr");
    });
    std::string kind = text;
    kind.replace(kind.find("\"auto-correction\""), 17, "\"stacking\"");
    expectRefused("kind.glint-session", kind, "/layers/1/kind", none);
    // A format-1 file has no layer kinds: the key is unknown there.
    std::string one = text;
    one.replace(one.find("\"format\": 2"), 11, "\"format\": 1");
    expectRefused("one.glint-session", one, "/layers/1", none);
    // A correction that does not fit the session is refused, and nothing changes.
    Session s(testing::syntheticFrame(24, 20));
    EXPECT_THROW(s.addCorrection(Image(8, 8, 3)), Error);
    Image bad(24, 20, 3, 1.0f);
    bad(1, 1, 1) = INFINITY;
    EXPECT_THROW(s.addCorrection(bad), Error);
    EXPECT_EQ(s.layerCount(), 0u);
    EXPECT_FALSE(s.canUndo());
}

}  // namespace
}  // namespace glint::denoise

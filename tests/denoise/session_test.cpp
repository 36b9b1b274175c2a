// The painting session: the composite, strokes, fills, diffusion, undo/redo, reapply, session
// files (round trips, bad files, atomic saves) and exports.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "glint/denoise/prefilter.h"
#include "glint/denoise/registry.h"
#include "glint/denoise/session.h"
#include "glint/image/composite.h"
#include "glint/image/error.h"
#include "glint/image/io.h"
#include "synthetic_frames.h"

namespace glint::denoise {
namespace {

namespace fs = std::filesystem;

bool sameBits(const Image& a, const Image& b) {
    return a.sameShape(b) &&
           std::memcmp(a.data().data(), b.data().data(), a.data().size_bytes()) == 0;
}

// The composite built from scratch, layer by layer, over the whole frame.
Image compositeFromScratch(const Session& s) {
    Image c = s.input().color();
    for (std::size_t i = 0; i < s.layerCount(); ++i)
        c = blend(c, *s.layer(i).output, s.layer(i).weights);
    return c;
}

// Everything an edit can change: the layers (filter, parameters, output, weights, painted) and
// the composite.
struct SessionState {
    std::vector<std::string> filters;
    std::vector<ParamValues> params;
    std::vector<Image> outputs, weights, painted;
    Image composite;
};

SessionState stateOf(const Session& s) {
    SessionState st;
    for (std::size_t i = 0; i < s.layerCount(); ++i) {
        st.filters.push_back(s.layer(i).filter);
        st.params.push_back(s.layer(i).params);
        st.outputs.push_back(*s.layer(i).output);
        st.weights.push_back(s.layer(i).weights);
        st.painted.push_back(s.layer(i).painted);
    }
    st.composite = s.composite();
    return st;
}

// Empty when equal bit for bit, else what differs.
std::string differences(const SessionState& a, const SessionState& b) {
    if (a.filters != b.filters) return "filters";
    if (a.params != b.params) return "params";
    for (std::size_t i = 0; i < a.filters.size(); ++i) {
        if (!sameBits(a.outputs[i], b.outputs[i])) return "output of layer " + std::to_string(i);
        if (!sameBits(a.weights[i], b.weights[i])) return "weights of layer " + std::to_string(i);
        if (!sameBits(a.painted[i], b.painted[i])) return "painted of layer " + std::to_string(i);
    }
    if (!sameBits(a.composite, b.composite)) return "composite";
    return {};
}

class SessionTest : public ::testing::Test {
  protected:
    void SetUp() override {
        m_dir = fs::temp_directory_path() /
                ("glint_session_" + std::to_string(::getpid()) + "_" +
                 ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(m_dir);
        fs::create_directories(m_dir);
    }
    void TearDown() override { fs::remove_all(m_dir); }
    fs::path m_dir;
};

TEST_F(SessionTest, CompositeIsTheFilterWhereWeightIsOneAndTheInputWhereZero) {
    Session s(testing::syntheticFrame(48, 40));
    EXPECT_TRUE(sameBits(s.composite(), s.input().color()));
    const std::size_t g = s.addLayer("gaussian", {{"sigma", 2.0}});
    EXPECT_TRUE(sameBits(*s.layer(g).output,
                         applyFilter(findFilter("gaussian"), s.input(), {{"sigma", 2.0}})));
    Image w(48, 40, 1, 0.0f);
    for (int y = 0; y < 40; ++y)
        for (int x = 24; x < 48; ++x) w(x, y, 0) = 1.0f;
    s.setWeights(g, w);
    for (int y = 0; y < 40; ++y)
        for (int x = 0; x < 48; ++x)
            for (int c = 0; c < 3; ++c)
                EXPECT_EQ(s.composite()(x, y, c),
                          x < 24 ? s.input().color()(x, y, c) : (*s.layer(g).output)(x, y, c));
    // Layers apply left to right: a second layer at w = 1 wins over the first.
    const std::size_t b = s.addLayer("bilateral", {});
    s.setWeights(b, Image(48, 40, 1, 1.0f));
    EXPECT_TRUE(sameBits(s.composite(), *s.layer(b).output));
    EXPECT_TRUE(sameBits(s.composite(), compositeFromScratch(s)));
}

TEST_F(SessionTest, ADabChangesOnlyItsRectangleAndAStrokeDoesNotPileUp) {
    Session s(testing::syntheticFrame(64, 64));
    const std::size_t g = s.addLayer("gaussian", {{"sigma", 3.0}});
    const Image before = s.composite();
    const Brush brush{16.0, 0.5};
    s.beginStroke(g, brush, BrushMode::Add);
    const Rect r = s.dab(20.0, 20.0);
    EXPECT_FALSE(r.empty());
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) {
            if (r.contains(x, y)) continue;
            for (int c = 0; c < 3; ++c) EXPECT_EQ(s.composite()(x, y, c), before(x, y, c));
            EXPECT_EQ(s.layer(g).weights(x, y, 0), 0.0f);
        }
    // The dab's weights are the brush profile: 1 at the centre, falling off to the edge.
    EXPECT_EQ(s.layer(g).weights(19, 19, 0), 1.0f);
    EXPECT_FLOAT_EQ(s.layer(g).weights(20 + 5, 19, 0), brushWeight(std::hypot(5.5, 0.5), brush));
    // Dabbing the same spot again within the stroke changes nothing (coverage is a maximum);
    // a shifted dab leaves each pixel at the larger of the two profiles, not their sum.
    const Image once = s.layer(g).weights;
    s.dab(20.0, 20.0);
    EXPECT_TRUE(sameBits(s.layer(g).weights, once));
    s.dab(22.0, 20.0);
    for (int y = 10; y < 30; ++y)
        for (int x = 10; x < 34; ++x) {
            const float a = brushWeight(std::hypot(x + 0.5 - 20.0, y + 0.5 - 20.0), brush);
            const float b = brushWeight(std::hypot(x + 0.5 - 22.0, y + 0.5 - 20.0), brush);
            EXPECT_EQ(s.layer(g).weights(x, y, 0), std::max(a, b)) << x << "," << y;
        }
    s.endStroke();
    EXPECT_TRUE(sameBits(s.composite(), compositeFromScratch(s)));
}

TEST_F(SessionTest, AddThenSubtractTheSameStrokeRoundTrips) {
    Session s(testing::syntheticFrame(48, 48));
    const std::size_t g = s.addLayer("gaussian", {});
    const Image before = s.composite();
    for (BrushMode mode : {BrushMode::Add, BrushMode::Subtract}) {
        s.beginStroke(g, Brush{20.0, 0.3}, mode);
        for (double x = 10; x < 40; x += 2) s.dab(x, 24.0);
        s.endStroke();
    }
    for (float v : s.layer(g).weights.data()) EXPECT_EQ(v, 0.0f);
    EXPECT_TRUE(sameBits(s.composite(), before));
}

TEST_F(SessionTest, UndoRedoOfEveryEditIsBitExact) {
    Session s(testing::syntheticFrame(40, 32));
    std::vector<SessionState> states{stateOf(s)};
    auto snap = [&] { states.push_back(stateOf(s)); };
    const std::size_t g = s.addLayer("gaussian", {{"sigma", 2.0}});
    snap();
    s.beginStroke(g, Brush{12.0, 0.5}, BrushMode::Add);
    s.dab(10.0, 10.0);
    s.dab(14.0, 12.0);
    s.endStroke();
    snap();
    Image mask(40, 32, 1, 0.0f);
    for (int y = 20; y < 30; ++y)
        for (int x = 20; x < 38; ++x) mask(x, y, 0) = 1.0f;
    s.fill(g, mask, BrushMode::Add);
    snap();
    const std::size_t b = s.addLayer("bilateral", {});
    snap();
    s.beginStroke(b, Brush{10.0, 0.0}, BrushMode::Add);
    s.dab(30.0, 8.0);
    s.endStroke();
    snap();
    s.beginStroke(g, Brush{8.0, 0.5}, BrushMode::Subtract);
    s.dab(12.0, 11.0);
    s.endStroke();
    snap();
    s.fill(g, mask, BrushMode::Subtract);
    snap();
    s.diffuse({g, b});
    snap();
    s.applyWeights({b}, {Image(40, 32, 1, 0.25f)});
    snap();
    s.setWeights(b, Image(40, 32, 1, 0.5f));
    snap();
    s.removeLayer(0);
    snap();
    const std::size_t steps = states.size() - 1;
    for (std::size_t i = steps; i > 0; --i) {
        ASSERT_TRUE(s.canUndo());
        s.undo();
        EXPECT_EQ(differences(stateOf(s), states[i - 1]), "") << "undo to state " << i - 1;
    }
    EXPECT_FALSE(s.canUndo());
    for (std::size_t i = 1; i <= steps; ++i) {
        ASSERT_TRUE(s.canRedo());
        s.redo();
        EXPECT_EQ(differences(stateOf(s), states[i]), "") << "redo to state " << i;
    }
    EXPECT_FALSE(s.canRedo());
    EXPECT_TRUE(sameBits(s.composite(), compositeFromScratch(s)));
    // A stroke that changed nothing (every dab off the frame) is no undo step.
    s.beginStroke(0, Brush{8.0, 0.5}, BrushMode::Add);
    s.dab(-100.0, -100.0);
    s.endStroke();
    EXPECT_EQ(differences(stateOf(s), states.back()), "");
    s.undo();
    EXPECT_EQ(differences(stateOf(s), states[steps - 1]), "");
    // A new edit clears redo.
    s.addLayer("gaussian", {});
    EXPECT_FALSE(s.canRedo());
}

TEST_F(SessionTest, DiffusionFillsTheUnpaintedPixelsBetweenScribbles) {
    Session s(testing::syntheticFrame(64, 32));
    const std::size_t g = s.addLayer("gaussian", {});
    s.beginStroke(g, Brush{6.0, 1.0}, BrushMode::Add);
    for (int y = 0; y < 32; y += 2) s.dab(5.0, y + 0.5);  // a painted column at x ≈ 5
    s.endStroke();
    s.beginStroke(g, Brush{6.0, 1.0}, BrushMode::Subtract);
    for (int y = 0; y < 32; y += 2) s.dab(58.0, y + 0.5);  // an erased column at x ≈ 58
    s.endStroke();
    s.diffuse({g});
    // Between the two the weight falls from 1 to 0.
    const Image& w = s.layer(g).weights;
    EXPECT_EQ(w(5, 16, 0), 1.0f);
    EXPECT_EQ(w(58, 16, 0), 0.0f);
    EXPECT_GT(w(20, 16, 0), w(40, 16, 0));
    EXPECT_GT(w(20, 16, 0), 0.0f);
    EXPECT_LT(w(40, 16, 0), 1.0f);
    EXPECT_THROW(s.diffuse({g, g}), Error);  // a layer listed twice
    EXPECT_THROW(s.diffuse({}), Error);
    Session empty(testing::syntheticFrame(16, 16));
    const std::size_t e = empty.addLayer("gaussian", {});
    EXPECT_THROW(empty.diffuse({e}), Error);
}

TEST_F(SessionTest, SaveAndLoadRoundTripBitExactly) {
    SessionOptions options;
    options.prefilter = true;
    Session s(testing::syntheticFrame(40, 32), options);
    const std::size_t g = s.addLayer("guided", {{"guide", 1}, {"radius", 3}});
    s.beginStroke(g, Brush{14.0, 0.4}, BrushMode::Add);
    s.dab(12.0, 12.0);
    s.endStroke();
    const std::size_t n = s.addLayer("nlmeans", {{"strength", 0.8}});
    s.setWeights(n, Image(40, 32, 1, 0.25f));
    s.region = Rect{2, 30, 4, 20};
    s.bankDir = "/some/bank";
    s.viewState["exposure"] = "0.5";
    const fs::path file = m_dir / "look.glint-session.json";
    s.save(file);
    EXPECT_TRUE(fs::exists(m_dir / "look.glint-session" / "input.exr"));
    const Session back = Session::load(file);
    ASSERT_EQ(back.layerCount(), 2u);
    for (std::size_t i = 0; i < 2; ++i) {
        EXPECT_EQ(back.layer(i).filter, s.layer(i).filter);
        EXPECT_EQ(back.layer(i).params, s.layer(i).params);
        EXPECT_TRUE(sameBits(back.layer(i).weights, s.layer(i).weights));
        EXPECT_TRUE(sameBits(back.layer(i).painted, s.layer(i).painted));
        EXPECT_TRUE(sameBits(*back.layer(i).output, *s.layer(i).output));
    }
    EXPECT_TRUE(sameBits(back.composite(), s.composite()));
    EXPECT_TRUE(back.options().prefilter);
    EXPECT_EQ(back.region, s.region);
    EXPECT_EQ(back.bankDir, s.bankDir);
    EXPECT_EQ(back.viewState, s.viewState);
    // Saving again over it replaces it cleanly (no temporaries left).
    s.removeLayer(1);
    s.save(file);
    EXPECT_EQ(Session::load(file).layerCount(), 1u);
    for (const auto& e : fs::directory_iterator(m_dir))
        EXPECT_EQ(e.path().filename().string().find(".tmp-"), std::string::npos) << e.path();
}

TEST_F(SessionTest, ALayerIsRenamedAsAnUndoStepAndItsNameIsSaved) {
    Session s(testing::syntheticFrame(24, 20));
    const std::size_t g = s.addLayer("gaussian", {{"sigma", 2.0}});
    EXPECT_EQ(s.layer(g).name, "");
    s.renameLayer(g, "walls");
    EXPECT_EQ(s.layer(g).name, "walls");
    s.renameLayer(g, "walls");  // the same name: no step
    s.undo();
    EXPECT_EQ(s.layer(g).name, "");
    ASSERT_EQ(s.layerCount(), 1u);  // the rename was undone, not the layer
    s.redo();
    EXPECT_EQ(s.layer(g).name, "walls");
    EXPECT_THROW(s.renameLayer(5, "x"), Error);
    const fs::path file = m_dir / "named.glint-session.json";
    s.save(file);
    EXPECT_EQ(Session::load(file).layer(0).name, "walls");
}

TEST_F(SessionTest, SideFramesAreSavedInTheSideFolderAndLoadedBack) {
    Session s(testing::syntheticFrame(24, 20));
    s.addLayer("gaussian", {});
    const fs::path plain = m_dir / "plain.glint-session.json";
    s.save(plain);  // a session without side frames: no "frames" key, as older files
    EXPECT_TRUE(Session::load(plain).sideFrames.empty());
    std::ifstream in(plain);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_EQ(text.find("\"frames\""), std::string::npos);

    auto reference =
        std::make_shared<const FrameBuffers>(testing::syntheticFrame(24, 20, 0.05f, 99));
    s.sideFrames["reference"] = reference;
    const fs::path file = m_dir / "framed.glint-session.json";
    s.save(file);
    EXPECT_TRUE(fs::exists(m_dir / "framed.glint-session" / "reference.exr"));
    const Session back = Session::load(file);
    ASSERT_EQ(back.sideFrames.count("reference"), 1u);
    EXPECT_TRUE(sameBits(back.sideFrames.at("reference")->color(), reference->color()));
    // A side frame whose file is gone is refused with its place.
    fs::remove(m_dir / "framed.glint-session" / "reference.exr");
    try {
        Session::load(file);
        ADD_FAILURE() << "loaded without its side frame";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("/frames/reference"), std::string::npos) << e.what();
    }
    // A name that is no plain file name, or one of the session's own files, is refused.
    for (const char* bad : {"../escape", "input", "layer-0", ""}) {
        Session t(testing::syntheticFrame(8, 8));
        t.sideFrames[bad] = reference;
        EXPECT_THROW(t.save(m_dir / "bad.glint-session.json"), Error) << bad;
    }
    EXPECT_FALSE(fs::exists(m_dir / "bad.glint-session.json"));
}

TEST_F(SessionTest, BadSessionFilesAreRefusedAndNothingIsOverwritten) {
    Session s(testing::syntheticFrame(24, 20));
    s.addLayer("gaussian", {});
    const fs::path good = m_dir / "good.glint-session.json";
    s.save(good);
    std::ifstream in(good);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    auto expectRefused = [&](const std::string& name, const std::string& mention) {
        try {
            Session::load(m_dir / name);
            ADD_FAILURE() << name << " loaded";
        } catch (const Error& e) {
            EXPECT_NE(e.kind(), ErrorKind::Internal);
            EXPECT_EQ(fs::path(e.file()).filename(), name) << e.what();
            EXPECT_NE(std::string(e.what()).find(mention), std::string::npos) << e.what();
        }
    };
    // Truncated JSON: line and column.
    std::ofstream(m_dir / "cut.glint-session.json") << text.substr(0, text.size() / 2);
    fs::copy(m_dir / "good.glint-session", m_dir / "cut.glint-session");
    expectRefused("cut.glint-session.json", "line");
    // A newer format.
    std::string newer = text;
    newer.replace(newer.find("\"format\": 1"), 11, "\"format\": 99");
    std::ofstream(m_dir / "new.glint-session.json") << newer;
    fs::copy(m_dir / "good.glint-session", m_dir / "new.glint-session");
    expectRefused("new.glint-session.json", "newer");
    // A missing side file.
    std::ofstream(m_dir / "lost.glint-session.json") << text;
    fs::create_directories(m_dir / "lost.glint-session");
    fs::copy(m_dir / "good.glint-session/input.exr", m_dir / "lost.glint-session/input.exr");
    expectRefused("lost.glint-session.json", "layer-0.exr");
    // Weights of another size.
    std::ofstream(m_dir / "size.glint-session.json") << text;
    fs::copy(m_dir / "good.glint-session", m_dir / "size.glint-session");
    writeImage(Image(5, 5, 2), m_dir / "size.glint-session/layer-0.exr");
    expectRefused("size.glint-session.json", "5x5x2");
    // An unknown filter.
    std::string unknown = text;
    unknown.replace(unknown.find("\"gaussian\""), 10, "\"gausian\"");
    std::ofstream(m_dir / "filter.glint-session.json") << unknown;
    fs::copy(m_dir / "good.glint-session", m_dir / "filter.glint-session");
    expectRefused("filter.glint-session.json", "/layers/0");
    // A failed save (the folder is gone) leaves the good session as it was.
    EXPECT_THROW(s.save(m_dir / "nowhere" / "x.glint-session.json"), Error);
    EXPECT_EQ(Session::load(good).layerCount(), 1u);
    EXPECT_THROW(s.save(m_dir / "notjson.txt"), Error);
}

TEST_F(SessionTest, ASaveIntoAFolderThatCannotBeWrittenLeavesTheOldSession) {
    Session old(testing::syntheticFrame(24, 20));
    old.addLayer("gaussian", {});
    old.setWeights(0, Image(24, 20, 1, 0.25f));
    const fs::path folder = m_dir / "locked";
    fs::create_directories(folder);
    const fs::path file = folder / "look.glint-session.json";
    old.save(file);
    Session next(testing::syntheticFrame(24, 20));
    next.addLayer("bilateral", {});
    next.addLayer("gaussian", {});
    fs::permissions(folder, fs::perms::owner_read | fs::perms::owner_exec | fs::perms::group_read |
                                fs::perms::group_exec | fs::perms::others_read |
                                fs::perms::others_exec);
    // Root writes anywhere, whatever the permissions: there a directory standing where the save
    // writes its temporary JSON makes the write fail the same way (no fork: a forked child of a
    // multithreaded process may deadlock).
    const fs::path obstacle = temporaryPathFor(file);
    if (::geteuid() == 0) fs::create_directories(obstacle / "x");
    try {
        next.save(file);
        ADD_FAILURE() << "the save went through";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::Io) << e.what();
    }
    fs::remove_all(obstacle);
    fs::permissions(folder, fs::perms::owner_all, fs::perm_options::add);
    // The old session is whole, and no temporary is left.
    const Session back = Session::load(file);
    ASSERT_EQ(back.layerCount(), 1u);
    EXPECT_TRUE(sameBits(back.layer(0).weights, old.layer(0).weights));
    EXPECT_TRUE(sameBits(back.composite(), old.composite()));
    for (const auto& e : fs::directory_iterator(folder))
        EXPECT_TRUE(e.path() == file || e.path() == folder / "look.glint-session") << e.path();
}

TEST_F(SessionTest, ReapplyKeepsTheHistoryWithOutputsOnTheNewRender) {
    Session s(testing::syntheticFrame(40, 32, 0.05f, 1));
    const std::size_t g = s.addLayer("gaussian", {{"sigma", 2.0}});
    s.setWeights(g, Image(40, 32, 1, 1.0f));
    const std::size_t b = s.addLayer("bilateral", {});
    s.setWeights(b, Image(40, 32, 1, 0.5f));
    s.removeLayer(b);  // history holds the bilateral layer
    EXPECT_EQ(s.layerSpecs().size(), 2u);
    const FrameBuffers next = testing::syntheticFrame(40, 32, 0.05f, 2);
    s.reapply(next);
    ASSERT_TRUE(s.canUndo());
    s.undo();  // the bilateral layer comes back, computed on the new render
    ASSERT_EQ(s.layerCount(), 2u);
    EXPECT_TRUE(sameBits(*s.layer(1).output, applyFilter(findFilter("bilateral"), next, {})));
    EXPECT_TRUE(sameBits(s.composite(), compositeFromScratch(s)));
}

TEST_F(SessionTest, ARenamedLayerIsReappliedOnANewRender) {
    // A rename in the history names no filter: the new render's outputs are the layer's own
    // (found by fuzz_journal: the studio's look edit after a rename failed, "unknown filter ''").
    Session s(testing::syntheticFrame(40, 32, 0.05f, 1));
    const std::size_t g = s.addLayer("gaussian", {{"sigma", 2.0}});
    s.renameLayer(g, "walls");
    s.renameLayer(g, "floor");
    s.undo();  // one rename in the undo history, one in the redo history
    const std::vector<LayerSpec> specs = s.layerSpecs();
    ASSERT_EQ(specs.size(), 1u);
    EXPECT_EQ(specs[0].filter, "gaussian");
    const FrameBuffers next = testing::syntheticFrame(40, 32, 0.05f, 2);
    s.reapply(next);
    EXPECT_EQ(s.layer(g).name, "walls");
    EXPECT_TRUE(
        sameBits(*s.layer(g).output, applyFilter(findFilter("gaussian"), next, {{"sigma", 2.0}})));
    s.redo();
    EXPECT_EQ(s.layer(g).name, "floor");
    EXPECT_TRUE(sameBits(s.composite(), compositeFromScratch(s)));
}

TEST_F(SessionTest, ReapplyKeepsThePaintingOnANewRender) {
    Session s(testing::syntheticFrame(40, 32, 0.05f, 1));
    const std::size_t g = s.addLayer("gaussian", {{"sigma", 2.0}});
    s.setWeights(g, Image(40, 32, 1, 0.75f));
    const Image weights = s.layer(g).weights;
    const FrameBuffers next = testing::syntheticFrame(40, 32, 0.05f, 2);
    s.reapply(next);
    EXPECT_TRUE(sameBits(s.input().color(), next.color()));
    EXPECT_TRUE(sameBits(s.layer(g).weights, weights));
    EXPECT_TRUE(
        sameBits(*s.layer(g).output, applyFilter(findFilter("gaussian"), next, {{"sigma", 2.0}})));
    EXPECT_TRUE(sameBits(s.composite(), compositeFromScratch(s)));
    // Another size is refused and changes nothing.
    const SessionState before = stateOf(s);
    try {
        s.reapply(testing::syntheticFrame(10, 10));
        ADD_FAILURE() << "a 10x10 render was accepted";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::InvalidArgument);
        EXPECT_NE(std::string(e.what()).find("10x10"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("40x32"), std::string::npos) << e.what();
    }
    EXPECT_THROW(s.reapply(testing::syntheticFrame(40, 31), std::vector<Image>{Image(40, 31, 3)}),
                 Error);
    EXPECT_EQ(differences(stateOf(s), before), "");
    EXPECT_TRUE(sameBits(s.input().color(), next.color()));
    EXPECT_TRUE(s.canUndo());
}

TEST_F(SessionTest, LayerOutputsAreSharedNotCopied) {
    Session s(testing::syntheticFrame(40, 32, 0.05f, 1));
    const std::size_t g = s.addLayer("gaussian", {{"sigma", 2.0}});
    const Image* output = s.layer(g).output.get();
    s.removeLayer(g);
    s.undo();  // the layer comes back from the history: the same image, not a copy
    EXPECT_EQ(s.layer(g).output.get(), output);
    // A re-application gives the current layer and the history's copy one new image.
    s.setWeights(g, Image(40, 32, 1, 0.5f));
    s.removeLayer(g);
    s.reapply(testing::syntheticFrame(40, 32, 0.05f, 2));
    s.undo();
    const Image* fresh = s.layer(g).output.get();
    EXPECT_NE(fresh, output);
    s.undo();  // weights back to 0
    s.undo();  // the layer removed (its AddLayer undone)
    s.redo();
    EXPECT_EQ(s.layer(g).output.get(), fresh);
}

TEST_F(SessionTest, APreparedReapplicationEqualsReapplyBitForBit) {
    auto painted = [] {
        Session s(testing::syntheticFrame(40, 32, 0.05f, 1));
        const std::size_t g = s.addLayer("gaussian", {{"sigma", 2.0}});
        s.setWeights(g, Image(40, 32, 1, 0.75f));
        const std::size_t b = s.addLayer("bilateral", {});
        s.beginStroke(b, Brush{6.0, 0.5}, BrushMode::Add);
        s.dab(20.0, 16.0);
        s.endStroke();
        const std::size_t m = s.addLayer("gaussian", {{"sigma", 1.0}});
        s.removeLayer(m);  // the history holds a third filter
        return s;
    };
    const FrameBuffers next = testing::syntheticFrame(40, 32, 0.05f, 2);
    Session direct = painted();
    direct.reapply(next);
    Session prepared = painted();
    const Session::Snapshot snap = prepared.snapshot();
    ASSERT_EQ(snap.specs.size(), 3u);
    ASSERT_EQ(snap.uses.size(), 2u);
    Session::Reapplication r = Session::prepareReapply(
        next, Session::computeOutputs(next, snap.options, snap.specs), snap);
    prepared.reapply(std::move(r));
    EXPECT_EQ(differences(stateOf(prepared), stateOf(direct)), "");
    EXPECT_TRUE(sameBits(prepared.composite(), compositeFromScratch(prepared)));
    prepared.undo();  // the median layer comes back on the new render
    direct.undo();
    EXPECT_EQ(differences(stateOf(prepared), stateOf(direct)), "");
}

TEST_F(SessionTest, APreparedReapplicationKeepsTheFilterInputItIsGiven) {
    // The studio prefilters a new render's features once, for the filters, and hands them to
    // prepareReapply: the session keeps them rather than prefiltering again.
    SessionOptions options;
    options.prefilter = true;
    auto painted = [&] {
        Session s(testing::syntheticFrame(40, 32, 0.05f, 1), options);
        const std::size_t g = s.addLayer("gaussian", {{"sigma", 2.0}});
        s.setWeights(g, Image(40, 32, 1, 0.5f));
        return s;
    };
    const FrameBuffers next = testing::syntheticFrame(40, 32, 0.05f, 2);
    const FrameBuffers prefiltered = prefilterFeatures(next, options.prefilterParams);
    Session made = painted(), given = painted(), other = painted();
    const Session::Snapshot snap = made.snapshot();
    const std::vector<Image> outputs = Session::computeOutputs(next, snap.options, snap.specs);
    made.reapply(Session::prepareReapply(next, outputs, snap));
    given.reapply(Session::prepareReapply(next, outputs, snap, prefiltered));
    EXPECT_EQ(differences(stateOf(given), stateOf(made)), "");
    for (Layer l : {Layer::Albedo, Layer::Normal, Layer::Depth})
        EXPECT_TRUE(sameBits(given.filterInput().layer(l), made.filterInput().layer(l)));
    // A filter input that prefiltering would not make (one albedo pixel marked) is the one kept:
    // prepareReapply did not make its own.
    FrameBuffers marked = prefiltered;
    marked.layer(Layer::Albedo)(3, 2, 0) += 0.125f;
    other.reapply(Session::prepareReapply(next, outputs, other.snapshot(), marked));
    EXPECT_TRUE(sameBits(other.filterInput().layer(Layer::Albedo), marked.layer(Layer::Albedo)));
    // A filter input of another size is refused; without prefiltering one is not kept.
    EXPECT_THROW(Session::prepareReapply(next, outputs, snap,
                                         prefilterFeatures(testing::syntheticFrame(20, 16))),
                 Error);
    Session plain(testing::syntheticFrame(40, 32, 0.05f, 1));
    plain.addLayer("gaussian", {{"sigma", 2.0}});
    const Session::Snapshot plainSnap = plain.snapshot();
    plain.reapply(Session::prepareReapply(
        next, Session::computeOutputs(next, plainSnap.options, plainSnap.specs), plainSnap,
        marked));
    EXPECT_TRUE(sameBits(plain.filterInput().layer(Layer::Albedo), next.layer(Layer::Albedo)));
}

TEST_F(SessionTest, APreparedReapplicationFollowsEditsMadeMeanwhile) {
    Session s(testing::syntheticFrame(40, 32, 0.05f, 1));
    const std::size_t g = s.addLayer("gaussian", {{"sigma", 2.0}});
    s.setWeights(g, Image(40, 32, 1, 0.25f));
    const FrameBuffers next = testing::syntheticFrame(40, 32, 0.05f, 2);
    const Session::Snapshot snap = s.snapshot();
    Session::Reapplication r = Session::prepareReapply(
        next, Session::computeOutputs(next, snap.options, snap.specs), snap);
    // An edit while the worker prepared: its composite is stale and is rebuilt on install.
    s.setWeights(g, Image(40, 32, 1, 1.0f));
    s.reapply(std::move(r));
    EXPECT_TRUE(sameBits(s.composite(), compositeFromScratch(s)));
    EXPECT_TRUE(sameBits(s.composite(), *s.layer(g).output));
    // A layer added meanwhile: the preparation is of other layers and is refused.
    const Session::Snapshot old = s.snapshot();
    Session::Reapplication stale =
        Session::prepareReapply(next, Session::computeOutputs(next, old.options, old.specs), old);
    s.addLayer("bilateral", {});
    const SessionState before = stateOf(s);
    EXPECT_THROW(s.reapply(std::move(stale)), Error);
    EXPECT_EQ(differences(stateOf(s), before), "");
    // Outputs that do not fit the snapshot are refused while preparing.
    EXPECT_THROW(Session::prepareReapply(next, {}, old), Error);
}

TEST_F(SessionTest, ExportsTheCompositeAndRefusesBadEdits) {
    Session s(testing::syntheticFrame(24, 20));
    const std::size_t g = s.addLayer("gaussian", {});
    s.setWeights(g, Image(24, 20, 1, 1.0f));
    s.exportExr(m_dir / "out.exr");
    s.exportPng(m_dir / "out.png");
    const FrameBuffers out = readExr(m_dir / "out.exr");
    EXPECT_TRUE(sameBits(out.color(), s.composite()));
    EXPECT_TRUE(out.has(Layer::Albedo));
    // The render stays in the file (layer noisy) and the file says it is denoised.
    ASSERT_TRUE(out.has(Layer::Noisy));
    EXPECT_TRUE(sameBits(out.layer(Layer::Noisy), testing::syntheticFrame(24, 20).color()));
    EXPECT_EQ(out.metadata().extra.at("denoiseSession"), "1 layer");
    EXPECT_TRUE(fs::exists(m_dir / "out.png"));
    EXPECT_THROW(s.addLayer("nope", {}), Error);
    EXPECT_THROW(s.addLayer("gaussian", {{"sigma", -1.0}}), Error);
    EXPECT_THROW(s.addLayer("gaussian", {}, Image(3, 3, 3)), Error);
    EXPECT_THROW(s.beginStroke(7, Brush{}, BrushMode::Add), Error);
    EXPECT_THROW(s.dab(1.0, 1.0), Error);  // no stroke open
    s.beginStroke(g, Brush{}, BrushMode::Add);
    EXPECT_THROW(s.beginStroke(g, Brush{}, BrushMode::Add), Error);
    EXPECT_THROW(s.addLayer("gaussian", {}), Error);  // a stroke is open
    s.endStroke();
    EXPECT_EQ(s.layerCount(), 1u);
}

}  // namespace
}  // namespace glint::denoise

namespace glint::denoise {
namespace {

// The split forms the studio uses (heavy work on a worker thread, the edit on the UI thread)
// give exactly what the one-call forms give.
TEST(SessionSplit, ComputedElsewhereEqualsInPlace) {
    Session a(testing::syntheticFrame(40, 32, 0.05f, 1)),
        b(testing::syntheticFrame(40, 32, 0.05f, 1));
    for (Session* s : {&a, &b}) {
        const std::size_t g = s->addLayer("gaussian", {{"sigma", 2.0}});
        s->beginStroke(g, Brush{10.0, 0.5}, BrushMode::Add);
        s->dab(8.0, 8.0);
        s->endStroke();
        s->beginStroke(g, Brush{10.0, 0.5}, BrushMode::Subtract);
        s->dab(32.0, 24.0);
        s->endStroke();
    }
    a.diffuse({0});
    b.applyWeights({0}, b.diffusionMaps({0}));
    EXPECT_TRUE(sameBits(a.layer(0).weights, b.layer(0).weights));
    EXPECT_TRUE(sameBits(a.composite(), b.composite()));
    const FrameBuffers next = testing::syntheticFrame(40, 32, 0.05f, 2);
    a.reapply(next);
    b.reapply(next, Session::computeOutputs(next, b.options(), b.layerSpecs()));
    EXPECT_TRUE(sameBits(a.composite(), b.composite()));
    EXPECT_THROW(b.reapply(next, std::vector<Image>{}), Error);
    EXPECT_THROW(b.applyWeights({0}, {Image(3, 3, 1)}), Error);
}

}  // namespace
}  // namespace glint::denoise

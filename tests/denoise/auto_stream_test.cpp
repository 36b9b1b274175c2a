// The automatic selection's tiles (pipeline.h; docs/auto-memory.md): on tiny strips, so that
// every strip boundary and every margin (the filters', the choice's windows, feathering, the
// stacking's windows and tiles) is crossed, without the bank's results (auto_stream.h) it gives
// autoComposite's result over the whole bank, for SURE and for the halves with a shortlist,
// feathering and stacking, and one tile and many give the same floats; it reports progress and
// stops when told. Its spill file changes no value, and a spill that cannot be written gives the
// same result. The tiles' height follows the memory budget.
#include <gtest/gtest.h>
#include <sys/resource.h>

#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "auto/options.h"
#include "auto/pipeline.h"
#include "auto/stacking.h"
#include "bank/bank_detail.h"
#include "glint/denoise/auto.h"
#include "glint/denoise/auto_stream.h"
#include "glint/denoise/bank.h"
#include "glint/image/error.h"
#include "halves_frames.h"

namespace glint::denoise {
namespace {

using namespace halves_test;

// A 96×64 frame with half buffers and, for the stacking's regressors, an albedo and a normal
// (with their halves) that change across the disc's edge and the checkerboard.
FrameBuffers featureFrame(std::uint32_t seed) {
    const Image clean = cleanImage(96, 64);
    FrameBuffers f = halvesFrame(clean, 0.08, Noise::Skewed, seed);
    Image albedo(96, 64, 3), normal(96, 64, 3);
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 96; ++x) {
            for (int c = 0; c < 3; ++c) albedo(x, y, c) = 0.5f * clean(x, y, c) + 0.2f;
            const float tilt = x >= 48 ? 0.3f : 0.0f;
            normal(x, y, 0) = tilt, normal(x, y, 1) = 0.1f, normal(x, y, 2) = 0.95f;
        }
    for (Layer l : {Layer::Albedo, Layer::HalfAlbedo}) f.set(l, albedo);
    for (Layer l : {Layer::Normal, Layer::HalfNormal}) f.set(l, normal);
    return f;
}

// Tiles of `rows` rows, with the spill as given.
detail::TileControl tiles(int rows, detail::SpillMode spill = detail::SpillMode::Auto) {
    return {rows, spill};
}

BankOptions smallBank() {
    BankOptions b;
    b.size = 8;
    b.filters = {"gaussian", "bilateral", "cross-bilateral"};
    return b;
}

// The largest difference between two images of one shape.
double maxDifference(const Image& a, const Image& b) {
    EXPECT_TRUE(a.sameShape(b));
    double d = 0.0;
    for (std::size_t i = 0; i < a.data().size(); ++i)
        d = std::max(d, std::fabs(double(a.data()[i]) - double(b.data()[i])));
    return d;
}

// The streamed result against autoComposite's over the same bank. A filter over a strip gives
// the strip of its whole-frame output and the passes add up their sums in the same order (the
// stacking's too, tile after tile), so everything is the same, value for value.
void expectSame(const AutoResult& whole, const StreamedAuto& streamed, const FilterBank& bank) {
    const AutoResult& s = streamed.result;
    ASSERT_EQ(streamed.bank.size(), bank.size());
    for (std::size_t m = 0; m < bank.size(); ++m) {
        EXPECT_EQ(streamed.bank.members()[m].filter, bank.members()[m].filter);
        EXPECT_EQ(streamed.bank.members()[m].params, bank.members()[m].params);
    }
    EXPECT_EQ(streamed.bank.region(), bank.region());
    EXPECT_EQ(streamed.bank.inputHash(), bank.inputHash());
    EXPECT_TRUE(streamed.bank.results().empty());
    ASSERT_EQ(s.estimatedMse.size(), whole.estimatedMse.size());
    for (std::size_t m = 0; m < s.estimatedMse.size(); ++m)
        EXPECT_EQ(s.estimatedMse[m], whole.estimatedMse[m]) << "member " << m;
    EXPECT_EQ(s.bestMember, whole.bestMember);
    EXPECT_EQ(s.analytic, whole.analytic);
    EXPECT_EQ(s.stacked, whole.stacked);
    EXPECT_EQ(s.stackFeatures, whole.stackFeatures);
    ASSERT_EQ(s.layers.size(), whole.layers.size());
    for (std::size_t i = 0; i < s.layers.size(); ++i) {
        EXPECT_EQ(s.layers[i].member, whole.layers[i].member);
        EXPECT_EQ(maxDifference(s.layers[i].weights, whole.layers[i].weights), 0.0);
    }
    EXPECT_EQ(maxDifference(s.choice, whole.choice), 0.0);
    EXPECT_EQ(maxDifference(s.composite, whole.composite), 0.0);
}

// The halves with a shortlist, feathering and stacking (every pass of the streamed selection).
AutoOptions stackingOptions() {
    AutoOptions o;
    o.estimator = AutoEstimator::Halves;
    o.tuning["shortlist"] = 4;
    o.tuning["feather"] = 3;
    o.tuning["stack"] = 2;
    o.tuning["stackWindow"] = 3;
    o.tuning["stackSmooth"] = 2;
    o.tuning["stackFeatureWindow"] = 2;
    return o;
}

TEST(AutoStream, HalvesWithShortlistFeatheringAndStackingMatchTheWholeFrame) {
    const FrameBuffers f = featureFrame(5);
    const BankOptions b = smallBank();
    const FilterBank bank = buildBank(f, b);
    ASSERT_GT(bank.size(), 6u);
    const AutoOptions o = stackingOptions();
    const AutoResult whole = autoComposite(bank, f, o);
    ASSERT_EQ(whole.stacked, 2);
    ASSERT_EQ(whole.stackFeatures, 4);  // the albedo's and the normal's three
    for (int rows : {16, 7, 64}) {
        SCOPED_TRACE("strips of " + std::to_string(rows) + " rows");
        expectSame(whole, detail::autoCompositeStreamed(f, b, o, tiles(rows)), bank);
    }
}

TEST(AutoStream, HalvesInEverySpaceMatchTheWholeFrame) {
    const FrameBuffers f = halvesFrame(cleanImage(96, 64), 0.08, Noise::Fireflies, 9);
    const BankOptions b = smallBank();
    const FilterBank bank = buildBank(f, b);
    for (detail::SureSpace space : {detail::SureSpace::Linear, detail::SureSpace::DisplayTangent,
                                    detail::SureSpace::DisplayExact}) {
        SCOPED_TRACE("space " + std::to_string(int(space)));
        AutoOptions o;
        o.estimator = AutoEstimator::Halves;
        o.tuning["space"] = double(space);
        o.tuning["shortlist"] = 0;  // every member on both halves
        o.tuning["stack"] = 1;
        expectSame(autoComposite(bank, f, o), detail::autoCompositeStreamed(f, b, o, tiles(16)),
                   bank);
    }
}

TEST(AutoStream, SureMatchesTheWholeFrame) {
    const FrameBuffers f = halvesFrame(cleanImage(96, 64), 0.08, Noise::Gaussian, 4);
    const BankOptions b = smallBank();
    const FilterBank bank = buildBank(f, b);
    for (detail::SureSpace space : {detail::SureSpace::Display, detail::SureSpace::Linear}) {
        SCOPED_TRACE("space " + std::to_string(int(space)));
        AutoOptions o;
        o.estimator = AutoEstimator::Sure;
        o.tuning["space"] = double(space);
        o.tuning["feather"] = 2;
        expectSame(autoComposite(bank, f, o), detail::autoCompositeStreamed(f, b, o, tiles(16)),
                   bank);
    }
}

TEST(AutoStream, ReportsProgressToTheEndAndStopsWhenTold) {
    const FrameBuffers f = featureFrame(7);
    const BankOptions b = smallBank();
    AutoOptions o;
    o.estimator = AutoEstimator::Halves;
    o.tuning["shortlist"] = 4;
    o.tuning["stack"] = 2;
    std::mutex mutex;
    std::vector<double> fractions;
    o.progress = [&](double x) {
        const std::lock_guard<std::mutex> lock(mutex);
        fractions.push_back(x);
        return true;
    };
    detail::autoCompositeStreamed(f, b, o, tiles(16));
    ASSERT_GT(fractions.size(), 10u);
    EXPECT_EQ(fractions.front(), 0.0);
    EXPECT_EQ(fractions.back(), 1.0);
    EXPECT_TRUE(std::is_sorted(fractions.begin(), fractions.end()));
    // Stopped at the first report, in the estimates' pass and in the later ones.
    for (double stopAt : {0.0, 0.3, 0.8}) {
        SCOPED_TRACE("stop at " + std::to_string(stopAt));
        o.progress = [stopAt](double x) { return x < stopAt; };
        try {
            detail::autoCompositeStreamed(f, b, o, tiles(16));
            FAIL() << "not cancelled";
        } catch (const Error& e) {
            EXPECT_EQ(e.kind(), ErrorKind::Cancelled) << e.what();
        }
    }
}

constexpr detail::SpillMode kSpillAuto = detail::SpillMode::Auto, kSpillOn = detail::SpillMode::On,
                            kSpillOff = detail::SpillMode::Off;

// Two streamed results equal value for value.
void expectIdentical(const StreamedAuto& a, const StreamedAuto& b) {
    EXPECT_EQ(a.result.estimatedMse, b.result.estimatedMse);
    EXPECT_EQ(a.result.bestMember, b.result.bestMember);
    EXPECT_EQ(a.result.stacked, b.result.stacked);
    ASSERT_EQ(a.result.layers.size(), b.result.layers.size());
    for (std::size_t i = 0; i < a.result.layers.size(); ++i) {
        EXPECT_EQ(a.result.layers[i].member, b.result.layers[i].member);
        EXPECT_EQ(maxDifference(a.result.layers[i].weights, b.result.layers[i].weights), 0.0);
    }
    EXPECT_EQ(maxDifference(a.result.choice, b.result.choice), 0.0);
    EXPECT_EQ(maxDifference(a.result.composite, b.result.composite), 0.0);
}

// The spill stores the floats the filters give, and the stacking reads its rows across the
// strips they were written in: the result with it is the one without it, bit for bit.
TEST(AutoStream, TheSpillGivesTheSameFloatsAsFilteringAgain) {
    const FrameBuffers f = featureFrame(5);
    const BankOptions b = smallBank();
    for (int rows : {7, 16}) {
        SCOPED_TRACE("strips of " + std::to_string(rows) + " rows");
        const StreamedAuto off =
            detail::autoCompositeStreamed(f, b, stackingOptions(), tiles(rows, kSpillOff));
        EXPECT_FALSE(off.spilled);
        EXPECT_TRUE(off.warning.empty()) << off.warning;
        ASSERT_EQ(off.result.stacked, 2);
        const StreamedAuto on =
            detail::autoCompositeStreamed(f, b, stackingOptions(), tiles(rows, kSpillOn));
        EXPECT_TRUE(on.spilled) << on.warning;
        EXPECT_TRUE(on.warning.empty()) << on.warning;
        expectIdentical(on, off);
    }
    // SURE reads the median's pass's results instead of filtering the input again.
    const FrameBuffers g = halvesFrame(cleanImage(96, 64), 0.08, Noise::Gaussian, 4);
    AutoOptions o;
    o.estimator = AutoEstimator::Sure;
    o.tuning["feather"] = 2;
    const StreamedAuto on = detail::autoCompositeStreamed(g, b, o, tiles(16, kSpillAuto));
    EXPECT_TRUE(on.spilled) << on.warning;
    expectIdentical(on, detail::autoCompositeStreamed(g, b, o, tiles(16, kSpillOff)));
}

// Sets an environment variable for its lifetime.
class ScopedEnv {
  public:
    ScopedEnv(const char* name, const char* value) : m_name(name) {
        if (const char* old = std::getenv(name)) m_old = old;
        setenv(name, value, 1);
    }
    ~ScopedEnv() {
        if (m_old)
            setenv(m_name, m_old->c_str(), 1);
        else
            unsetenv(m_name);
    }

  private:
    const char* m_name;
    std::optional<std::string> m_old;
};

// Limits the size of the files this process writes for its lifetime (a write past it fails
// with EFBIG instead of raising SIGXFSZ).
class ScopedFileSizeLimit {
  public:
    explicit ScopedFileSizeLimit(rlim_t bytes) {
        getrlimit(RLIMIT_FSIZE, &m_old);
        m_oldHandler = std::signal(SIGXFSZ, SIG_IGN);
        rlimit limit = m_old;
        limit.rlim_cur = bytes;
        setrlimit(RLIMIT_FSIZE, &limit);
    }
    ~ScopedFileSizeLimit() {
        setrlimit(RLIMIT_FSIZE, &m_old);
        std::signal(SIGXFSZ, m_oldHandler);
    }

  private:
    rlimit m_old{};
    void (*m_oldHandler)(int) = nullptr;
};

TEST(AutoStream, ASpillThatCannotBeWrittenFallsBackWithTheSameResult) {
    const FrameBuffers f = featureFrame(6);
    const BankOptions b = smallBank();
    const StreamedAuto off =
        detail::autoCompositeStreamed(f, b, stackingOptions(), tiles(16, kSpillOff));
    {
        // No file can be created: asked for, a warning; automatic, silently filtered again.
        const ScopedEnv tmp("TMPDIR", "/nonexistent/glint-spill");
        const StreamedAuto on =
            detail::autoCompositeStreamed(f, b, stackingOptions(), tiles(16, kSpillOn));
        EXPECT_FALSE(on.spilled);
        EXPECT_NE(on.warning.find("/nonexistent/glint-spill"), std::string::npos) << on.warning;
        expectIdentical(on, off);
        const StreamedAuto automatic =
            detail::autoCompositeStreamed(f, b, stackingOptions(), tiles(16, kSpillAuto));
        EXPECT_FALSE(automatic.spilled);
        EXPECT_TRUE(automatic.warning.empty()) << automatic.warning;
        expectIdentical(automatic, off);
    }
    {
        // The file stops growing after two of the 96×64 results: the writes fail mid-pass.
        const ScopedFileSizeLimit limit(2 * 96 * 64 * 3 * sizeof(float) + 100);
        const StreamedAuto failed =
            detail::autoCompositeStreamed(f, b, stackingOptions(), tiles(16, kSpillAuto));
        EXPECT_FALSE(failed.spilled);
        EXPECT_NE(failed.warning.find("cannot write"), std::string::npos) << failed.warning;
        expectIdentical(failed, off);
    }
}

// A frame taller than the stacking's regression tiles (kStackTileRows), with half buffers and
// the features, so that the stacking's tiles and its smoothing cross the pipeline's tiles.
FrameBuffers tallFrame(std::uint32_t seed) {
    const Image clean = cleanImage(48, 2 * detail::kStackTileRows + 40);
    FrameBuffers f = halvesFrame(clean, 0.08, Noise::Skewed, seed);
    Image albedo(clean.width(), clean.height(), 3), normal(clean.width(), clean.height(), 3);
    for (int y = 0; y < clean.height(); ++y)
        for (int x = 0; x < clean.width(); ++x) {
            for (int c = 0; c < 3; ++c) albedo(x, y, c) = 0.5f * clean(x, y, c) + 0.2f;
            normal(x, y, 0) = y >= 150 ? 0.3f : 0.0f, normal(x, y, 1) = 0.1f;
            normal(x, y, 2) = 0.95f;
        }
    for (Layer l : {Layer::Albedo, Layer::HalfAlbedo}) f.set(l, albedo);
    for (Layer l : {Layer::Normal, Layer::HalfNormal}) f.set(l, normal);
    return f;
}

// Two results equal value for value (a bank's layers included).
void expectIdentical(const AutoResult& a, const AutoResult& b) {
    EXPECT_EQ(a.estimatedMse, b.estimatedMse);
    EXPECT_EQ(a.bestMember, b.bestMember);
    EXPECT_EQ(a.stacked, b.stacked);
    EXPECT_EQ(a.stackFeatures, b.stackFeatures);
    ASSERT_EQ(a.layers.size(), b.layers.size());
    for (std::size_t i = 0; i < a.layers.size(); ++i) {
        EXPECT_EQ(a.layers[i].member, b.layers[i].member);
        EXPECT_EQ(maxDifference(a.layers[i].weights, b.layers[i].weights), 0.0);
    }
    EXPECT_EQ(maxDifference(a.choice, b.choice), 0.0);
    ASSERT_TRUE(a.composite.sameShape(b.composite));
    EXPECT_EQ(std::memcmp(a.composite.data().data(), b.composite.data().data(),
                          a.composite.data().size() * sizeof(float)),
              0);  // bit for bit
}

// The one pipeline: the whole region as one tile and many tiles of any height give the same
// floats, with the bank's results read by rows or the members applied tile by tile, with the
// default options (the halves, a shortlist, feathering, the stacking with the features) and
// with SURE.
TEST(AutoTiles, OneTileAndManyTilesGiveTheSameFloats) {
    const FrameBuffers f = tallFrame(3);
    const int height = f.height();
    const BankOptions b = smallBank();
    const FilterBank bank = buildBank(f, b);
    AutoOptions o;
    o.tuning["shortlist"] = 4;  // fewer than the members: the shortlist's pass runs
    const detail::TiledAuto one = detail::autoCompositeTiled(bank, f, o, tiles(height));
    ASSERT_EQ(one.result.tileRows, height);
    ASSERT_GT(one.result.stacked, 0);
    ASSERT_EQ(one.result.stackFeatures, 4);
    for (int rows : {height / 2 + 1, 100, 37}) {
        SCOPED_TRACE("tiles of " + std::to_string(rows) + " rows");
        const detail::TiledAuto many = detail::autoCompositeTiled(bank, f, o, tiles(rows));
        EXPECT_EQ(many.result.tileRows, rows);
        expectIdentical(one.result, many.result);
        expectIdentical(one.result, detail::autoCompositeStreamed(f, b, o, tiles(rows)).result);
    }
    AutoOptions sure;
    sure.estimator = AutoEstimator::Sure;
    const AutoResult oneSure = detail::autoCompositeTiled(bank, f, sure, tiles(height)).result;
    expectIdentical(oneSure, detail::autoCompositeTiled(bank, f, sure, tiles(45)).result);
    expectIdentical(oneSure, detail::autoCompositeStreamed(f, b, sure, tiles(45)).result);
}

// The tiles' height comes from the memory budget: one tile when the region fits, fewer rows as
// the budget shrinks (never below the lowest height but where the region is lower), tiles of
// one height; and AutoOptions::memoryLimit sets it without changing a value.
TEST(AutoTiles, TheTileHeightFollowsTheMemoryBudget) {
    const FrameBuffers f = tallFrame(4);
    const int height = f.height();
    const BankOptions b = smallBank();
    const FilterBank bank = buildBank(f, b);
    const FilterBank unbuilt = autoCompositeStreamed(f, b, {}).bank;
    const detail::AutoSettings s = detail::resolveSettings(bank, f, {});
    const std::uint64_t fixed = detail::autoFixedMemory(unbuilt, f, s);
    EXPECT_EQ(detail::autoTileRows(unbuilt, f, s, std::uint64_t(1) << 40), height);
    int previous = height;
    for (std::uint64_t extra : {std::uint64_t(1) << 20, std::uint64_t(1) << 19, std::uint64_t(0)}) {
        const int rows = detail::autoTileRows(unbuilt, f, s, fixed + extra);
        EXPECT_LE(rows, previous) << extra;
        EXPECT_GE(rows, detail::kMinTileRows * 3 / 4) << extra;  // evened out below the lowest
        const int count = (height + rows - 1) / rows;
        EXPECT_LT(count * rows - height, count) << rows;  // tiles of one height, but for rounding
        previous = rows;
    }
    EXPECT_LT(previous, height);
    // The bank's results are not the selection's to hold: with them, taller tiles.
    EXPECT_GE(detail::autoTileRows(bank, f, s, fixed + (std::uint64_t(1) << 19)),
              detail::autoTileRows(unbuilt, f, s, fixed + (std::uint64_t(1) << 19)));
    // The public option: a tiny budget tiles the frame; the same floats as one tile.
    AutoOptions tight;
    tight.memoryLimit = 1;
    const AutoResult tiled = autoComposite(bank, f, tight);
    EXPECT_LT(tiled.tileRows, height);
    const AutoResult whole = autoComposite(bank, f, {});
    EXPECT_EQ(whole.tileRows, height);
    expectIdentical(whole, tiled);
    EXPECT_EQ(autoMemoryBudget(1000), 1000u);
    EXPECT_LE(autoMemoryBudget(0), detail::kDefaultAutoMemory);
}

// A render's layers (all but the position and a denoiser's noisy layer) on a w × h frame, the w × h
// ones two images shared (130 MB at 4K, not 1.4 GB), with the settings and the bank's members of a
// small render.
struct RenderLike {
    FrameBuffers frame;
    FilterBank bank;
    detail::AutoSettings settings;
};
RenderLike renderLike(int w, int h) {
    std::vector<Layer> layers;
    for (int l = 0; l < kLayerCount; ++l)
        if (Layer(l) != Layer::Position && Layer(l) != Layer::Noisy) layers.push_back(Layer(l));
    FrameBuffers small(16, 16);
    for (Layer l : layers) small.ensure(l);
    small.layer(Layer::SampleCount).fill(4.0f);
    small.layer(Layer::HalfSampleCount).fill(2.0f);
    const FilterBank smallBank = detail::bankWithoutResults(small, BankOptions{});
    RenderLike r{FrameBuffers(w, h), FilterBank(smallBank.members(), {}, Rect{0, w, 0, h}, w, h, 0),
                 detail::resolveSettings(smallBank, small, {})};
    r.frame.set(Layer::Depth, Image(w, h, 1));
    for (Layer l : layers)
        if (l != Layer::Color && l != Layer::Depth)
            r.frame.shareLayer(l, r.frame,
                               layerInfo(l).channels == 3 ? Layer::Color : Layer::Depth);
    return r;
}

// At 3840×2160, a render with half buffers (42 floats a pixel, as glint-render --set
// halfBuffers=true writes them), the default bank and the default budget: the model's estimate of
// the peak — the frame, half A's own layers (half B is the frame's layers, shared), the most the
// blend or the stacking holds, a band and a tile — is under 4 GB (issue 47; docs/lab/auto-memory.md
// has the measured peak), and counts at least the frame and half A's 21 floats a pixel.
TEST(AutoTiles, TheModelsEstimateForA4KRenderIsUnderFourGigabytes) {
    const int w = 3840, h = 2160;
    const RenderLike r = renderLike(w, h);
    ASSERT_TRUE(r.settings.halves);
    ASSERT_GT(r.settings.stack, 0);
    const detail::TileModel model = detail::autoTileModel(r.bank, true, true, 2);
    const std::uint64_t estimate =
        detail::autoMemoryEstimate(r.bank, r.frame, r.settings, detail::kDefaultAutoMemory, model);
    EXPECT_LE(estimate, std::uint64_t(4000000000));
    EXPECT_GE(estimate, std::uint64_t(w) * std::uint64_t(h) * (42 + 21) * sizeof(float));
}

// The learned member's own budget is what the default budget leaves beside half A: at 1920×1080
// its default, 1024 MiB, as the in-memory path gave it (0.6 of the room, 668 MiB, cut its
// U-Net into 6 tiles of 2.9 Mpx in all instead of 2 of 2.3 Mpx: CPU time;
// docs/lab/auto-memory.md), and at 4K no more than the room.
TEST(AutoTiles, TheLearnedMemberKeepsItsDefaultBudgetAt1080p) {
    const RenderLike hd = renderLike(1920, 1080);
    EXPECT_EQ(
        detail::autoMemberMemoryMB(hd.bank, hd.frame, hd.settings, detail::kDefaultAutoMemory),
        1024.0);
    const RenderLike uhd = renderLike(3840, 2160);
    // Half A's own layers: the colour, albedo, normal and depth, their variances, the counts.
    const double room = double(detail::kDefaultAutoMemory) - 3840.0 * 2160.0 * 21.0 * 4.0;
    const double mb =
        detail::autoMemberMemoryMB(uhd.bank, uhd.frame, uhd.settings, detail::kDefaultAutoMemory);
    EXPECT_LE(mb * 1048576.0, room);
    EXPECT_GT(mb, 256.0);
}

// Banded (the spill on, no bank results): each member is applied into the spill and the median
// and the blend read the results back band by band, and the error maps live in a spill file of
// their own; bands of any height give the floats of the results and maps held, with the halves
// (a shortlist, feathering, the stacking) and with SURE.
TEST(AutoTiles, BandsAndSpilledErrorMapsGiveTheSameFloatsAsHeldOnes) {
    const FrameBuffers f = tallFrame(5);
    const BankOptions b = smallBank();
    const FilterBank unbuilt = autoCompositeStreamed(f, b, {}).bank;
    AutoOptions sure;
    sure.estimator = AutoEstimator::Sure;
    for (const AutoOptions& o : {AutoOptions{}, stackingOptions(), sure}) {
        const detail::TiledAuto held =
            detail::autoCompositeTiled(unbuilt, f, o, tiles(100, kSpillOff));
        EXPECT_EQ(held.bandRows, 0);
        EXPECT_FALSE(held.mapsSpilled);
        for (int band : {1, 7, 100}) {
            SCOPED_TRACE("bands of " + std::to_string(band) + " rows");
            detail::TileControl control = tiles(100, kSpillOn);
            control.bandRows = band;
            const detail::TiledAuto banded = detail::autoCompositeTiled(unbuilt, f, o, control);
            EXPECT_EQ(banded.bandRows, band);
            EXPECT_TRUE(banded.mapsSpilled);
            expectIdentical(banded.result, held.result);
        }
    }
}

// With the spill, a tile holds the filters under way, not every member's result: its height
// follows the budget at kApplyBytesPerPixel per filter and pixel whatever the bank's size. The
// model bands only where that costs less than the bank's results (12 bytes a pixel a member),
// with the spill and without the bank's results.
TEST(AutoTiles, BandedTilesTakeTheFiltersUnderWayNotTheBank) {
    const FrameBuffers f = tallFrame(4);
    BankOptions b = smallBank();
    b.size = 24;
    const FilterBank bank = buildBank(f, b);
    const FilterBank unbuilt = autoCompositeStreamed(f, b, {}).bank;
    const std::size_t n = unbuilt.size();
    ASSERT_GT(12 * n, detail::kApplyBytesPerPixel);
    const detail::TileModel one = detail::autoTileModel(unbuilt, true, true, 1);
    EXPECT_TRUE(one.banded);
    EXPECT_TRUE(one.mapsSpilled);
    EXPECT_FALSE(detail::autoTileModel(unbuilt, true, true, int(n)).banded);
    EXPECT_FALSE(detail::autoTileModel(unbuilt, false, false, 1).banded);
    EXPECT_FALSE(detail::autoTileModel(bank, true, true, 1).banded);
    const detail::AutoSettings s = detail::resolveSettings(bank, f, {});
    const std::uint64_t fixed = detail::autoFixedMemory(unbuilt, f, s, one);
    // A band (or the choice's score strip) is in the fixed part; the maps are not.
    detail::TileModel spilledMaps;
    spilledMaps.mapsSpilled = true;
    EXPECT_EQ(fixed, detail::autoFixedMemory(unbuilt, f, s, spilledMaps) + detail::kBandBytes);
    EXPECT_LT(detail::autoFixedMemory(unbuilt, f, s, spilledMaps),
              detail::autoFixedMemory(unbuilt, f, s, {}));
    const std::uint64_t perRow = std::uint64_t(f.width()) * (detail::kApplyBytesPerPixel + 64);
    // Room for 100 rows of the region's 296: three tiles of 99.
    EXPECT_EQ(detail::autoTileRows(unbuilt, f, s, fixed + 100 * perRow, one), 99);
    EXPECT_EQ(detail::autoTileRows(unbuilt, f, s, fixed + 296 * perRow, one), 296);
    // Two filters at once: fewer rows than one's 200, evened out (three tiles of 99).
    detail::TileModel two = one;
    two.concurrency = 2;
    EXPECT_EQ(detail::autoTileRows(unbuilt, f, s, fixed + 200 * perRow, one), 148);
    EXPECT_EQ(detail::autoTileRows(unbuilt, f, s, fixed + 200 * perRow, two), 99);
    // The band: every member's result (the input's) in kBandBytes, at most the region.
    EXPECT_EQ(detail::autoBandRows(unbuilt, s), f.height());
}

// The stacking's feature regressors (one image per regressor on each of the three sides) go to
// the spill and are read back by rows instead of being held over the frame: the spill grows by
// exactly their bytes, and the floats are those with the spill off.
TEST(AutoTiles, TheStackingsFeatureRegressorsAreReadFromTheSpill) {
    const FrameBuffers f = tallFrame(6);
    const BankOptions b = smallBank();
    const FilterBank unbuilt = autoCompositeStreamed(f, b, {}).bank;
    AutoOptions without;
    without.tuning["stackAlbedo"] = 2;  // off
    without.tuning["stackNormal"] = 2;
    const detail::TiledAuto plain = detail::autoCompositeTiled(unbuilt, f, without, tiles(100));
    ASSERT_EQ(plain.result.stackFeatures, 0);
    const detail::TiledAuto with = detail::autoCompositeTiled(unbuilt, f, {}, tiles(100));
    ASSERT_GT(with.result.stackFeatures, 0);
    EXPECT_EQ(with.spillBytes - plain.spillBytes,
              3 * std::uint64_t(with.result.stackFeatures) * std::uint64_t(f.width()) *
                  std::uint64_t(f.height()) * 3 * sizeof(float));
    expectIdentical(with.result,
                    detail::autoCompositeTiled(unbuilt, f, {}, tiles(100, kSpillOff)).result);
}

TEST(AutoStream, RejectsBadBankOptions) {
    const FrameBuffers f = halvesFrame(cleanImage(32, 24), 0.08, Noise::Gaussian, 1);
    BankOptions b;
    b.size = 0;
    b.filters = {"no-such-filter"};
    EXPECT_THROW(autoCompositeStreamed(f, b, {}), Error);
}

}  // namespace
}  // namespace glint::denoise

// The steering loop's refresh (glint/pipeline/refresh.h), shared by glint-final and the studio's
// Keep Refining: when a refresh is due, the map's schedule scale, and the focus that keeps only
// the worst pixels open; a refresh at convergence only of a grown frame; auto in an arena of the
// threads asked for, with the same bits.
#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include "glint/pipeline/refresh.h"
#include "glint/pipeline/steering.h"
#include "glint/render/renderer.h"
#include "glint/render/scene.h"

namespace glint::pipeline {
namespace {

/// A 4 × 1 frame whose pixels took `spp` samples each.
FrameBuffers frameAt(float spp) {
    FrameBuffers f(4, 1);
    f.ensure(Layer::SampleCount).fill(spp);
    return f;
}

/// A refresh's result with this relative error at `spp` samples a pixel.
Denoised denoisedAt(double spp, const Image& relative) {
    Denoised d;
    d.relative = relative;
    d.relMse = estimatedRelMse(relative);
    d.meanSpp = spp;
    return d;
}

Image ramp() {
    Image relative(4, 1, 1);
    for (int x = 0; x < 4; ++x) relative(x, 0, 0) = float(x + 1);
    return relative;
}

TEST(Refresh, IsDueFirstAndThenWhenTheSamplesGrewByTheFactor) {
    RefreshOptions o;
    o.growth = 1.5;
    Refresher r(o);
    EXPECT_TRUE(r.due(frameAt(16.0f)));
    r.adopt(denoisedAt(16.0, ramp()));
    EXPECT_FALSE(r.due(frameAt(23.0f)));
    EXPECT_TRUE(r.due(frameAt(24.0f)));
    EXPECT_EQ(r.refreshes(), 1);
}

TEST(Refresh, TheMapIsAutosErrorAtTheScheduleScale) {
    Refresher r(RefreshOptions{});
    r.adopt(denoisedAt(16.0, ramp()));
    const Image first = *r.map();
    const Image expected = importanceFromError(ramp(), 1.0);
    for (int x = 0; x < 4; ++x) EXPECT_FLOAT_EQ(first(x, 0, 0), expected(x, 0, 0));
    // Four times the samples: twice the scale (the renderer's error halved).
    r.adopt(denoisedAt(64.0, ramp()));
    const Image later = *r.map();
    for (int x = 0; x < 4; ++x) EXPECT_FLOAT_EQ(later(x, 0, 0), 2.0f * expected(x, 0, 0));
}

TEST(Refresh, TheFocusKeepsOnlyTheWorstPixelsOpen) {
    RefreshOptions o;
    o.focus = 0.5;  // the worst two of four
    Refresher r(o);
    r.adopt(denoisedAt(16.0, ramp()));
    const Image map = *r.map();
    const Image expected = importanceFromError(ramp(), 1.0);
    EXPECT_EQ(map(0, 0, 0), 0.0f);
    EXPECT_EQ(map(1, 0, 0), 0.0f);
    EXPECT_FLOAT_EQ(map(2, 0, 0), expected(2, 0, 0));
    EXPECT_FLOAT_EQ(map(3, 0, 0), expected(3, 0, 0));
}

TEST(Refresh, TheFocusKeepsExactlyItsShareOpenWhenScoresTie) {
    // Four pixels of one relative error: the focus's two stay open (the first two), not all
    // four (a neighbourhood's mean makes equal scores common).
    RefreshOptions o;
    o.focus = 0.5;
    Refresher r(o);
    r.adopt(denoisedAt(16.0, Image(4, 1, 1, 0.25f)));
    const Image map = *r.map();
    EXPECT_GT(map(0, 0, 0), 0.0f);
    EXPECT_GT(map(1, 0, 0), 0.0f);
    EXPECT_EQ(map(2, 0, 0), 0.0f);
    EXPECT_EQ(map(3, 0, 0), 0.0f);
}

/// A 16 spp frame of grey (0.5) whose variance of the mean is `variance[x]` at column x.
FrameBuffers provisionalFrame(const std::vector<float>& variance) {
    FrameBuffers f(int(variance.size()), 1);
    f.ensure(Layer::SampleCount).fill(16.0f);
    f.ensure(Layer::Color).fill(0.5f);
    Image& v = f.ensure(Layer::Variance);
    for (int x = 0; x < f.width(); ++x)
        for (int c = 0; c < 3; ++c) v(x, 0, c) = variance[std::size_t(x)];
    return f;
}

/// Four regions of five columns whose relative variances (the colour's square plus 0.01 is 0.26)
/// are 0.04, 0.4, 0.004, 4.
std::vector<float> fourRegions() {
    const float v[] = {0.0104f, 0.104f, 0.00104f, 1.04f};
    std::vector<float> out;
    for (float r : v) out.insert(out.end(), 5, r);
    return out;
}

TEST(Refresh, TheProvisionalMapOpensTheNoisiestRegions) {
    RefreshOptions o;
    o.focus = 0.5;
    const Refresher r(o);
    const Image map = *r.provisional(provisionalFrame(fourRegions()));
    // The regions' centres: the two noisiest open, the two quietest closed.
    EXPECT_EQ(map(2, 0, 0), 0.0f);
    EXPECT_EQ(map(7, 0, 0), 1.0f);
    EXPECT_EQ(map(12, 0, 0), 0.0f);
    EXPECT_EQ(map(17, 0, 0), 1.0f);
}

TEST(Refresh, AProvisionalMapsShareNarrowsItToTheWorstOfTheFocus) {
    RefreshOptions o;
    o.focus = 0.5;
    const Refresher r(o);
    // Half of the focus (five of twenty): the noisiest region alone.
    const Image map = *r.provisional(provisionalFrame(fourRegions()), 0.5);
    for (int x = 0; x < 20; ++x) EXPECT_EQ(map(x, 0, 0), x >= 15 ? 1.0f : 0.0f) << "column " << x;
}

TEST(Refresh, TheProvisionalMapScoresAPixelByItsNeighbourhoodNotItsOwnSamplesAlone) {
    // One pixel whose own samples look noisiest (relative variance 1) in a quiet region, and a
    // region of moderate noise (0.4). Opened by its own samples alone, the spike is chosen and the
    // quiet pixels that kept their few samples stay closed: the bias of adaptive sampling by a
    // pixel's own samples (docs/lab/adaptive-bias.md). Scored on its 5 × 5 neighbourhood it is not.
    std::vector<float> v(16, 0.00104f);
    v[2] = 0.26f;
    for (int x = 10; x < 16; ++x) v[std::size_t(x)] = 0.104f;
    RefreshOptions o;
    o.focus = 0.25;  // four of sixteen
    const Refresher r(o);
    const Image map = *r.provisional(provisionalFrame(v));
    EXPECT_EQ(map(2, 0, 0), 0.0f);
    EXPECT_EQ(map(0, 0, 0), 0.0f);
    EXPECT_EQ(map(13, 0, 0), 1.0f);
    EXPECT_EQ(map(14, 0, 0), 1.0f);
}

TEST(Refresh, TheProvisionalMapDecidesWithHalfBAloneWhenTheFrameHasIt) {
    // The whole frame says the first region is the noisiest, half B the last: the map follows
    // half B, so half A (the even samples) never decides and stays an unbiased estimate (docs/lab/
    // adaptive-bias.md: the whole frame's bias then halves). A frame without halves: the whole.
    std::vector<float> whole = fourRegions(), halfB = fourRegions();
    for (int x = 0; x < 5; ++x) std::swap(whole[std::size_t(x)], whole[std::size_t(15 + x)]);
    FrameBuffers f = provisionalFrame(whole);
    f.ensure(Layer::HalfSampleCount).fill(8.0f);
    f.ensure(Layer::HalfColor).fill(0.5f);
    Image& v = f.ensure(Layer::HalfVariance);
    for (int x = 0; x < f.width(); ++x)
        for (int c = 0; c < 3; ++c) v(x, 0, c) = 2.0f * halfB[std::size_t(x)];
    RefreshOptions o;
    o.focus = 0.25;  // five of twenty: the noisiest region
    const Refresher r(o);
    const Image map = *r.provisional(f);
    for (int x = 0; x < 20; ++x) EXPECT_EQ(map(x, 0, 0), x >= 15 ? 1.0f : 0.0f) << "column " << x;
    const Image wholeMap = *r.provisional(provisionalFrame(whole));
    for (int x = 0; x < 20; ++x)
        EXPECT_EQ(wholeMap(x, 0, 0), x < 5 ? 1.0f : 0.0f) << "column " << x;
}

/// A 16 × 16 Cornell box at `spp` with half buffers (auto's error needs them).
FrameBuffers smallCornell(int spp) {
    const std::string obj = std::string(GLINT_RENDER_TEST_DATA) + "/cornell_box.obj";
    render::Renderer renderer(render::parseScene(
        R"({"camera": {"position": [278, 273, -800], "lookAt": [278, 273, 0], "fovY": 39.3},
            "film": {"width": 16, "height": 16}, "shapes": [{"obj": ")" +
            obj + R"("}], "render": {"spp": )" + std::to_string(spp) +
            R"(, "maxDepth": 4, "seed": 3, "halfBuffers": true}})",
        std::string(GLINT_RENDER_TEST_DATA) + "/scene.json"));
    return renderer.render(renderer.scene().settings()).frame;
}

/// The studio's refreshes (ProgressiveRender::refreshOptions) on `threads`.
RefreshOptions studioRefreshes(int threads) {
    RefreshOptions o;
    o.quality = denoise::AutoQuality::Fast;
    o.bankSize = 2;
    o.filters = {"cross-bilateral"};
    o.focus = 0.1;
    o.threads = threads;
    return o;
}

TEST(Refresh, AtConvergenceAGrownFrameIsRefreshedAndAnUnchangedOneEndsTheRender) {
    // Callbacks::converged: no pixel open under the latest map. A refresh of a frame with more
    // samples than the last refresh's may open others; of the same frame it would repeat itself.
    Refresher r(studioRefreshes(0));
    const FrameBuffers at8 = smallCornell(8), at16 = smallCornell(16);
    EXPECT_TRUE(r.grew(at8));
    const auto first = r.converged(at8);  // no refresh yet: one now
    ASSERT_TRUE(first);
    EXPECT_EQ(r.refreshes(), 1);
    EXPECT_EQ(r.last()->meanSpp, 8.0);
    EXPECT_FALSE(r.grew(at8));
    EXPECT_FALSE(r.converged(at8));  // the frame as it was: the render ends
    EXPECT_EQ(r.refreshes(), 1);
    const auto second = r.converged(at16);
    ASSERT_TRUE(second);
    EXPECT_EQ(r.refreshes(), 2);
    EXPECT_EQ(r.last()->meanSpp, 16.0);
    EXPECT_FALSE(r.converged(at16));
    // The map is the refresh's: its worst tenth open.
    const auto open = std::count_if(second->data().begin(), second->data().end(),
                                    [](float v) { return v > 0.0f; });
    EXPECT_GE(open, 26);  // ⌈0.1 × 256⌉
    EXPECT_LT(open, 256);
}

TEST(Refresh, AutoRunsOnTheThreadsAskedForWithTheSameBits) {
    const FrameBuffers frame = smallCornell(8);
    // The widest arena auto's progress was reported from.
    int widest = 0;
    auto denoised = [&](int threads) {
        RefreshOptions o = studioRefreshes(threads);
        o.focus = 1.0;
        o.autoOptions.progress = [&](double) {
            widest = std::max(widest, tbb::this_task_arena::max_concurrency());
            return true;
        };
        widest = 0;
        return Refresher(o).denoise(frame);
    };
    const Denoised one = denoised(1);
    EXPECT_EQ(widest, 1);
    const Denoised all = denoised(0);
    EXPECT_EQ(widest, tbb::this_task_arena::max_concurrency());
    ASSERT_EQ(one.result.composite.data().size(), all.result.composite.data().size());
    EXPECT_TRUE(std::equal(one.result.composite.data().begin(), one.result.composite.data().end(),
                           all.result.composite.data().begin()));
    EXPECT_EQ(one.relMse, all.relMse);
}

TEST(Refresh, RefusesNegativeThreads) {
    RefreshOptions o;
    o.threads = -1;
    EXPECT_ANY_THROW(Refresher{o});
}

}  // namespace
}  // namespace glint::pipeline

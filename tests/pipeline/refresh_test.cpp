// The steering loop's refresh (glint/pipeline/refresh.h), shared by glint-final and the studio's
// Keep Refining: when a refresh is due, the map's schedule scale, and the focus that keeps only
// the worst pixels open; auto in an arena of the threads asked for, with the same bits.
#include <algorithm>
#include <cmath>
#include <string>

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

TEST(Refresh, TheProvisionalMapOpensTheNoisiestPixelsByTheirOwnVariance) {
    RefreshOptions o;
    o.focus = 0.5;
    const Refresher r(o);
    FrameBuffers f = frameAt(16.0f);
    f.ensure(Layer::Color).fill(0.5f);
    Image& variance = f.ensure(Layer::Variance);
    // Relative variances 0.04, 0.4, 0.004, 4 (the colour's square plus 0.01 is 0.26).
    const float v[] = {0.0104f, 0.104f, 0.00104f, 1.04f};
    for (int x = 0; x < 4; ++x)
        for (int c = 0; c < 3; ++c) variance(x, 0, c) = v[x];
    const Image map = *r.provisional(f);
    EXPECT_EQ(map(0, 0, 0), 0.0f);
    EXPECT_EQ(map(1, 0, 0), 1.0f);
    EXPECT_EQ(map(2, 0, 0), 0.0f);
    EXPECT_EQ(map(3, 0, 0), 1.0f);
}

TEST(Refresh, AProvisionalMapsShareNarrowsItToTheWorstOfTheFocus) {
    RefreshOptions o;
    o.focus = 0.5;
    const Refresher r(o);
    FrameBuffers f = frameAt(16.0f);
    f.ensure(Layer::Color).fill(0.5f);
    Image& variance = f.ensure(Layer::Variance);
    const float v[] = {0.0104f, 0.104f, 0.00104f, 1.04f};
    for (int x = 0; x < 4; ++x)
        for (int c = 0; c < 3; ++c) variance(x, 0, c) = v[x];
    // Half of the focus (two of four): the worst one.
    const Image map = *r.provisional(f, 0.5);
    EXPECT_EQ(map(0, 0, 0), 0.0f);
    EXPECT_EQ(map(1, 0, 0), 0.0f);
    EXPECT_EQ(map(2, 0, 0), 0.0f);
    EXPECT_EQ(map(3, 0, 0), 1.0f);
}

TEST(Refresh, AutoRunsOnTheThreadsAskedForWithTheSameBits) {
    // A 16 × 16 Cornell box at 8 spp with half buffers (auto's error needs them).
    const std::string obj = std::string(GLINT_RENDER_TEST_DATA) + "/cornell_box.obj";
    render::Renderer renderer(render::parseScene(
        R"({"camera": {"position": [278, 273, -800], "lookAt": [278, 273, 0], "fovY": 39.3},
            "film": {"width": 16, "height": 16}, "shapes": [{"obj": ")" +
            obj + R"("}], "render": {"spp": 8, "maxDepth": 4, "seed": 3, "halfBuffers": true}})",
        std::string(GLINT_RENDER_TEST_DATA) + "/scene.json"));
    const FrameBuffers frame = renderer.render(renderer.scene().settings()).frame;
    // The widest arena auto's progress was reported from.
    int widest = 0;
    auto denoised = [&](int threads) {
        RefreshOptions o;
        o.quality = denoise::AutoQuality::Fast;
        o.bankSize = 2;
        o.filters = {"cross-bilateral"};
        o.threads = threads;
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

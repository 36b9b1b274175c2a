// Renderer behaviour through the public API: thread-count determinism, cancellation, layers.
#include <gtest/gtest.h>

#include <atomic>
#include <cstring>

#include "glint/image/error.h"
#include "glint/render/renderer.h"
#include "glint/render/scene.h"
#include "test_util.h"

namespace glint::render {
namespace {

Scene cornell(int size) {
    const std::string dir = GLINT_RENDER_TEST_DATA;
    return parseScene(R"({
      "camera": {"position": [278, 273, -800], "lookAt": [278, 273, 0], "fovY": 39.3},
      "film": {"width": )" +
                          std::to_string(size) + R"(, "height": )" + std::to_string(size) + R"(},
      "shapes": [{"obj": "cornell_box.obj"}],
      "render": {"spp": 8, "maxDepth": 8}
    })",
                      dir + "/cornell_inline.json");
}

TEST(Renderer, BitIdenticalForAnyThreadCount) {
    Renderer renderer(cornell(32));
    Settings s = renderer.scene().settings();
    s.positionLayer = true;
    s.threads = 1;
    const FrameBuffers one = renderer.render(s).frame;
    s.threads = 2;
    s.tileSize = 8;  // a different tiling must not matter either
    const FrameBuffers two = renderer.render(s).frame;
    test::expectSameFrames(one, two);
    EXPECT_EQ(one.metadata().spp, 8);
    // A different seed gives a different image.
    s.seed = 99;
    EXPECT_FALSE(test::sameLayer(one, renderer.render(s).frame, Layer::Color));
}

TEST(Renderer, ProducesFeatureLayersAndCounts) {
    Renderer renderer(cornell(16));
    const RenderResult result = renderer.render(renderer.scene().settings());
    const FrameBuffers& f = result.frame;
    for (Layer l :
         {Layer::Color, Layer::Variance, Layer::Albedo, Layer::AlbedoVariance, Layer::Normal,
          Layer::NormalVariance, Layer::Depth, Layer::DepthVariance, Layer::SampleCount})
        EXPECT_TRUE(f.has(l)) << layerInfo(l).name;
    EXPECT_FALSE(f.has(Layer::Position));
    const Image& count = f.layer(Layer::SampleCount);
    for (float v : count.data()) EXPECT_EQ(v, 8.0f);
    // Centre pixel looks at the back wall: white albedo, normal towards the camera (-z), depth
    // 800 + 559.2 (camera-space z of the wall).
    EXPECT_NEAR(f.layer(Layer::Albedo)(8, 4, 0), 0.725f, 1e-4);
    EXPECT_NEAR(f.layer(Layer::Normal)(8, 4, 2), -1.0f, 1e-4);
    EXPECT_NEAR(f.layer(Layer::Depth)(8, 4, 0), 1359.2f, 1.0f);
    EXPECT_GT(result.stats.rays, result.stats.samples);
    EXPECT_EQ(result.stats.samples, 16u * 16u * 8u);
    EXPECT_FALSE(result.stats.mlt.has_value());
}

TEST(Renderer, CancelReturnsConsistentPartialFrame) {
    Renderer renderer(cornell(32));
    Settings s = renderer.scene().settings();
    s.threads = 2;
    s.tileSize = 8;
    std::atomic<int> tiles{0};
    Callbacks cb;
    cb.tileDone = [&](const Rect&) { ++tiles; };
    // 16 tiles per pass, passes of 1, 1, 2, 4 spp: stop during the third pass.
    cb.cancel = [&] { return tiles.load() >= 16 + 16 + 5; };
    const RenderResult result = renderer.render(s, cb);
    const FrameBuffers& partial = result.frame;
    EXPECT_TRUE(result.stats.cancelled);
    EXPECT_EQ(partial.metadata().spp, 2);
    EXPECT_EQ(partial.metadata().extra.at("cancelled"), "true");
    // Every pixel has either the 2 spp of the complete passes or 4 (its tile finished pass 3),
    // and its statistics equal an uncancelled render of that many samples.
    s.spp = 2;
    const FrameBuffers two = renderer.render(s).frame;
    s.spp = 4;
    const FrameBuffers four = renderer.render(s).frame;
    const Image& count = partial.layer(Layer::SampleCount);
    int withFour = 0;
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 32; ++x) {
            const float n = count(x, y, 0);
            ASSERT_TRUE(n == 2.0f || n == 4.0f) << n;
            const FrameBuffers& ref = n == 2.0f ? two : four;
            withFour += n == 4.0f;
            for (int c = 0; c < 3; ++c) {
                EXPECT_EQ(partial.color()(x, y, c), ref.color()(x, y, c));
                EXPECT_EQ(partial.layer(Layer::Variance)(x, y, c),
                          ref.layer(Layer::Variance)(x, y, c));
            }
        }
    EXPECT_GE(withFour, 5 * 64);
    EXPECT_LT(withFour, 32 * 32);
}

TEST(Renderer, ProgressAndPassCallbacks) {
    Renderer renderer(cornell(16));
    Settings s = renderer.scene().settings();
    double last = 0.0;
    int passes = 0;
    Callbacks cb;
    cb.progress = [&](int, double f) {
        EXPECT_GE(f, last - 1e-12);
        last = f;
    };
    cb.passDone = [&](int pass, const FrameBuffers& frame) {
        EXPECT_EQ(pass, passes++);
        EXPECT_EQ(frame.width(), 16);
    };
    renderer.render(s, cb);
    EXPECT_NEAR(last, 1.0, 1e-9);
    EXPECT_EQ(passes, 4);  // 1 + 1 + 2 + 4 spp
}

TEST(Renderer, RejectsBadSettings) {
    Renderer renderer(cornell(8));
    Settings s = renderer.scene().settings();
    s.spp = -1;
    EXPECT_THROW(renderer.render(s), Error);
    // Bad Metropolis parameters (more in mlt_test.cpp).
    s.spp = 1;
    s.integrator = Integrator::Mlt;
    s.mlt.chains = 17;  // not a multiple of the 16 groups
    try {
        renderer.render(s);
        FAIL() << "chains must be a multiple of groups";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("multiple of groups"), std::string::npos);
    }
}

}  // namespace
}  // namespace glint::render

namespace glint::render {
namespace {

// A render region samples only its pixels, and those exactly as a full render does (the same
// per-pixel streams), so a studio can merge a region render into its frame.
TEST(Renderer, ARegionRendersOnlyItsPixelsAndTheSameValues) {
    Renderer renderer(cornell(24));
    Settings s = renderer.scene().settings();
    s.spp = 4;
    const FrameBuffers full = renderer.render(s).frame;
    s.region = Rect{5, 17, 3, 11};
    const RenderResult part = renderer.render(s);
    EXPECT_EQ(part.stats.samples, 12u * 8u * 4u);
    for (int y = 0; y < 24; ++y)
        for (int x = 0; x < 24; ++x) {
            const bool inside = s.region->contains(x, y);
            EXPECT_EQ(part.frame.layer(Layer::SampleCount)(x, y, 0), inside ? 4.0f : 0.0f);
            if (!inside) continue;
            for (int c = 0; c < 3; ++c)
                EXPECT_EQ(part.frame.color()(x, y, c), full.color()(x, y, c));
        }
    s.region = Rect{20, 30, 0, 4};  // outside the film
    EXPECT_THROW(renderer.render(s), Error);
    s.region = Rect{2, 2, 0, 4};  // empty
    EXPECT_THROW(renderer.render(s), Error);
    s.region = Rect{0, 4, 0, 4};
    s.integrator = Integrator::Mlt;
    EXPECT_THROW(renderer.render(s), Error);
}

}  // namespace
}  // namespace glint::render

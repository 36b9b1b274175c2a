// Tests of the "guided" filter through the public API.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "glint/denoise/filter.h"
#include "glint/denoise/registry.h"
#include "glint/image/error.h"
#include "synthetic_frames.h"

using namespace glint;
using namespace glint::denoise;

namespace {

// A w × h frame of uniform random colour in [0.1, 1.1) (grey when `grey`), seed fixed.
FrameBuffers randomFrame(int w, int h, bool grey, unsigned seed = 3) {
    FrameBuffers f(w, h);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.1f, 1.1f);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const float g = u(rng);
            for (int c = 0; c < 3; ++c) f.color()(x, y, c) = grey ? g : u(rng);
        }
    return f;
}

float maxAbsDiff(const Image& a, const Image& b) {
    float m = 0.0f;
    for (std::size_t i = 0; i < a.data().size(); ++i)
        m = std::max(m, std::fabs(a.data()[i] - b.data()[i]));
    return m;
}

}  // namespace

TEST(Guided, TinyEpsWithTheInputAsGuideIsIdentity) {
    const Filter& f = findFilter("guided");
    // Grey image, guide = its luminance: q = a I + b fits exactly with a = 1, b = 0.
    const FrameBuffers grey = randomFrame(24, 20, true);
    const Image out = applyFilter(f, grey, {{"radius", 3}, {"eps", 1e-8}, {"guide", 0}});
    EXPECT_LT(maxAbsDiff(out, grey.color()), 1e-4f);
    // Colour image, 3-channel guide = the colour itself (passed as albedo).
    FrameBuffers colour = randomFrame(24, 20, false);
    colour.set(Layer::Albedo, colour.color());
    const Image out3 = applyFilter(f, colour, {{"radius", 3}, {"eps", 1e-8}, {"guide", 1}});
    EXPECT_LT(maxAbsDiff(out3, colour.color()), 1e-3f);
    // A large eps smooths instead.
    const Image smooth = applyFilter(f, colour, {{"radius", 3}, {"eps", 1e2}, {"guide", 1}});
    EXPECT_GT(maxAbsDiff(smooth, colour.color()), 0.1f);
}

TEST(Guided, KeepsTheGuideEdge) {
    const Filter& f = findFilter("guided");
    // Noisy step in colour aligned with a clean depth step used as guide.
    FrameBuffers frame(32, 16);
    Image depth(32, 16, 1);
    std::mt19937 rng(5);
    std::normal_distribution<float> noise(0.0f, 0.05f);
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 32; ++x) {
            depth(x, y, 0) = x < 16 ? 1.0f : 3.0f;
            for (int c = 0; c < 3; ++c)
                frame.color()(x, y, c) = (x < 16 ? 0.2f : 0.8f) + noise(rng);
        }
    frame.set(Layer::Depth, depth);
    const Image out = applyFilter(f, frame, {{"radius", 4}, {"eps", 1e-4}, {"guide", 3}});
    // Column means either side of the edge stay at their level (noise of a column mean after
    // smoothing is far below 0.05).
    double left = 0.0, right = 0.0;
    for (int y = 0; y < 16; ++y) {
        left += out(15, y, 0);
        right += out(16, y, 0);
    }
    EXPECT_NEAR(left / 16, 0.2, 0.05);
    EXPECT_NEAR(right / 16, 0.8, 0.05);
}

TEST(Guided, RoiMatchesFullOutputExactly) {
    const Filter& f = findFilter("guided");
    FrameBuffers frame = randomFrame(600, 90, false);
    frame.set(Layer::Normal, randomFrame(600, 90, false, 9).color());
    for (int guide : {0, 2}) {
        const ParamValues p{{"radius", 5}, {"guide", guide}};
        const Image full = applyFilter(f, frame, p);
        const Rect roi{67, 590, 70, 85};  // strips of 192 columns here, 192 in the full frame
        const Image part = applyFilter(f, frame, p, glint::denoise::testing::inRegion(roi));
        for (int y = 0; y < roi.height(); ++y)
            for (int x = 0; x < roi.width(); ++x)
                for (int c = 0; c < 3; ++c)
                    ASSERT_EQ(part(x, y, c), full(x + roi.x0, y + roi.y0, c)) << x << "," << y;
    }
}

TEST(Guided, MissingGuideLayerThrows) {
    const Filter& f = findFilter("guided");
    const FrameBuffers frame = randomFrame(8, 8, false);
    for (int guide : {1, 2, 3}) {
        try {
            applyFilter(f, frame, {{"guide", guide}});
            FAIL() << "no error for guide " << guide;
        } catch (const Error& e) {
            EXPECT_EQ(e.kind(), ErrorKind::InvalidArgument);
        }
    }
    EXPECT_THROW(applyFilter(f, frame, {{"guide", 4}}), Error);
    EXPECT_THROW(applyFilter(f, frame, {{"radius", 1.5}}), Error);
}

TEST(Guided, BrightSpikeDoesNotReachBeyondTheMargin) {
    // A finite 1e20 pixel in a constant image: outside the filter's margin the output must stay
    // exactly constant. Plain running box sums lost ~1e-16 * 1e20 when the spike left the window
    // and corrupted every row up to the next restart (64 rows); compensated sums recover it.
    const Filter& f = findFilter("guided");
    for (float spike : {1e20f, 1e30f}) {
        FrameBuffers frame(16, 80);
        frame.color().fill(1.0f);
        for (int c = 0; c < 3; ++c) frame.color()(3, 2, c) = spike;
        const ParamValues params{{"radius", 5}, {"eps", 5e-2}, {"guide", 0}};
        const int margin = f.margin(resolveParams(f, params));
        const Image out = applyFilter(f, frame, params);
        for (int y = 2 + margin + 1; y < 80; ++y)
            for (int x = 0; x < 16; ++x)
                for (int c = 0; c < 3; ++c)
                    ASSERT_NEAR(out(x, y, c), 1.0f, 1e-6f)
                        << "spike " << spike << " at " << x << "," << y;
    }
}

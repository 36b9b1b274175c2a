// paste() and blend(): the region paste and weighted blend that filters, sessions and the studio
// share (glint/image/composite.h).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <utility>

#include "glint/image/composite.h"
#include "glint/image/error.h"
#include "glint/image/frame_buffers.h"

namespace glint {
namespace {

Image ramp(int w, int h, int c, float offset) {
    Image im(w, h, c);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int k = 0; k < c; ++k) im(x, y, k) = offset + float(x + 10 * y + 100 * k);
    return im;
}

TEST(Paste, CopiesTheRegionAndLeavesTheRest) {
    Image dst = ramp(8, 6, 3, 0.0f);
    const Image before = dst;
    const Image src = ramp(3, 2, 3, 1000.0f);
    paste(dst, src, 4, 3);
    for (int y = 0; y < 6; ++y)
        for (int x = 0; x < 8; ++x)
            for (int c = 0; c < 3; ++c) {
                const bool inside = x >= 4 && x < 7 && y >= 3 && y < 5;
                EXPECT_EQ(dst(x, y, c), inside ? src(x - 4, y - 3, c) : before(x, y, c));
            }
}

// A denoiser's output frame: the colour with the result pasted over it, every other layer the
// input's own image, shared and not copied; the input's colour is left as it was.
TEST(Paste, TheOutputFrameCopiesOnlyItsColour) {
    FrameBuffers frame(5, 4);
    frame.color().fill(1.0f);
    frame.set(Layer::Albedo, Image(5, 4, 3, 0.5f));
    frame.set(Layer::Depth, Image(5, 4, 1, 3.0f));
    frame.metadata().spp = 7;
    const FrameBuffers out = withColorPasted(frame, Image(2, 2, 3, 8.0f), 3, 1);
    EXPECT_EQ(out.color()(3, 1, 0), 8.0f);
    EXPECT_EQ(out.color()(4, 2, 2), 8.0f);
    EXPECT_EQ(out.color()(2, 1, 0), 1.0f);
    EXPECT_EQ(std::as_const(frame).color()(3, 1, 0), 1.0f);
    EXPECT_NE(&out.color(), &std::as_const(frame).color());
    EXPECT_EQ(&out.layer(Layer::Albedo), &std::as_const(frame).layer(Layer::Albedo));
    EXPECT_EQ(&out.layer(Layer::Depth), &std::as_const(frame).layer(Layer::Depth));
    EXPECT_EQ(out.metadata().spp, 7);
    EXPECT_THROW(withColorPasted(frame, Image(2, 2, 3), 4, 3), Error);
}

TEST(Paste, RefusesWhatDoesNotFit) {
    Image dst(8, 6, 3);
    EXPECT_THROW(paste(dst, Image(3, 2, 3), 6, 0), Error);
    EXPECT_THROW(paste(dst, Image(3, 2, 3), -1, 0), Error);
    EXPECT_THROW(paste(dst, Image(3, 2, 1), 0, 0), Error);
}

TEST(Blend, SelectsInputsExactlyAtZeroAndOneAndMixesBetween) {
    Image a = ramp(5, 4, 3, 0.0f), b = ramp(5, 4, 3, 50.0f);
    a(0, 0, 1) = std::numeric_limits<float>::quiet_NaN();  // no weight on it: must not leak
    Image w(5, 4, 1, 0.0f);
    w(0, 0, 0) = 1.0f;
    w(1, 0, 0) = 0.25f;
    w(2, 0, 0) = 7.0f;   // clamped to 1
    w(3, 0, 0) = -3.0f;  // clamped to 0
    const Image out = blend(a, b, w);
    for (int c = 0; c < 3; ++c) {
        EXPECT_EQ(out(0, 0, c), b(0, 0, c));
        EXPECT_FLOAT_EQ(out(1, 0, c), 0.75f * a(1, 0, c) + 0.25f * b(1, 0, c));
        EXPECT_EQ(out(2, 0, c), b(2, 0, c));
        EXPECT_EQ(out(3, 0, c), a(3, 0, c));
        EXPECT_EQ(out(4, 3, c), a(4, 3, c));
    }
    // Per-channel weights.
    Image wc(5, 4, 3, 0.0f);
    wc(2, 2, 1) = 1.0f;
    const Image perChannel = blend(a, b, wc);
    EXPECT_EQ(perChannel(2, 2, 0), a(2, 2, 0));
    EXPECT_EQ(perChannel(2, 2, 1), b(2, 2, 1));
}

TEST(Blend, InPlaceTouchesOnlyTheRectangle) {
    Image dst = ramp(6, 6, 3, 0.0f);
    const Image before = dst;
    const Image src = ramp(6, 6, 3, 9.0f);
    const Image w(6, 6, 1, 1.0f);
    blendInPlace(dst, src, w, Rect{1, 3, 2, 4});
    for (int y = 0; y < 6; ++y)
        for (int x = 0; x < 6; ++x) {
            const bool inside = x >= 1 && x < 3 && y >= 2 && y < 4;
            EXPECT_EQ(dst(x, y, 0), inside ? src(x, y, 0) : before(x, y, 0));
        }
}

TEST(Blend, RefusesMismatchedShapes) {
    EXPECT_THROW(blend(Image(4, 4, 3), Image(4, 5, 3), Image(4, 4, 1)), Error);
    EXPECT_THROW(blend(Image(4, 4, 3), Image(4, 4, 3), Image(4, 4, 2)), Error);
    EXPECT_THROW(blend(Image(4, 4, 3), Image(4, 4, 3), Image(3, 4, 1)), Error);
}

TEST(LayerNames, OneDisplayNamePerLayerAndBack) {
    EXPECT_EQ(layerDisplayName(Layer::Color), "color");
    EXPECT_EQ(layerDisplayName(Layer::DepthVariance), "depthVariance");
    for (int l = 0; l < kLayerCount; ++l)
        EXPECT_EQ(findLayer(layerDisplayName(Layer(l))), Layer(l));
    EXPECT_EQ(findLayer("rgb"), Layer::Color);
    EXPECT_FALSE(findLayer("colour").has_value());
}

}  // namespace
}  // namespace glint

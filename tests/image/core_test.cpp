#include <gtest/gtest.h>

#include <utility>

#include <cmath>
#include <limits>

#include "glint/image/error.h"
#include "glint/image/frame_buffers.h"
#include "glint/image/image.h"

using namespace glint;

TEST(Image, AtIsBoundsChecked) {
    Image im(4, 3, 2, 1.5f);
    EXPECT_EQ(im.at(3, 2, 1), 1.5f);
    im.at(1, 2, 0) = 7.0f;
    EXPECT_EQ(im(1, 2, 0), 7.0f);
    EXPECT_EQ(im.row(2)[2], 7.0f);
    EXPECT_THROW(im.at(4, 0, 0), Error);
    EXPECT_THROW(im.at(0, -1, 0), Error);
    EXPECT_THROW(im.at(0, 0, 2), Error);
    EXPECT_THROW(Image(-1, 2, 3), Error);
}

TEST(Image, CropCopiesTheRectangle) {
    Image im(5, 4, 1);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 5; ++x) im(x, y, 0) = float(10 * y + x);
    Image c = im.crop({1, 4, 2, 4});
    ASSERT_EQ(c.width(), 3);
    ASSERT_EQ(c.height(), 2);
    EXPECT_EQ(c(0, 0, 0), 21.0f);
    EXPECT_EQ(c(2, 1, 0), 33.0f);
    EXPECT_THROW(im.crop({3, 6, 0, 1}), Error);
    EXPECT_THROW(im.crop({2, 2, 0, 1}), Error);
}

TEST(Image, CountsNonFinite) {
    Image im(2, 2, 3);
    im(0, 0, 1) = std::numeric_limits<float>::quiet_NaN();
    im(1, 1, 2) = std::numeric_limits<float>::infinity();
    EXPECT_EQ(im.countNonFinite(), 2u);
}

TEST(FrameBuffers, LayersHaveDesignNames) {
    EXPECT_EQ(channelName(Layer::Color, 0), "R");
    EXPECT_EQ(channelName(Layer::Variance, 2), "variance.B");
    EXPECT_EQ(channelName(Layer::AlbedoVariance, 1), "albedoVariance.G");
    EXPECT_EQ(channelName(Layer::Normal, 0), "normal.X");
    EXPECT_EQ(channelName(Layer::Depth, 0), "depth.Z");
    EXPECT_EQ(channelName(Layer::DepthVariance, 0), "depthVariance.Z");
    EXPECT_EQ(channelName(Layer::SampleCount, 0), "sampleCount.Y");
    EXPECT_EQ(varianceLayer(Layer::Albedo), Layer::AlbedoVariance);
    EXPECT_EQ(varianceOf(Layer::DepthVariance), Layer::Depth);
}

TEST(FrameBuffers, SetChecksShape) {
    FrameBuffers fb(8, 4);
    EXPECT_TRUE(fb.has(Layer::Color));
    EXPECT_FALSE(fb.has(Layer::Albedo));
    EXPECT_THROW(fb.layer(Layer::Albedo), Error);
    EXPECT_THROW(fb.set(Layer::Depth, Image(8, 4, 3)), Error);
    EXPECT_THROW(fb.set(Layer::Albedo, Image(4, 8, 3)), Error);
    fb.set(Layer::Depth, Image(8, 4, 1, 2.0f));
    EXPECT_EQ(fb.layer(Layer::Depth)(7, 3, 0), 2.0f);
    fb.remove(Layer::Depth);
    EXPECT_FALSE(fb.has(Layer::Depth));
    EXPECT_THROW(fb.remove(Layer::Color), Error);
}

// A layer shared between frames (shareLayer, sharedCopy) is one image, not copies, until one of
// them writes it: then that frame gets its own copy and the others keep their values. A plain
// copy of a frame copies every layer.
TEST(FrameBuffers, ASharedLayerIsCopiedWhenWrittenAndACopyCopiesEveryLayer) {
    FrameBuffers fb(6, 5);
    fb.color()(2, 3, 1) = 1.5f;
    fb.set(Layer::Depth, Image(6, 5, 1, 4.0f));
    const FrameBuffers& constFb = fb;
    const FrameBuffers shared = fb.sharedCopy();
    EXPECT_EQ(&shared.color(), &constFb.color());
    EXPECT_EQ(&shared.layer(Layer::Depth), &constFb.layer(Layer::Depth));
    FrameBuffers other(6, 5);
    other.shareLayer(Layer::Albedo, fb, Layer::Color);
    EXPECT_EQ(&std::as_const(other).layer(Layer::Albedo), &constFb.color());
    EXPECT_THROW(other.shareLayer(Layer::Depth, fb, Layer::Color), Error);  // 3 channels, not 1
    // Writing through one frame: its own copy; the others see what they had.
    other.layer(Layer::Albedo)(2, 3, 1) = 9.0f;
    EXPECT_EQ(constFb.color()(2, 3, 1), 1.5f);
    EXPECT_EQ(shared.color()(2, 3, 1), 1.5f);
    EXPECT_EQ(std::as_const(other).layer(Layer::Albedo)(2, 3, 1), 9.0f);
    fb.color()(2, 3, 1) = 2.5f;  // shared with `shared` still: copied first
    EXPECT_EQ(shared.color()(2, 3, 1), 1.5f);
    EXPECT_NE(&shared.color(), &constFb.color());
    // A copy holds layers of its own.
    const FrameBuffers copy = shared;
    EXPECT_NE(&copy.layer(Layer::Depth), &shared.layer(Layer::Depth));
    EXPECT_EQ(copy.layer(Layer::Depth)(5, 4, 0), 4.0f);
}

TEST(Error, MessageNamesFileAndPlace) {
    Error e(ErrorKind::Format, "expected a number", "scene.json", "line 3");
    EXPECT_STREQ(e.what(), "scene.json: line 3: expected a number");
    EXPECT_EQ(e.kind(), ErrorKind::Format);
}

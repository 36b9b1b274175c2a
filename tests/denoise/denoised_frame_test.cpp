// A denoised frame keeps the render it came from (denoise/denoised_frame.h; docs/image.md, "The
// noisy layer").
#include <gtest/gtest.h>

#include <algorithm>

#include "glint/denoise/denoised_frame.h"
#include "glint/image/error.h"
#include "synthetic_frames.h"

namespace glint::denoise {
namespace {

bool same(const Image& a, const Image& b) {
    return a.sameShape(b) && std::equal(a.data().begin(), a.data().end(), b.data().begin());
}

TEST(DenoisedFrame, KeepsTheRendersColourAndRenderOfGivesTheRenderBack) {
    const FrameBuffers render = testing::syntheticFrame(12, 8, 0.1f);
    EXPECT_FALSE(colourIsDenoised(render));
    EXPECT_FALSE(keepsRender(render));
    const Image patch(4, 3, 3, 0.25f);
    const FrameBuffers out = denoisedFrame(render, patch, 5, 2, "gaussian");
    EXPECT_TRUE(colourIsDenoised(out));
    EXPECT_TRUE(keepsRender(out));
    EXPECT_EQ(denoisedMark(out), "denoiseFilter: gaussian");
    EXPECT_TRUE(same(out.layer(Layer::Noisy), render.color()));
    EXPECT_FLOAT_EQ(out.color()(6, 3, 1), 0.25f);  // inside the patch
    EXPECT_EQ(out.color()(0, 0, 0), render.color()(0, 0, 0));
    EXPECT_TRUE(same(out.layer(Layer::Variance), render.layer(Layer::Variance)));

    const FrameBuffers back = renderOf(out);
    EXPECT_TRUE(same(back.color(), render.color()));
    EXPECT_FALSE(back.has(Layer::Noisy));
    EXPECT_FALSE(colourIsDenoised(back));
    EXPECT_TRUE(renderOfNote(back, "x.exr").empty());
    EXPECT_EQ(renderOfNote(out, "x.exr"),
              "x.exr keeps its render (layer noisy): denoising that, not its colour (denoised by "
              "gaussian)\n");
    // A render is its own render.
    EXPECT_TRUE(same(renderOf(render).color(), render.color()));
}

TEST(DenoisedFrame, ErrorsAboutTheRendersColourNameTheNoisyLayer) {
    const FrameBuffers render = testing::syntheticFrame(6, 4, 0.1f);
    EXPECT_EQ(layerInFile(render, Layer::Color), "the color");
    EXPECT_EQ(channelInFile(render, Layer::Color, 1), "G");
    const FrameBuffers out = denoisedFrame(render, Image(6, 4, 3, 1.0f), 0, 0, "auto");
    FrameBuffers back = renderOf(out);
    EXPECT_EQ(layerInFile(back, Layer::Color), "the noisy layer (the render the file keeps)");
    EXPECT_EQ(channelInFile(back, Layer::Color, 1), "noisy.G");
    EXPECT_EQ(channelInFile(back, Layer::Variance, 1), "variance.G");  // read from itself
    // Denoising it again gives a colour of its own; so does setting one.
    EXPECT_EQ(channelInFile(denoisedFrame(back, Image(6, 4, 3), 0, 0, "auto"), Layer::Color, 0),
              "R");
    back.set(Layer::Color, Image(6, 4, 3));
    EXPECT_EQ(layerInFile(back, Layer::Color), "the color");
}

TEST(DenoisedFrame, DenoisingADenoisedFrameKeepsTheOriginalRender) {
    const FrameBuffers render = testing::syntheticFrame(8, 8, 0.1f);
    const FrameBuffers once = denoisedFrame(render, Image(8, 8, 3, 1.0f), 0, 0, "auto");
    const FrameBuffers twice = denoisedFrame(once, Image(8, 8, 3, 2.0f), 0, 0, "gaussian");
    EXPECT_TRUE(same(twice.layer(Layer::Noisy), render.color()));
    EXPECT_EQ(twice.metadata().extra.at("denoiseFilter"), "gaussian");
    // Without a noisy layer the render is gone: nothing to keep, still marked as denoised.
    FrameBuffers lost = once;
    lost.remove(Layer::Noisy);
    const FrameBuffers again = denoisedFrame(lost, Image(8, 8, 3, 2.0f), 0, 0, "gaussian");
    EXPECT_FALSE(again.has(Layer::Noisy));
    EXPECT_TRUE(colourIsDenoised(again));
    EXPECT_TRUE(same(renderOf(lost).color(), lost.color()));  // nothing to give back
}

TEST(DenoisedFrame, ASessionExportAndACyclesNoisyLayerMarkTheColourDenoised) {
    FrameBuffers exported = testing::syntheticFrame(4, 4, 0.1f);
    exported.metadata().extra["denoiseSession"] = "2 layers";
    EXPECT_TRUE(colourIsDenoised(exported));
    EXPECT_EQ(denoisedMark(exported), "denoiseSession: 2 layers");
    EXPECT_FALSE(keepsRender(exported));
    FrameBuffers cycles = testing::syntheticFrame(4, 4, 0.1f);
    cycles.set(Layer::Noisy, Image(4, 4, 3, 0.5f));
    EXPECT_TRUE(colourIsDenoised(cycles));
    EXPECT_EQ(denoisedMark(cycles), "layer noisy");
    EXPECT_FLOAT_EQ(renderOf(cycles).color()(1, 1, 2), 0.5f);
}

TEST(DenoisedFrame, ARegionDenoisedAgainKeepsTheColourShownAroundIt) {
    const FrameBuffers render = testing::syntheticFrame(8, 6, 0.1f);
    const Image shown(8, 6, 3, 0.75f);  // a denoised file's colour
    const FrameBuffers out = denoisedFrame(render, Image(2, 2, 3, 0.25f), 3, 1, "auto", &shown);
    EXPECT_FLOAT_EQ(out.color()(3, 1, 0), 0.25f);
    EXPECT_FLOAT_EQ(out.color()(0, 0, 0), 0.75f);
    EXPECT_FLOAT_EQ(out.color()(5, 1, 2), 0.75f);
    EXPECT_TRUE(same(out.layer(Layer::Noisy), render.color()));
}

TEST(DenoisedFrame, APatchThatDoesNotFitIsRefused) {
    const FrameBuffers render = testing::syntheticFrame(4, 4, 0.1f);
    EXPECT_THROW(denoisedFrame(render, Image(3, 3, 3), 2, 2, "auto"), Error);
    const Image small(3, 3, 3);
    EXPECT_THROW(denoisedFrame(render, Image(2, 2, 3), 0, 0, "auto", &small), Error);
}

}  // namespace
}  // namespace glint::denoise

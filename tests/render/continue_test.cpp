// Going on from a finished render (Settings::continueFrom, docs/renderer.md "Adaptive
// sampling"): the frame's statistics become the film's and the adaptive passes follow, each
// pixel continuing its own sample sequence, so the result is the render that never stopped (up
// to the float rounding of the frame's layers); the same bits for any thread count; any frame
// that is not a render this one can go on from is refused naming what differs.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <memory>
#include <string>

#include <gtest/gtest.h>

#include "glint/image/error.h"
#include "glint/render/renderer.h"
#include "glint/render/scene.h"
#include "test_util.h"

namespace glint::render {
namespace {

/// The Cornell box at 24 × 24: the box fills the frame, so every pixel is noisy (a noiseless
/// pixel would converge at any threshold).
class ContinueRender : public ::testing::Test {
  protected:
    ContinueRender()
        : m_dir("continue"),
          m_renderer(loadScene(m_dir.write("scene.json", R"({
            "camera": {"position": [278, 273, -800], "lookAt": [278, 273, 0], "fovY": 39.3},
            "film": {"width": 24, "height": 24},
            "shapes": [{"obj": ")" + std::string(GLINT_RENDER_TEST_DATA) +
                                                             R"(/cornell_box.obj"}],
            "render": {"spp": 8, "maxDepth": 3}
          })"))) {}

    /// The finished render a refinement goes on from: 16 spp, half buffers.
    static Settings finishedSettings() {
        Settings s;
        s.spp = 16;
        s.seed = 7;
        s.maxDepth = 3;
        s.threads = 2;
        s.tileSize = 8;
        s.halfBuffers = true;
        return s;
    }
    /// The refinement of it: adaptive from 16 spp to at most 256, steered by half B.
    static Settings refiningSettings(double threshold) {
        Settings s = finishedSettings();
        s.adaptive = true;
        s.minSpp = 16;
        s.spp = 256;
        s.noiseThreshold = threshold;
        return s;
    }

    test::TempDir m_dir;
    Renderer m_renderer;
};

/// The largest |a − b| / (|b| + 1e-3) over the pixels of `layer` where both frames took the same
/// count, and the share of pixels that did.
struct Agreement {
    double sameCounts = 0.0;
    double largestRelative = 0.0;
};
Agreement agreement(const FrameBuffers& a, const FrameBuffers& b, Layer layer) {
    const Image& ca = a.layer(Layer::SampleCount);
    const Image& cb = b.layer(Layer::SampleCount);
    const Image& la = a.layer(layer);
    const Image& lb = b.layer(layer);
    Agreement r;
    int same = 0;
    for (int y = 0; y < la.height(); ++y)
        for (int x = 0; x < la.width(); ++x) {
            if (ca(x, y, 0) != cb(x, y, 0)) continue;
            ++same;
            for (int c = 0; c < la.channels(); ++c)
                r.largestRelative =
                    std::max(r.largestRelative, double(std::abs(la(x, y, c) - lb(x, y, c))) /
                                                    (double(std::abs(lb(x, y, c))) + 1e-3));
        }
    r.sameCounts = double(same) / double(la.width() * la.height());
    return r;
}

TEST_F(ContinueRender, WithEveryPixelOpenItIsTheUniformRenderThatNeverStopped) {
    // A threshold no pixel reaches: the refinement adds samples 16 … 255 to every pixel, in
    // order, as a uniform 256-spp render does. The counts are the same; the values differ only
    // by the float rounding of the 16-spp frame's means and variances, which the later samples
    // dilute (a mean's is at most 2^-24 relative): within 1e-6 of the value.
    const FrameBuffers finished = m_renderer.render(finishedSettings()).frame;
    Settings s = refiningSettings(1e-9);
    s.continueFrom = std::make_shared<const FrameBuffers>(finished);
    const RenderResult went = m_renderer.render(s);
    Settings uniform = finishedSettings();
    uniform.spp = 256;
    const FrameBuffers never = m_renderer.render(uniform).frame;
    EXPECT_TRUE(test::sameLayer(went.frame, never, Layer::SampleCount));
    EXPECT_TRUE(test::sameLayer(went.frame, never, Layer::HalfSampleCount));
    for (Layer l : {Layer::Color, Layer::HalfColor, Layer::Albedo, Layer::Normal, Layer::Depth}) {
        const Agreement a = agreement(went.frame, never, l);
        EXPECT_LT(a.largestRelative, 1e-6) << layerDisplayName(l);
    }
    for (Layer l : {Layer::Variance, Layer::HalfVariance, Layer::AlbedoVariance}) {
        const Agreement a = agreement(went.frame, never, l);
        EXPECT_LT(a.largestRelative, 1e-4) << layerDisplayName(l);
    }
    // Only the new samples were taken: 240 a pixel.
    EXPECT_EQ(went.stats.samples, std::uint64_t(24 * 24 * 240));
    EXPECT_EQ(went.stats.completedSpp, 256);
    EXPECT_EQ(went.frame.metadata().spp, 256);
}

TEST_F(ContinueRender, AtARealThresholdItTakesTheSamplesTheUnstoppedRefinementTakes) {
    // The refinement from the finished frame against the same refinement from nothing (its
    // first 16 spp are the finished render's samples). The pixels' decisions read the frame's
    // float-rounded statistics, so a decision at the threshold's edge may differ: nearly every
    // pixel takes the same count (≥ 98 %), and there the values agree within 1e-6.
    const FrameBuffers finished = m_renderer.render(finishedSettings()).frame;
    Settings s = refiningSettings(0.003);
    const RenderResult neverResult = m_renderer.render(s);
    const FrameBuffers& never = neverResult.frame;
    s.continueFrom = std::make_shared<const FrameBuffers>(finished);
    const RenderResult wentResult = m_renderer.render(s);
    const FrameBuffers& went = wentResult.frame;
    const Image& count = never.layer(Layer::SampleCount);
    const auto counts = count.data();
    // The refinement took different counts (else this would be the test above).
    ASSERT_LT(*std::min_element(counts.begin(), counts.end()),
              *std::max_element(counts.begin(), counts.end()));
    const Agreement colour = agreement(went, never, Layer::Color);
    std::printf("same counts in %.1f %% of the pixels; largest colour difference there %.2g\n",
                100.0 * colour.sameCounts, colour.largestRelative);
    EXPECT_GE(colour.sameCounts, 0.98);
    EXPECT_LT(colour.largestRelative, 1e-6);
    // It took the samples past the finished frame's 16 a pixel, not those again.
    if (colour.sameCounts == 1.0) {
        EXPECT_EQ(wentResult.stats.samples + 24 * 24 * 16, neverResult.stats.samples);
    }
}

TEST_F(ContinueRender, TheSameFrameGivesTheSameBitsForAnyThreadCount) {
    const FrameBuffers finished = m_renderer.render(finishedSettings()).frame;
    Settings s = refiningSettings(0.003);
    s.continueFrom = std::make_shared<const FrameBuffers>(finished);
    s.threads = 1;
    s.tileSize = 16;
    const FrameBuffers one = m_renderer.render(s).frame;
    s.threads = 2;
    s.tileSize = 8;
    test::expectSameFrames(one, m_renderer.render(s).frame);
}

TEST_F(ContinueRender, AFrameItCannotGoOnFromIsRefusedNamingWhatDiffers) {
    const FrameBuffers finished = m_renderer.render(finishedSettings()).frame;
    struct Case {
        const char* what;
        std::function<void(Settings&, FrameBuffers&)> change;
        const char* expected;  // in the message, besides "continueFrom"
    };
    const Case cases[] = {
        {"not adaptive", [](Settings& s, FrameBuffers&) { s.adaptive = false; },
         "needs adaptive sampling on"},
        {"a region",
         [](Settings& s, FrameBuffers&) {
             s.region = Rect{0, 8, 0, 8};
         },
         "whole film"},
        {"zsobol", [](Settings& s, FrameBuffers&) { s.sampler = SamplerKind::ZSobol; }, "zsobol"},
        {"another seed", [](Settings& s, FrameBuffers&) { s.seed = 8; }, "seed 7"},
        {"another depth", [](Settings& s, FrameBuffers&) { s.maxDepth = 4; }, "maxDepth '3'"},
        {"no half buffers",
         [](Settings&, FrameBuffers& f) {
             f.metadata().extra["halfBuffers"] = "false";
             f.remove(Layer::HalfColor);
         },
         "halfBuffers 'false'"},
        {"a missing layer", [](Settings&, FrameBuffers& f) { f.remove(Layer::HalfColor); },
         "no halfColor layer"},
        {"another size", [](Settings&, FrameBuffers& f) { f = FrameBuffers(4, 4); },
         "it is 4x4, the scene renders 24x24"},
        {"discarded samples", [](Settings&, FrameBuffers& f) { f.metadata().nonFiniteSamples = 2; },
         "discarded 2 non-finite samples"},
        {"a pixel below the start",
         [](Settings&, FrameBuffers& f) { f.layer(Layer::SampleCount)(5, 3, 0) = 3.0f; },
         "pixel (5, 3): cannot go on from this frame: sample count 3; expected a whole number in "
         "[16, 256]"},
        {"half B's count",
         [](Settings&, FrameBuffers& f) { f.layer(Layer::HalfSampleCount)(1, 2, 0) = 7.0f; },
         "half B's sample count 7"},
        {"a NaN pixel",
         [](Settings&, FrameBuffers& f) {
             f.layer(Layer::Albedo)(6, 7, 1) = std::numeric_limits<float>::quiet_NaN();
         },
         "albedo is nan; expected a finite value"},
    };
    for (const Case& c : cases) {
        Settings s = refiningSettings(0.003);
        FrameBuffers frame = finished;
        c.change(s, frame);
        s.continueFrom = std::make_shared<const FrameBuffers>(frame);
        const std::string message = test::errorOf([&] { m_renderer.render(s); });
        EXPECT_NE(message.find("continueFrom"), std::string::npos) << c.what << ": " << message;
        EXPECT_NE(message.find(c.expected), std::string::npos) << c.what << ": " << message;
    }
}

}  // namespace
}  // namespace glint::render

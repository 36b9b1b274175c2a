// Adaptive sampling's bias (issue 49; docs/renderer.md "Adaptive sampling",
// docs/lab/adaptive-bias.md): pixel by pixel, an adaptive render's mean is a uniform render's of
// the same total samples within the noise both report, for both choices of the error that steers it
// (the odd half alone, every sample). The comparison is the image module's Monte Carlo test
// (glint/image/ mc_compare.h, docs/testing.md): per-value z-scores from both variance layers,
// self-normalised window sums, a stated false-alarm rate.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>

#include <gtest/gtest.h>

#include "glint/image/frame_buffers.h"
#include "glint/image/mc_compare.h"
#include "glint/render/renderer.h"
#include "glint/render/scene.h"
#include "test_util.h"

namespace glint::render {
namespace {

/// The false-alarm rate of one comparison (kAlpha / 3 for each channel). The first test makes 12 (4
/// seeds; the whole image of both choices and the even half of `half`): by Bonferroni, an unbiased
/// renderer fails it with a probability of at most 1.2 % over the draw of seeds; the seeds are
/// fixed, so it either always passes or always fails.
constexpr double kAlpha = 1e-3;
constexpr int kSeeds[] = {1, 2, 3, 4};

/// The ball scene of test::writeBallScene.
class AdaptiveBias : public ::testing::Test {
  protected:
    AdaptiveBias() : m_dir("adaptive_bias") {}

    /// The scene with the ball's albedo (r, 0.3, 0.2).
    Scene scene(double ballRed) const { return loadScene(test::writeBallScene(m_dir, ballRed)); }

    /// Adaptive sampling from 64 spp up to 512 at threshold 0.005 (about 190 spp a pixel on
    /// average), half buffers on.
    static Settings adaptive(AdaptiveError from, std::uint64_t seed) {
        Settings s;
        s.spp = 512;
        s.seed = seed;
        s.maxDepth = 3;
        s.threads = 2;
        s.tileSize = 8;
        s.halfBuffers = true;
        s.adaptive = true;
        s.minSpp = 64;
        s.noiseThreshold = 0.005;
        s.adaptiveError = from;
        return s;
    }

    /// A uniform render of `samples` samples in all (rounded to whole spp) with another seed.
    static Settings uniform(double samples, int pixels, std::uint64_t seed) {
        Settings s = adaptive(AdaptiveError::Half, seed + 1000);
        s.adaptive = false;
        s.spp = int(std::lround(samples / pixels));
        return s;
    }

    test::TempDir m_dir;
};

double totalSamples(const FrameBuffers& f) {
    double n = 0.0;
    for (float c : f.layer(Layer::SampleCount).data()) n += c;
    return n;
}

/// The Monte Carlo comparison of the colour of `a` and `b` with their variance layers, channel
/// by channel (mcCompareByChannel: sharper for a change of one channel, as the tests' red ball).
McCompareResult compareColour(const FrameBuffers& a, const FrameBuffers& b) {
    return mcCompareByChannel(a.layer(Layer::Color), a.layer(Layer::Variance),
                              b.layer(Layer::Color), b.layer(Layer::Variance),
                              McCompareOptions{kAlpha});
}

TEST_F(AdaptiveBias, EachPixelsMeanIsTheUniformRendersOfTheSameSamplesForBothChoices) {
    Renderer renderer(scene(0.8));
    for (const int seed : kSeeds) {
        for (AdaptiveError from : {AdaptiveError::Half, AdaptiveError::Whole}) {
            const FrameBuffers a = renderer.render(adaptive(from, seed)).frame;
            // The pixels took different counts (else this would compare two uniform renders).
            const auto counts = a.layer(Layer::SampleCount).data();
            ASSERT_LT(*std::min_element(counts.begin(), counts.end()),
                      *std::max_element(counts.begin(), counts.end()));
            const int pixels = a.width() * a.height();
            const FrameBuffers u = renderer.render(uniform(totalSamples(a), pixels, seed)).frame;
            const std::string what = std::string(adaptiveErrorName(from)) + ", seed " +
                                     std::to_string(seed) + ", mean spp " +
                                     std::to_string(totalSamples(a) / pixels);
            const McCompareResult whole = compareColour(a, u);
            std::printf("%s, every sample: %s\n", what.c_str(), test::describe(whole).c_str());
            EXPECT_TRUE(whole.passed) << what << ": " << test::describe(whole);
            if (from == AdaptiveError::Half) {
                // The even half (half A), which never steered: unbiased by construction.
                const McCompareResult even = compareColour(splitHalves(a).first, u);
                std::printf("%s, even half: %s\n", what.c_str(), test::describe(even).c_str());
                EXPECT_TRUE(even.passed) << what << " (even half): " << test::describe(even);
            }
        }
    }
}

TEST_F(AdaptiveBias, TheComparisonFindsAThreePercentChangeOfTheBallsRed) {
    // The power of the test above on this scene at these sample counts: the uniform render of
    // a ball 3 % less red fails the comparison for every seed.
    Renderer renderer(scene(0.8));
    Renderer darker(scene(0.8 * 0.97));
    for (const int seed : kSeeds) {
        const FrameBuffers a = renderer.render(adaptive(AdaptiveError::Half, seed)).frame;
        const int pixels = a.width() * a.height();
        const FrameBuffers u = darker.render(uniform(totalSamples(a), pixels, seed)).frame;
        const McCompareResult r = compareColour(a, u);
        std::printf("seed %d, ball 3 %% less red: %s\n", seed, test::describe(r).c_str());
        EXPECT_FALSE(r.passed) << "seed " << seed << ": " << test::describe(r);
    }
}

}  // namespace
}  // namespace glint::render

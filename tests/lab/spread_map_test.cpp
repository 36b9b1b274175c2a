// The spread map (glint/lab/spread_map.h, importanceFromSpread): the weights that turn the
// renderer's threshold, which stops pixel i at n_i ∝ a_i², into the allocation that minimises the
// noisy image's relMSE, n_i ∝ s_i.
#include <cmath>

#include <gtest/gtest.h>

#include "glint/lab/spread_map.h"
#include "glint/render/importance_map.h"

namespace glint::lab {
namespace {

/// A pixel's grey mean, a sample's variance and sample count.
struct Pixel {
    float mean, sampleVariance, count;
};

FrameBuffers frameOf(const std::vector<Pixel>& pixels) {
    FrameBuffers f(int(pixels.size()), 1);
    Image& mean = f.ensure(Layer::Color);
    Image& variance = f.ensure(Layer::Variance);
    Image& count = f.ensure(Layer::SampleCount);
    for (int x = 0; x < int(pixels.size()); ++x) {
        const Pixel& p = pixels[std::size_t(x)];
        for (int c = 0; c < 3; ++c) {
            mean(x, 0, c) = p.mean;
            variance(x, 0, c) = p.sampleVariance / p.count;  // of the mean
        }
        count(x, 0, 0) = p.count;
    }
    return f;
}

/// Where the renderer's threshold stops a pixel of this frame under weight w, up to one constant:
/// (a w)², a = Σc √(v n) / (1e-4 + √Σc μ) (Film::adaptiveError times √n, without √(2/π)).
double stoppingCount(const Pixel& p, double w) {
    const double a = 3.0 * std::sqrt(double(p.sampleVariance)) / (1e-4 + std::sqrt(3.0 * p.mean));
    return a * w * a * w;
}

/// The relative spread of a sample, √(v / (μ² + 0.01)).
double spread(const Pixel& p) {
    return std::sqrt(double(p.sampleVariance) / (double(p.mean) * p.mean + 0.01));
}

TEST(SpreadMap, TheThresholdStopsEachPixelAtSamplesProportionalToItsRelativeSpread) {
    // Means and variances chosen so that no factor reaches the clamp (within 8× of the mean).
    const std::vector<Pixel> pixels = {
        {0.5f, 0.04f, 64.0f}, {0.5f, 0.64f, 64.0f}, {2.0f, 1.0f, 128.0f}, {0.1f, 0.02f, 32.0f}};
    const Image w = importanceFromSpread(frameOf(pixels), 3.0);
    // Without the map the threshold gives pixel 1 sixteen times pixel 0's samples (variance ×16);
    // relMSE is best served by four times (its spread ×4).
    for (std::size_t i = 1; i < pixels.size(); ++i) {
        const double ratio =
            stoppingCount(pixels[i], w(int(i), 0, 0)) / stoppingCount(pixels[0], w(0, 0, 0));
        EXPECT_NEAR(ratio, spread(pixels[i]) / spread(pixels[0]), 1e-4 * ratio) << "pixel " << i;
    }
    // The weights average the scale over the pixels that have an estimate.
    double sum = 0.0;
    for (float v : w.data()) sum += v;
    EXPECT_NEAR(sum / 4.0, 3.0, 1e-5);
}

TEST(SpreadMap, PixelsWithoutAnEstimateWeighTheScaleAndTheMapIsOneTheRendererTakes) {
    // Below two samples, without noise, and a noise 1e6 times the others' (clamped to 8×).
    const std::vector<Pixel> pixels = {{0.5f, 0.04f, 1.0f},
                                       {0.5f, 0.0f, 64.0f},
                                       {0.5f, 0.04f, 64.0f},
                                       {0.5f, 0.04f, 64.0f},
                                       {0.5f, 4e4f, 64.0f}};
    const Image w = importanceFromSpread(frameOf(pixels), 2.0);
    EXPECT_FLOAT_EQ(w(0, 0, 0), 2.0f);
    EXPECT_FLOAT_EQ(w(1, 0, 0), 2.0f);
    EXPECT_GT(w(2, 0, 0), w(4, 0, 0));
    EXPECT_GE(w(4, 0, 0), 2.0f / 8.0f * (1.0f - 1e-6f));
    EXPECT_LE(w(2, 0, 0), 2.0f * 8.0f * (1.0f + 1e-6f));
    EXPECT_NO_THROW(render::checkImportanceMap(w, 5, 1));
}

}  // namespace
}  // namespace glint::lab

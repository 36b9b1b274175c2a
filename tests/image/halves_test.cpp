// Half buffers (docs/image.md, "Half buffers"): the layer names, and splitHalves recovering
// half A's statistics from the whole and half B exactly as if A had been accumulated alone.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "glint/image/error.h"
#include "glint/image/frame_buffers.h"

namespace glint {
namespace {

TEST(HalfBuffers, LayerNamesAndPairs) {
    EXPECT_EQ(channelName(Layer::HalfColor, 0), "halfColor.R");
    EXPECT_EQ(channelName(Layer::HalfNormalVariance, 2), "halfNormalVariance.Z");
    EXPECT_EQ(channelName(Layer::HalfSampleCount, 0), "halfSampleCount.Y");
    EXPECT_EQ(findLayer("halfDepth"), Layer::HalfDepth);
    const std::pair<Layer, Layer> pairs[] = {{Layer::Color, Layer::HalfColor},
                                             {Layer::Variance, Layer::HalfVariance},
                                             {Layer::Albedo, Layer::HalfAlbedo},
                                             {Layer::AlbedoVariance, Layer::HalfAlbedoVariance},
                                             {Layer::Normal, Layer::HalfNormal},
                                             {Layer::NormalVariance, Layer::HalfNormalVariance},
                                             {Layer::Depth, Layer::HalfDepth},
                                             {Layer::DepthVariance, Layer::HalfDepthVariance},
                                             {Layer::SampleCount, Layer::HalfSampleCount}};
    for (const auto& [whole, half] : pairs) {
        EXPECT_EQ(halfLayer(whole), half) << layerDisplayName(whole);
        EXPECT_TRUE(isHalfLayer(half));
        EXPECT_FALSE(isHalfLayer(whole));
        EXPECT_EQ(layerInfo(whole).channels, layerInfo(half).channels);
    }
    EXPECT_FALSE(halfLayer(Layer::Position));
    // The noisy layer (a denoised file's render colour) has no half and is no half.
    EXPECT_FALSE(halfLayer(Layer::Noisy));
    EXPECT_FALSE(isHalfLayer(Layer::Noisy));
    EXPECT_EQ(findLayer("noisy"), Layer::Noisy);
    EXPECT_EQ(varianceOf(Layer::HalfVariance), Layer::HalfColor);
    EXPECT_EQ(varianceLayer(Layer::HalfDepth), Layer::HalfDepthVariance);
}

/// Running statistics of a set of samples, as the film keeps them (double).
struct Stats {
    double n = 0, mean = 0, m2 = 0;
    void add(double v) {
        ++n;
        const double d = v - mean;
        mean += d / n;
        m2 += d * (v - mean);
    }
    double varianceOfMean() const { return n > 1 ? m2 / (n * (n - 1)) : 0.0; }
};

TEST(HalfBuffers, SplitHalvesRecoversTheEvenSamplesStatistics) {
    // Per pixel a random number of samples (0 to 9), even indices to A, odd ones to B, values
    // spread over five orders of magnitude like radiance.
    const int w = 7, h = 5;
    std::mt19937 rng(3);
    std::uniform_int_distribution<int> count(0, 9);
    std::lognormal_distribution<double> value(0.0, 2.0);
    FrameBuffers f(w, h);
    for (Layer l : {Layer::Variance, Layer::Depth, Layer::DepthVariance, Layer::SampleCount,
                    Layer::HalfColor, Layer::HalfVariance, Layer::HalfDepth,
                    Layer::HalfDepthVariance, Layer::HalfSampleCount, Layer::Position})
        f.ensure(l);
    std::vector<Stats> expectedA(std::size_t(w * h * 4));
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const int n = count(rng);
            f.layer(Layer::SampleCount)(x, y, 0) = float(n);
            f.layer(Layer::HalfSampleCount)(x, y, 0) = float(n / 2);
            f.layer(Layer::Position)(x, y, 1) = 42.0f;
            for (int c = 0; c < 4; ++c) {  // RGB, then depth
                Stats whole, a, b;
                for (int s = 0; s < n; ++s) {
                    const double v = value(rng);
                    whole.add(v);
                    (s % 2 ? b : a).add(v);
                }
                const Layer mean = c < 3 ? Layer::Color : Layer::Depth;
                const int ch = c < 3 ? c : 0;
                f.layer(mean)(x, y, ch) = float(whole.mean);
                f.layer (*varianceLayer(mean))(x, y, ch) = float(whole.varianceOfMean());
                f.layer (*halfLayer(mean))(x, y, ch) = float(b.mean);
                f.layer (*halfLayer(*varianceLayer(mean)))(x, y, ch) = float(b.varianceOfMean());
                expectedA[std::size_t((y * w + x) * 4 + c)] = a;
            }
        }
    f.metadata().spp = 9;
    const auto [a, b] = splitHalves(f, "in.exr");
    EXPECT_EQ(a.metadata().spp, 5);
    EXPECT_EQ(b.metadata().spp, 4);
    // An error about B's colour names the file's layer it came from.
    EXPECT_EQ(channelInFile(b, Layer::Color, 1), "halfColor.G");
    EXPECT_EQ(layerInFile(b, Layer::Color), "the halfColor");
    EXPECT_EQ(channelInFile(a, Layer::Color, 1), "G");
    for (int l = 0; l < kLayerCount; ++l) {
        EXPECT_FALSE(isHalfLayer(Layer(l)) && (a.has(Layer(l)) || b.has(Layer(l))));
    }
    int checked = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const double n = f.layer(Layer::SampleCount)(x, y, 0);
            EXPECT_EQ(a.layer(Layer::SampleCount)(x, y, 0), float(n - std::floor(n / 2)));
            EXPECT_EQ(b.layer(Layer::SampleCount)(x, y, 0), float(std::floor(n / 2)));
            EXPECT_EQ(a.layer(Layer::Position)(x, y, 1), 42.0f);
            EXPECT_EQ(b.layer(Layer::Position)(x, y, 1), 42.0f);
            for (int c = 0; c < 4; ++c) {
                const Layer mean = c < 3 ? Layer::Color : Layer::Depth;
                const int ch = c < 3 ? c : 0;
                const Stats& e = expectedA[std::size_t((y * w + x) * 4 + c)];
                const double scale = std::max(std::abs(double(f.layer(mean)(x, y, ch))), 1e-3);
                // Float inputs: a few ulps of the whole's magnitude, amplified by n/n_A <= 3
                // for the mean and by the cancellation M2 − M2_B − … for the variance.
                EXPECT_NEAR(a.layer(mean)(x, y, ch), e.mean, 4e-6 * scale * n)
                    << x << "," << y << "," << c;
                EXPECT_NEAR(a.layer(*varianceLayer(mean))(x, y, ch), e.varianceOfMean(),
                            1e-5 * scale * scale * n * n + 1e-6 * e.varianceOfMean())
                    << x << "," << y << "," << c;
                EXPECT_GE(a.layer(*varianceLayer(mean))(x, y, ch), 0.0f);
                EXPECT_EQ(b.layer(mean)(x, y, ch), f.layer(*halfLayer(mean))(x, y, ch));
                ++checked;
            }
        }
    EXPECT_EQ(checked, w * h * 4);
}

// The halves share the frame's layers that they do not recompute, rather than copying them
// (issue 47: at 3840×2160 the copies held 1.4 GB): B's layers are the frame's half layers and
// both halves' position the frame's, one image each; A's means, variances and counts are its
// own. Writing a shared layer copies it first: the frame keeps its values.
TEST(HalfBuffers, SplitHalvesSharesTheLayersItDoesNotRecompute) {
    FrameBuffers f(4, 3);
    for (Layer l :
         {Layer::Variance, Layer::Albedo, Layer::SampleCount, Layer::Position, Layer::HalfColor,
          Layer::HalfVariance, Layer::HalfAlbedo, Layer::HalfSampleCount})
        f.ensure(l);
    f.layer(Layer::SampleCount).fill(4.0f);
    f.layer(Layer::HalfSampleCount).fill(2.0f);
    f.layer(Layer::HalfColor).fill(0.25f);
    auto [a, b] = splitHalves(f, "in.exr");
    const FrameBuffers &frame = f, &halfA = a, &halfB = b;
    for (Layer l : {Layer::Color, Layer::Variance, Layer::Albedo, Layer::SampleCount})
        EXPECT_EQ(&halfB.layer(l), &frame.layer(*halfLayer(l))) << layerDisplayName(l);
    EXPECT_EQ(&halfB.layer(Layer::Position), &frame.layer(Layer::Position));
    EXPECT_EQ(&halfA.layer(Layer::Position), &frame.layer(Layer::Position));
    for (Layer l : {Layer::Color, Layer::Variance, Layer::Albedo, Layer::SampleCount}) {
        EXPECT_NE(&halfA.layer(l), &frame.layer(l)) << layerDisplayName(l);
        EXPECT_NE(&halfA.layer(l), &frame.layer(*halfLayer(l))) << layerDisplayName(l);
    }
    b.layer(Layer::Color)(1, 2, 0) = 7.0f;
    EXPECT_EQ(frame.layer(Layer::HalfColor)(1, 2, 0), 0.25f);
    EXPECT_EQ(halfB.layer(Layer::Color)(1, 2, 0), 7.0f);
    // checkHalves: splitHalves' checks without the split.
    f.layer(Layer::HalfSampleCount)(3, 0, 0) = 5.0f;
    EXPECT_THROW(checkHalves(f, "in.exr"), Error);
    f.remove(Layer::HalfAlbedo);
    try {
        checkHalves(f, "in.exr");
        FAIL() << "no error";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::Format);
        EXPECT_EQ(e.where(), "layer 'halfAlbedo'");
    }
}

TEST(HalfBuffers, SplitHalvesNamesAMissingLayerAndBadCounts) {
    FrameBuffers f(4, 3);
    f.ensure(Layer::Variance);
    f.ensure(Layer::SampleCount);
    f.ensure(Layer::HalfColor);
    f.ensure(Layer::HalfSampleCount);
    try {
        splitHalves(f, "in.exr");
        FAIL() << "no error";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::Format);
        EXPECT_EQ(e.file(), "in.exr");
        EXPECT_EQ(e.where(), "layer 'halfVariance'");
    }
    f.ensure(Layer::HalfVariance);
    EXPECT_NO_THROW(splitHalves(f));
    f.layer(Layer::SampleCount)(2, 1, 0) = 3.0f;
    f.layer(Layer::HalfSampleCount)(2, 1, 0) = 5.0f;
    try {
        splitHalves(f, "in.exr");
        FAIL() << "no error";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::InvalidArgument);
        EXPECT_EQ(e.where(), "pixel (2, 1)");
    }
}

}  // namespace
}  // namespace glint

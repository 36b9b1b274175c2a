// Tests of the feature prefilter (prefilterFeatures).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "glint/denoise/prefilter.h"
#include "glint/image/error.h"

using namespace glint;
using namespace glint::denoise;

namespace {

// 48×32 frame: for x < 24 a static object with a sharp, exact (zero-variance) albedo/normal/depth
// edge at x = 12; for x >= 24 a "motion-blurred" region whose features are 0.5 plus noise of
// sigma 0.1 with variance-of-the-mean 0.01 (seed fixed).
FrameBuffers blurredScene() {
    const int w = 48, h = 32;
    FrameBuffers f(w, h);
    Image albedo(w, h, 3), normal(w, h, 3), depth(w, h, 1);
    Image va(w, h, 3, 0.0f), vn(w, h, 3, 0.0f), vd(w, h, 1, 0.0f);
    std::mt19937 rng(21);
    std::normal_distribution<float> noise(0.0f, 0.1f);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            if (x < 24) {
                const float v = x < 12 ? 0.2f : 0.8f;
                for (int c = 0; c < 3; ++c) albedo(x, y, c) = normal(x, y, c) = v;
                depth(x, y, 0) = v;
            } else {
                for (int c = 0; c < 3; ++c) {
                    albedo(x, y, c) = 0.5f + noise(rng);
                    normal(x, y, c) = 0.5f + noise(rng);
                    va(x, y, c) = vn(x, y, c) = 0.01f;
                }
                depth(x, y, 0) = 0.5f + noise(rng);
                vd(x, y, 0) = 0.01f;
            }
        }
    f.set(Layer::Albedo, albedo);
    f.set(Layer::Normal, normal);
    f.set(Layer::Depth, depth);
    f.set(Layer::AlbedoVariance, va);
    f.set(Layer::NormalVariance, vn);
    f.set(Layer::DepthVariance, vd);
    return f;
}

// RMS of (layer - 0.5) and mean variance over the blurred region, away from its border.
void blurredStats(const FrameBuffers& f, Layer layer, double& rms, double& meanVar) {
    const Image& im = f.layer(layer);
    const Image& var = f.layer(*varianceLayer(layer));
    double s = 0.0, v = 0.0;
    int n = 0;
    for (int y = 0; y < f.height(); ++y)
        for (int x = 30; x < f.width(); ++x)
            for (int c = 0; c < im.channels(); ++c, ++n) {
                s += std::pow(im(x, y, c) - 0.5, 2);
                v += var(x, y, c);
            }
    rms = std::sqrt(s / n);
    meanVar = v / n;
}

}  // namespace

TEST(Prefilter, SmoothsNoisyFeaturesKeepsSharpEdges) {
    const FrameBuffers in = blurredScene();
    const FrameBuffers out = prefilterFeatures(in);
    for (Layer layer : {Layer::Albedo, Layer::Normal, Layer::Depth}) {
        ASSERT_TRUE(out.has(layer));
        double rmsIn, varIn, rmsOut, varOut;
        blurredStats(in, layer, rmsIn, varIn);
        blurredStats(out, layer, rmsOut, varOut);
        // Input RMS ≈ 0.1; a radius-5 window averages dozens of samples, so at least halve it.
        EXPECT_LT(rmsOut, 0.5 * rmsIn) << layerInfo(layer).name;
        EXPECT_LT(varOut, 0.25 * varIn) << layerInfo(layer).name;
        // The static object, including its edge, is bit-for-bit unchanged.
        const Image& a = in.layer(layer);
        const Image& b = out.layer(layer);
        for (int y = 0; y < in.height(); ++y)
            for (int x = 0; x < 24; ++x)
                for (int c = 0; c < a.channels(); ++c) ASSERT_EQ(a(x, y, c), b(x, y, c));
    }
    // Colour is not touched.
    EXPECT_EQ(out.color().data()[5], in.color().data()[5]);
}

TEST(Prefilter, FeatureWithoutVarianceIsUnchanged) {
    FrameBuffers in = blurredScene();
    in.remove(Layer::NormalVariance);
    const FrameBuffers out = prefilterFeatures(in);
    const Image& a = in.layer(Layer::Normal);
    const Image& b = out.layer(Layer::Normal);
    for (std::size_t i = 0; i < a.data().size(); ++i) ASSERT_EQ(a.data()[i], b.data()[i]);
    EXPECT_FALSE(out.has(Layer::NormalVariance));
}

TEST(Prefilter, NonFiniteFeaturesDoNotSpread) {
    FrameBuffers in = blurredScene();
    in.layer(Layer::Albedo)(35, 10, 1) = std::numeric_limits<float>::quiet_NaN();
    in.layer(Layer::DepthVariance)(36, 12, 0) = std::numeric_limits<float>::infinity();
    const FrameBuffers out = prefilterFeatures(in);
    for (Layer layer : {Layer::Albedo, Layer::AlbedoVariance, Layer::Depth, Layer::DepthVariance})
        EXPECT_EQ(out.layer(layer).countNonFinite(), 0u) << layerInfo(layer).name;
}

TEST(Prefilter, AbsurdParamsThrow) {
    const FrameBuffers in = blurredScene();
    EXPECT_THROW(prefilterFeatures(in, {{"radius", -1}}), Error);
    EXPECT_THROW(prefilterFeatures(in, {{"radius", 1000}}), Error);
    EXPECT_THROW(prefilterFeatures(in, {{"sigmaSpatial", 0.0}}), Error);
    EXPECT_THROW(
        prefilterFeatures(in, {{"varianceScale", std::numeric_limits<double>::quiet_NaN()}}),
        Error);
    try {
        prefilterFeatures(in, {{"sigmaSpatial", -2.0}});
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::InvalidArgument);
        EXPECT_NE(std::string(e.what()).find("sigmaSpatial"), std::string::npos);
    }
}

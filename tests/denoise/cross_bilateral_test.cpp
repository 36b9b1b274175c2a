// Tests of the "cross-bilateral" filter through the public API.
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

// A 32×16 frame split at x = 16: depth 1 | 2, normal +z | +x, albedo 0.5 everywhere; colour
// 0.2 | 0.8 plus Gaussian noise of sigma 0.05 (seed 7).
FrameBuffers stepFrame() {
    const int w = 32, h = 16;
    FrameBuffers f(w, h);
    Image& c = f.color();
    Image albedo(w, h, 3, 0.5f), normal(w, h, 3, 0.0f), depth(w, h, 1);
    std::mt19937 rng(7);
    std::normal_distribution<float> noise(0.0f, 0.05f);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const bool right = x >= w / 2;
            for (int k = 0; k < 3; ++k) c(x, y, k) = (right ? 0.8f : 0.2f) + noise(rng);
            normal(x, y, right ? 0 : 2) = 1.0f;
            depth(x, y, 0) = right ? 2.0f : 1.0f;
        }
    f.set(Layer::Albedo, albedo);
    f.set(Layer::Normal, normal);
    f.set(Layer::Depth, depth);
    return f;
}

// Mean of channel 0 over column x.
double columnMean(const Image& im, int x) {
    double s = 0.0;
    for (int y = 0; y < im.height(); ++y) s += im(x, y, 0);
    return s / im.height();
}

}  // namespace

TEST(CrossBilateral, RespectsFeatureEdges) {
    const Filter& f = findFilter("cross-bilateral");
    const FrameBuffers frame = stepFrame();
    // The colour term is switched off (huge sigmaColor): only the features stop the bleeding.
    const ParamValues p{{"sigmaS", 3.0}, {"radius", 6}, {"sigmaColor", 1e3}};
    const Image out = applyFilter(f, frame, p);
    // Next to the edge each side keeps its own level (noise sigma 0.05 / sqrt(16) per column
    // mean, so 0.05 is > 4 standard deviations).
    EXPECT_NEAR(columnMean(out, 15), 0.2, 0.05);
    EXPECT_NEAR(columnMean(out, 16), 0.8, 0.05);
    // With the feature terms off as well it is a Gaussian blur and bleeds.
    const ParamValues blur{{"sigmaS", 3.0},      {"radius", 6},        {"sigmaColor", 1e3},
                           {"sigmaAlbedo", 1e3}, {"sigmaNormal", 1e3}, {"sigmaDepth", 1e3}};
    const Image blurred = applyFilter(f, frame, blur);
    EXPECT_GT(columnMean(blurred, 15), 0.35);
    // And it denoises within a side: residual spread well below the input's 0.05.
    double s2 = 0.0;
    int n = 0;
    for (int y = 0; y < 16; ++y)
        for (int x = 2; x < 12; ++x, ++n) s2 += std::pow(out(x, y, 1) - 0.2, 2);
    EXPECT_LT(std::sqrt(s2 / n), 0.02);
}

TEST(CrossBilateral, NoisyFeaturesCountForLess) {
    const Filter& f = findFilter("cross-bilateral");
    FrameBuffers frame = stepFrame();
    // Only depth separates the sides now, but its variance is huge: the edge may be crossed.
    frame.layer(Layer::Normal).fill(0.0f);
    const ParamValues p{{"sigmaS", 3.0}, {"radius", 6}, {"sigmaColor", 1e3}};
    EXPECT_NEAR(columnMean(applyFilter(f, frame, p), 15), 0.2, 0.05);
    frame.set(Layer::DepthVariance, Image(32, 16, 1, 100.0f));
    EXPECT_GT(columnMean(applyFilter(f, frame, p), 15), 0.35);
}

TEST(CrossBilateral, ConstantStaysConstantAndRoiMatches) {
    const Filter& f = findFilter("cross-bilateral");
    FrameBuffers frame = stepFrame();
    const Image noisy = frame.color();
    frame.color().fill(0.25f);
    const Image out = applyFilter(f, frame, {{"radius", 4}});
    for (float v : out.data()) EXPECT_NEAR(v, 0.25f, 1e-6f);
    frame.color() = noisy;
    const Image full = applyFilter(f, frame, {{"radius", 4}});
    const Rect roi{5, 21, 3, 9};
    const Image part =
        applyFilter(f, frame, {{"radius", 4}}, glint::denoise::testing::inRegion(roi));
    for (int y = 0; y < roi.height(); ++y)
        for (int x = 0; x < roi.width(); ++x)
            for (int c = 0; c < 3; ++c) EXPECT_EQ(part(x, y, c), full(x + 5, y + 3, c));
}

TEST(CrossBilateral, MissingLayersAndBadParamsThrow) {
    const Filter& f = findFilter("cross-bilateral");
    FrameBuffers frame = stepFrame();
    EXPECT_THROW(applyFilter(f, frame, {{"sigmaDepth", -1.0}}), Error);
    EXPECT_THROW(applyFilter(f, frame, {{"sigmaFoo", 1.0}}), Error);
    frame.remove(Layer::Depth);
    try {
        applyFilter(f, frame, {});
        FAIL() << "no error for a missing depth layer";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::InvalidArgument);
        EXPECT_NE(std::string(e.what()).find("depth"), std::string::npos);
    }
}

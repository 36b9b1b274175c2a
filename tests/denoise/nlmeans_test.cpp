// Tests of the "nlmeans" filter through the public API, and of its noise estimator.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "glint/denoise/filter.h"
#include "glint/denoise/registry.h"
#include "glint/image/error.h"
#include "synthetic_frames.h"

namespace glint::denoise {
std::array<double, 3> estimateNoiseVariance(const Image& image);
}

using namespace glint;
using namespace glint::denoise;

namespace {

// A w × h smooth ramp plus Gaussian noise of sigma 0.1 (seed fixed); `truth` gets the ramp.
FrameBuffers noisyRamp(int w, int h, Image* truth, bool withVariance) {
    FrameBuffers f(w, h);
    Image clean(w, h, 3);
    std::mt19937 rng(11);
    std::normal_distribution<float> noise(0.0f, 0.1f);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < 3; ++c) {
                clean(x, y, c) = 0.3f + 0.4f * float(x) / float(w) + 0.1f * float(c);
                f.color()(x, y, c) = clean(x, y, c) + noise(rng);
            }
    if (withVariance) f.set(Layer::Variance, Image(w, h, 3, 0.01f));
    if (truth) *truth = clean;
    return f;
}

double mseTo(const Image& a, const Image& b) {
    double s = 0.0;
    for (std::size_t i = 0; i < a.data().size(); ++i) s += std::pow(a.data()[i] - b.data()[i], 2);
    return s / double(a.data().size());
}

}  // namespace

TEST(NlMeans, TinyStrengthIsIdentity) {
    const Filter& f = findFilter("nlmeans");
    const FrameBuffers frame = noisyRamp(40, 30, nullptr, true);
    const Image out = applyFilter(f, frame, {{"strength", 1e-4}, {"searchRadius", 4}});
    for (std::size_t i = 0; i < out.data().size(); ++i)
        ASSERT_NEAR(out.data()[i], frame.color().data()[i], 1e-6f);
}

TEST(NlMeans, ReducesNoiseWithAndWithoutVarianceLayer) {
    const Filter& f = findFilter("nlmeans");
    Image truth;
    for (bool withVariance : {true, false}) {
        const FrameBuffers frame = noisyRamp(48, 40, &truth, withVariance);
        const ParamValues p{{"patchRadius", 2}, {"searchRadius", 5}, {"strength", 0.6}};
        const Image out = applyFilter(f, frame, p);
        // 11×11 search window: the MSE should drop by far more than 3× (input MSE 0.01).
        EXPECT_LT(mseTo(out, truth), mseTo(frame.color(), truth) / 3.0) << withVariance;
    }
}

TEST(NlMeans, NoiseEstimateMatchesTheTrueVariance) {
    Image truth;
    const FrameBuffers frame = noisyRamp(96, 96, &truth, false);
    const auto var = estimateNoiseVariance(frame.color());
    // Immerkær's estimator on ~9000 pixels: within 15% of 0.01 (its spread is a few percent).
    for (double v : var) EXPECT_NEAR(v, 0.01, 0.0015);
    EXPECT_EQ(estimateNoiseVariance(Image(2, 2, 3, 1.0f))[0], 0.0);
}

TEST(NlMeans, RoiMatchesFullOutputExactly) {
    const Filter& f = findFilter("nlmeans");
    const FrameBuffers frame = noisyRamp(150, 80, nullptr, true);
    const ParamValues p{{"patchRadius", 2}, {"searchRadius", 3}};
    const Image full = applyFilter(f, frame, p);
    const Rect roi{61, 149, 50, 77};
    const Image part = applyFilter(f, frame, p, glint::denoise::testing::inRegion(roi));
    for (int y = 0; y < roi.height(); ++y)
        for (int x = 0; x < roi.width(); ++x)
            for (int c = 0; c < 3; ++c)
                ASSERT_EQ(part(x, y, c), full(x + roi.x0, y + roi.y0, c)) << x << "," << y;
}

TEST(NlMeans, BadParamsThrow) {
    const Filter& f = findFilter("nlmeans");
    const FrameBuffers frame = noisyRamp(8, 8, nullptr, false);
    EXPECT_THROW(applyFilter(f, frame, {{"patchRadius", -1}}), Error);
    EXPECT_THROW(applyFilter(f, frame, {{"strength", 0.0}}), Error);
    EXPECT_THROW(applyFilter(f, frame, {{"searchRadius", 2.5}}), Error);
}

// gaussian: limits and shape (public API only).
#include <gtest/gtest.h>

#include <cmath>

#include "glint/denoise/filter.h"
#include "glint/denoise/registry.h"
#include "synthetic_frames.h"

namespace glint::denoise {
namespace {

TEST(Gaussian, TinySigmaIsTheIdentity) {
    const FrameBuffers frame = testing::syntheticFrame(21, 17, 0.2f);
    const Image out = applyFilter(findFilter("gaussian"), frame, {{"sigma", 1e-6}});
    // Neighbour weights exp(-1 / (2e-12)) underflow to exactly 0: bit-identical output.
    EXPECT_EQ(testing::maxAbsDiff(out, frame.color()), 0.0);
}

TEST(Gaussian, ImpulseResponseIsTheSampledGaussian) {
    FrameBuffers frame(41, 41);
    frame.color()(20, 20, 0) = 1.0f;
    const double sigma = 2.5;
    const Image out = applyFilter(findFilter("gaussian"), frame, {{"sigma", sigma}});
    // Separable weights normalised per axis: out(dx, dy) / out(0, 0) = exp(-(dx²+dy²)/(2σ²)).
    double sum = 0.0;
    for (int y = 0; y < 41; ++y)
        for (int x = 0; x < 41; ++x) {
            const double dx = x - 20, dy = y - 20;
            const double expect =
                out(20, 20, 0) * std::exp(-(dx * dx + dy * dy) / (2 * sigma * sigma));
            const double window = std::max(std::fabs(dx), std::fabs(dy)) <= std::ceil(3 * sigma);
            EXPECT_NEAR(out(x, y, 0), window * expect, 1e-6) << x << "," << y;
            EXPECT_EQ(out(x, y, 1), 0.0f);
            sum += out(x, y, 0);
        }
    // Energy is kept away from the border (the truncated kernel is renormalised to sum 1).
    EXPECT_NEAR(sum, 1.0, 1e-5);
}

TEST(Gaussian, HugeSigmaAveragesTheWholeImage) {
    const FrameBuffers frame = testing::syntheticFrame(9, 7, 0.3f);
    const Image out = applyFilter(findFilter("gaussian"), frame, {{"sigma", 1e6}});
    double mean = 0.0;
    for (int y = 0; y < 7; ++y)
        for (int x = 0; x < 9; ++x) mean += frame.color()(x, y, 0);
    mean /= 63.0;
    for (int y = 0; y < 7; ++y)
        for (int x = 0; x < 9; ++x) EXPECT_NEAR(out(x, y, 0), mean, 1e-5);
}

TEST(Gaussian, MissingPixelIsFilledFromItsNeighbours) {
    FrameBuffers frame = testing::constantFrame(11, 11, 0.5f, 0.5f, 0.5f);
    frame.color()(5, 5, 2) = std::nanf("");
    const Image out = applyFilter(findFilter("gaussian"), frame, {{"sigma", 1.0}});
    EXPECT_NEAR(out(5, 5, 0), 0.5f, 1e-6);
    EXPECT_NEAR(out(5, 5, 2), 0.5f, 1e-6);
}

TEST(Gaussian, MarginIsThreeSigma) {
    const Filter& g = findFilter("gaussian");
    EXPECT_EQ(g.margin(resolveParams(g, {{"sigma", 2.0}})), 6);
    EXPECT_EQ(g.margin(resolveParams(g, {{"sigma", 2.1}})), 7);
    EXPECT_EQ(g.margin(resolveParams(g, {{"sigma", 1e-6}})), 1);
}

}  // namespace
}  // namespace glint::denoise

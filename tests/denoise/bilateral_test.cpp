// bilateral (exact): limits, edge preservation and numerical extremes (public API only).
#include <gtest/gtest.h>

#include <cmath>

#include "glint/denoise/filter.h"
#include "glint/denoise/registry.h"
#include "synthetic_frames.h"

namespace glint::denoise {
namespace {

TEST(Bilateral, HugeRangeSigmaEqualsGaussian) {
    const FrameBuffers frame = testing::syntheticFrame(31, 27, 0.2f);
    for (double sigma : {0.7, 2.0, 3.5}) {
        const Image b =
            applyFilter(findFilter("bilateral"), frame, {{"sigmaS", sigma}, {"sigmaR", 1e6}});
        const Image g = applyFilter(findFilter("gaussian"), frame, {{"sigma", sigma}});
        // Range weights are exp(-d²/2e12) = 1 to float precision; summation orders differ.
        EXPECT_LT(testing::maxAbsDiff(b, g), 1e-5) << "sigma " << sigma;
    }
}

TEST(Bilateral, TinySigmasAreTheIdentity) {
    const FrameBuffers frame = testing::syntheticFrame(15, 12, 0.2f);
    const Image s =
        applyFilter(findFilter("bilateral"), frame, {{"sigmaS", 1e-6}, {"sigmaR", 1.0}});
    EXPECT_EQ(testing::maxAbsDiff(s, frame.color()), 0.0);
    // Every neighbour differs by far more than sigmaR = 1e-6: only the centre keeps weight.
    const Image r =
        applyFilter(findFilter("bilateral"), frame, {{"sigmaS", 2.0}, {"sigmaR", 1e-6}});
    EXPECT_LT(testing::maxAbsDiff(r, frame.color()), 1e-7);
}

TEST(Bilateral, KeepsAnEdgeThatGaussianBlurs) {
    FrameBuffers frame = testing::constantFrame(32, 16, 0.1f, 0.1f, 0.1f);
    for (int y = 0; y < 16; ++y)
        for (int x = 16; x < 32; ++x)
            for (int c = 0; c < 3; ++c) frame.color()(x, y, c) = 0.9f;
    const Image b = applyFilter(findFilter("bilateral"), frame, {{"sigmaS", 3.0}, {"sigmaR", 0.1}});
    const Image g = applyFilter(findFilter("gaussian"), frame, {{"sigma", 3.0}});
    EXPECT_NEAR(b(15, 8, 0), 0.1f, 1e-4);
    EXPECT_NEAR(b(16, 8, 0), 0.9f, 1e-4);
    EXPECT_GT(g(15, 8, 0), 0.3f);  // the Gaussian mixes the two sides
}

TEST(Bilateral, RadiusParameterSetsTheWindow) {
    const Filter& f = findFilter("bilateral");
    EXPECT_EQ(f.margin(resolveParams(f, {{"radius", 15}})), 15);    // OpenCV d = 31
    EXPECT_EQ(f.margin(resolveParams(f, {{"sigmaS", 5.0}})), 15);   // ceil(3 sigmaS)
    EXPECT_EQ(f.margin(resolveParams(f, {{"sigmaS", 1e6}})), 100);  // capped
    // A larger window with the same sigmas changes the result only through the tail weights.
    const FrameBuffers frame = testing::syntheticFrame(24, 24, 0.1f);
    const Image r2 = applyFilter(f, frame, {{"sigmaS", 3.0}, {"radius", 2}});
    const Image r9 = applyFilter(f, frame, {{"sigmaS", 3.0}, {"radius", 9}});
    EXPECT_GT(testing::maxAbsDiff(r2, r9), 1e-4);
}

TEST(Bilateral, ExtremeSigmasAndRadianceStayFinite) {
    for (double sS : {1e-6, 1.5, 1e6})
        for (double sR : {1e-6, 0.1, 1e6})
            for (float scale : {1e-30f, 1.0f, 1e30f}) {
                FrameBuffers frame = testing::syntheticFrame(13, 11, 0.2f);
                for (float& v : frame.color().data()) v *= scale;
                const Image out = applyFilter(findFilter("bilateral"), frame,
                                              {{"sigmaS", sS}, {"sigmaR", sR}, {"radius", 4}});
                EXPECT_EQ(out.countNonFinite(), 0u) << sS << " " << sR << " " << scale;
                // A normalised filter never leaves the range of its input.
                float lo = frame.color()(0, 0, 0), hi = lo;
                for (float v : frame.color().data()) lo = std::min(lo, v), hi = std::max(hi, v);
                for (float v : out.data()) {
                    EXPECT_GE(v, lo - 1e-6f * std::fabs(lo));
                    EXPECT_LE(v, hi + 1e-6f * std::fabs(hi));
                }
            }
}

}  // namespace
}  // namespace glint::denoise

// bilateral-mc (Banterle et al. 2012): the full window is exact, error falls with samples,
// determinism (public API only).
#include <gtest/gtest.h>

#include <string>

#include "glint/denoise/filter.h"
#include "glint/denoise/registry.h"
#include "glint/image/error.h"
#include "synthetic_frames.h"

namespace glint::denoise {
namespace {

const char* kPatternNames[] = {"poisson", "regular", "random", "stratified"};

TEST(BilateralMc, AllWindowSamplesEqualsBilateral) {
    const FrameBuffers frame = testing::syntheticFrame(29, 23, 0.15f);
    const ParamValues common{{"sigmaS", 2.0}, {"sigmaR", 0.2}, {"radius", 5}};
    const Image exact = applyFilter(findFilter("bilateral"), frame, common);
    for (int kind = 0; kind < 4; ++kind) {
        ParamValues p = common;
        p["samplesPerSide"] = 11;  // k = N = 11: every pixel of the 11 x 11 window
        p["pattern"] = kind;
        const Image mc = applyFilter(findFilter("bilateral-mc"), frame, p);
        // Same weights, different summation order.
        EXPECT_LT(testing::maxAbsDiff(mc, exact), 1e-5) << kPatternNames[kind];
    }
}

TEST(BilateralMc, ErrorAgainstBilateralFallsAsSamplesGrow) {
    // 48 x 48 noisy frame, 15 x 15 window (225 pixels); k N = 15, 45, 105 samples. Fixed seed;
    // the RMS error over 6912 values is an average over many independent pixels, so each step
    // must lower it clearly (we ask for 10 %, the expected drop is > 30 %).
    const FrameBuffers frame = testing::syntheticFrame(48, 48, 0.1f);
    const ParamValues common{{"sigmaS", 4.0}, {"sigmaR", 0.3}, {"radius", 7}};
    const Image exact = applyFilter(findFilter("bilateral"), frame, common);
    for (int kind = 0; kind < 4; ++kind) {
        double previous = 1e9;
        for (int k : {1, 3, 7}) {
            ParamValues p = common;
            p["samplesPerSide"] = k;
            p["pattern"] = kind;
            const double err =
                testing::rmsDiff(applyFilter(findFilter("bilateral-mc"), frame, p), exact);
            EXPECT_LT(err, 0.9 * previous) << kPatternNames[kind] << " k=" << k;
            EXPECT_GT(err, 0.0);
            previous = err;
        }
    }
}

TEST(BilateralMc, DeterministicPerSeed) {
    const FrameBuffers frame = testing::syntheticFrame(20, 20, 0.1f);
    const Filter& f = findFilter("bilateral-mc");
    const Image a = applyFilter(f, frame, {{"seed", 5}});
    const Image b = applyFilter(f, frame, {{"seed", 5}});
    const Image c = applyFilter(f, frame, {{"seed", 6}});
    EXPECT_EQ(testing::maxAbsDiff(a, b), 0.0);
    EXPECT_GT(testing::maxAbsDiff(a, c), 0.0);
}

TEST(BilateralMc, MatchesBilateralMarginAndRejectsUnknownPattern) {
    const Filter& f = findFilter("bilateral-mc");
    EXPECT_EQ(f.margin(resolveParams(f, {{"radius", 30}})), 30);  // d = 61
    EXPECT_THROW(resolveParams(f, {{"pattern", 4}}), Error);
}

}  // namespace
}  // namespace glint::denoise

// The automatic selection's per-pixel choice by the halves (docs/auto.md, "Per-pixel choice"):
// what it picks, its determinism and its finer windows.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <tuple>
#include <vector>

#include "auto/stacking.h"
#include "glint/denoise/auto.h"
#include "glint/denoise/bank.h"
#include "glint/denoise/registry.h"
#include "glint/denoise/session.h"
#include "glint/image/error.h"
#include "glint/image/metrics.h"
#include "halves_frames.h"
#include "synthetic_frames.h"

#include <tbb/task_arena.h>

namespace glint::denoise {
namespace {

using namespace halves_test;

TEST(AutoChoice, SelectionPicksTheMemberWithTheSmallestTrueErrorWhereUnambiguous) {
    const Image clean = cleanImage(128, 96);
    const FrameBuffers f = halvesFrame(clean, 0.08, Noise::Skewed, 5);
    const FilterBank bank = gaussianBank(f, {0.4, 1.0, 3.0});
    AutoOptions o;
    o.tuning["space"] = 3;  // linear
    o.tuning["window"] = 3;
    o.tuning["confidence"] = 0.0;
    o.tuning["temperature"] = 0.0;
    const AutoResult r = autoComposite(bank, f, o);
    EXPECT_EQ(r.estimator, AutoEstimator::Halves);  // Auto: the frame has half buffers
    const AutoResult withDefaults = autoComposite(bank, f, AutoOptions{});
    const auto [unambiguous, agree] = testing::agreementWhereUnambiguous(bank, clean, r.choice, 3);
    ASSERT_GT(unambiguous, 128 * 96 / 3);
    // The estimate is of the error on a half (twice the noise variance), so the choice may
    // differ near the boundary between members: 90 %.
    EXPECT_GT(double(agree) / unambiguous, 0.9) << agree << " of " << unambiguous;
    double bestSingle = 1e30;
    for (std::size_t m = 0; m < bank.size(); ++m)
        bestSingle = std::min(bestSingle, glint::mse(bank.result(m), clean).value);
    EXPECT_LT(glint::mse(r.composite, clean).value, bestSingle);
    EXPECT_LT(glint::mse(withDefaults.composite, clean).value, bestSingle);
}

TEST(AutoChoice, SameResultForAnyThreadCountAndOneSidedDiffers) {
    const Image clean = cleanImage(64, 48);
    const FrameBuffers f = halvesFrame(clean, 0.08, Noise::Skewed, 9);
    const FilterBank bank = gaussianBank(f, {0.5, 1.0, 2.0, 4.0});
    AutoResult one, two;
    {
        tbb::task_arena arena(1);
        arena.execute([&] { one = autoComposite(bank, f); });
    }
    {
        tbb::task_arena arena(2);
        arena.execute([&] { two = autoComposite(bank, f); });
    }
    ASSERT_EQ(one.composite.data().size(), two.composite.data().size());
    for (std::size_t i = 0; i < one.composite.data().size(); ++i)
        ASSERT_EQ(one.composite.data()[i], two.composite.data()[i]);
    EXPECT_EQ(one.estimatedMse, two.estimatedMse);
    AutoOptions o;
    o.tuning["oneSided"] = 1;
    EXPECT_NE(autoComposite(bank, f, o).estimatedMse, one.estimatedMse);
}

TEST(AutoChoice, AFinerWindowKeepsASmallFeatureTheFullWindowSmoothsOver) {
    // Flat grey (0.4) with a small checkerboard of 0.2 and 0.6 (4×4 pixels) in the middle. The
    // wide Gaussian is right on the flat part and wrong on the patch, the narrow one the
    // reverse. In the default window (radius 8) the patch is 16 of 289 pixels, too few to move
    // the mean; halved twice (radius 2) it is 16 of 25. Fixed seed; measured: the patch's
    // squared error 1.92 with the full window (the wide member's), 0.157 with the finer one
    // (the narrow member's), MSE 1.2e-4 and 4.2e-5. Asserted: the finer choice's error on the
    // patch at most half the full window's, its MSE no larger.
    const int w = 96, h = 72;
    Image clean(w, h, 3, 0.4f);
    for (int y = 34; y < 38; ++y)
        for (int x = 46; x < 50; ++x)
            for (int c = 0; c < 3; ++c) clean(x, y, c) = (x + y) % 2 ? 0.6f : 0.2f;
    const FrameBuffers f = halvesFrame(clean, 0.08, Noise::Gaussian, 17);
    const FilterBank bank = gaussianBank(f, {0.3, 3.0});
    AutoOptions full, finer;
    full.tuning["finer"] = 0;
    finer.tuning["finer"] = 2;
    const AutoResult a = autoComposite(bank, f, full), b = autoComposite(bank, f, finer);
    auto patchError = [&](const Image& image) {
        double s = 0.0;
        for (int y = 34; y < 38; ++y)
            for (int x = 46; x < 50; ++x)
                for (int c = 0; c < 3; ++c) {
                    const double d = double(image(x, y, c)) - clean(x, y, c);
                    s += d * d;
                }
        return s;
    };
    std::printf("patch squared error: full window %.4f, finer %.4f; MSE %.3g and %.3g\n",
                patchError(a.composite), patchError(b.composite),
                glint::mse(a.composite, clean).value, glint::mse(b.composite, clean).value);
    EXPECT_LT(patchError(b.composite), 0.5 * patchError(a.composite));
    EXPECT_LE(glint::mse(b.composite, clean).value, glint::mse(a.composite, clean).value);
    // The halves' default halves the window once; SURE's does not.
    EXPECT_EQ(autoTuningDefaults(AutoEstimator::Halves).at("finer"), 1);
    EXPECT_EQ(autoTuningDefaults(AutoEstimator::Sure).at("finer"), 0);
    for (int bad : {-1, 7}) {
        AutoOptions o;
        o.tuning["finer"] = bad;
        EXPECT_THROW(autoComposite(bank, f, o), Error) << bad;
    }
}

}  // namespace
}  // namespace glint::denoise

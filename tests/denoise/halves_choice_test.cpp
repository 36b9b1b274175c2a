// The automatic selection's per-pixel choice by the halves (docs/auto.md, "Per-pixel choice"):
// what it picks, its determinism and its finer windows.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <tuple>
#include <vector>

#include "auto/choice.h"
#include "auto/estimator.h"
#include "auto/options.h"
#include "auto/stacking.h"
#include "glint/denoise/auto.h"
#include "glint/denoise/bank.h"
#include "glint/denoise/progress.h"
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

TEST(AutoChoice, TheFamilywiseMarginIsTheBonferroniQuantileOfTheConfidence) {
    // Φ⁻¹(1 − Φ(−1)/30) = 2.5556 (Φ(−1) = 0.158655; tables: Φ(−2.5556) = 0.0052885).
    EXPECT_NEAR(detail::familywiseMargin(1.0, 30), 2.5556, 1e-3);
    EXPECT_DOUBLE_EQ(detail::familywiseMargin(1.0, 1), 1.0);
    EXPECT_DOUBLE_EQ(detail::familywiseMargin(0.0, 70), 0.0);
    double previous = 1.0;
    for (std::size_t n : {2, 15, 70, 1000}) {
        const double margin = detail::familywiseMargin(1.0, n);
        EXPECT_GT(margin, previous) << n;
        previous = margin;
    }
    // Back through the tail: Φ(−margin)·n = Φ(−confidence).
    const auto tail = [](double z) { return 0.5 * std::erfc(z / std::sqrt(2.0)); };
    EXPECT_NEAR(tail(detail::familywiseMargin(3.0, 70)) * 70.0, tail(3.0), 1e-9);
}

// 16 candidates' maps on 192² pixels: independent Gaussian noise (σ 1, fixed seed) about 0 for
// the baseline (candidate 0) and 0.01 for the others: none is better anywhere.
detail::Estimates noiseMaps() {
    const int w = 192, h = 192;
    std::mt19937 rng(41);
    std::normal_distribution<float> noise(0.0f, 1.0f);
    detail::Estimates estimates;
    for (std::size_t m = 0; m < 16; ++m) {
        Image map(w, h, 1);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) map(x, y, 0) = noise(rng) + (m == 0 ? 0.0f : 0.01f);
        estimates.mapMean.push_back(detail::meanPerChannel(map));
        estimates.maps.push_back(std::move(map));
    }
    return estimates;
}

// The final choice among the 16 with window radius 8, confidence 1, `finer` 1 and a hard choice.
detail::Choice chooseAmong(const detail::Estimates& estimates, bool familywise) {
    std::vector<std::size_t> candidates(estimates.maps.size());
    for (std::size_t m = 0; m < candidates.size(); ++m) candidates[m] = m;
    detail::AutoSettings settings;
    settings.window = 8;
    settings.confidence = 1.0;
    settings.finer = 1;
    settings.familywise = familywise;
    WorkContext work;
    return detail::choose(estimates, candidates, true, settings, Image{}, work);
}

TEST(AutoChoice, AmongManyEqualCandidatesTheFamilywiseMarginKeepsTheBaseline) {
    // The winner's curse (docs/auto.md, "Per-pixel choice"): none of 15 candidates is better
    // than the baseline anywhere, yet with each comparison at one standard error the lowest of
    // 30 scores (two radii) leaves the baseline at most pixels; with the family's margin at
    // about Φ(−1) = 16 % of them or fewer (Bonferroni is conservative). About 128 independent
    // windows: standard error of a fraction about 0.03. Measured (fixed seed): 0.72 and 0.09.
    // Asserted: above 0.6 and below 0.25.
    const detail::Estimates estimates = noiseMaps();
    std::size_t baseline = 0;
    for (std::size_t m = 0; m < estimates.maps.size(); ++m)
        if (estimates.mapMean[m] < estimates.mapMean[baseline]) baseline = m;
    const auto leaving = [&](bool familywise) {
        const detail::Choice c = chooseAmong(estimates, familywise);
        return 1.0 - double(c.wins[baseline]) / double(192 * 192);
    };
    const double each = leaving(false), family = leaving(true);
    std::printf("pixels leaving the baseline: %.3f each, %.3f family\n", each, family);
    EXPECT_GT(each, 0.6);
    EXPECT_LT(family, 0.25);
    // Not the default: it loses where a mix of members is really better (docs/auto.md).
    EXPECT_EQ(autoTuningDefaults(AutoEstimator::Halves).at("margin"), 0);  // each
}

}  // namespace
}  // namespace glint::denoise

// Tests of glint/image/mc_compare.h and glint/image/expectation.h: the Monte Carlo-aware
// comparison's false-alarm rate and power on synthetic Monte Carlo images of known variance,
// expectations and bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <string>

#include "glint/image/error.h"
#include "glint/image/expectation.h"
#include "glint/image/mc_compare.h"

using namespace glint;

namespace mc_test {

constexpr int kSize = 64;

/// A Monte Carlo estimate of `truth` at `spp` samples of standard deviation sigma per sample
/// (Gaussian samples): the mean is truth + N(0, sigma^2/spp), the variance of the mean
/// sigma^2/spp * chi2(spp - 1)/(spp - 1) (chi-square by the Wilson-Hilferty approximation).
struct Estimate {
    Image mean, variance;
};

/// The test image, `bias` (relative) added in `biased` to channel `only` (-1: every channel).
Image truth(double bias, Rect biased, int only = -1) {
    Image t(kSize, kSize, 3);
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x)
            for (int c = 0; c < 3; ++c) {
                const double v = 0.35 + 0.3 * std::sin(0.1 * x + c) * std::cos(0.07 * y);
                const bool in = x >= biased.x0 && x < biased.x1 && y >= biased.y0 && y < biased.y1;
                t(x, y, c) = float(in && (only < 0 || only == c) ? v * (1.0 + bias) : v);
            }
    return t;
}

/// With `correlated`, a pixel's three channels share their noise (as a render's R, G and B come
/// from the same paths): one deviate and one variance estimate per pixel.
Estimate render(const Image& t, int spp, double sigma, std::uint64_t seed,
                bool correlated = false) {
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> normal;
    Estimate e{Image(kSize, kSize, 3), Image(kSize, kSize, 3)};
    const double k = spp - 1.0;
    double noise = 0.0, wh = 1.0;
    for (std::size_t i = 0; i < t.data().size(); ++i) {
        const double meanVariance = sigma * sigma / spp;
        if (!correlated || i % 3 == 0) {
            noise = normal(rng);
            wh = 1.0 - 2.0 / (9.0 * k) + std::sqrt(2.0 / (9.0 * k)) * normal(rng);
        }
        e.mean.data()[i] = float(t.data()[i] + std::sqrt(meanVariance) * noise);
        e.variance.data()[i] = float(meanVariance * wh * wh * wh);
    }
    return e;
}

// The test renders: 64 spp, per-sample standard deviation 0.15 (30 % of the mean 0.5); the
// reference: 4096 spp of the unbiased image.
constexpr int kSpp = 64;
constexpr double kSigma = 0.15;
const Rect kBiasRegion{21, 37, 37, 53};  // 16 x 16, on no window boundary

McCompareResult compareSeed(std::uint64_t seed, double bias, double alpha,
                            bool correlated = false) {
    const Estimate reference = render(truth(0.0, {}), 4096, kSigma, 1000000 + seed, correlated);
    const Estimate test = render(truth(bias, kBiasRegion), kSpp, kSigma, seed, correlated);
    McCompareOptions options;
    options.falseAlarmRate = alpha;
    return mcCompare(test.mean, test.variance, reference.mean, reference.variance, options);
}

}  // namespace mc_test

using namespace mc_test;

TEST(McCompare, NoFalseAlarmOverAThousandSeedsAtItsStatedRate) {
    // At the default rate 1e-4, 1,000 unbiased renders are expected to give 0.1 alarms: none is
    // seen. At 5 % the alarms stay within the binomial bound (50 + 3 sd): the bound holds.
    int alarms = 0, alarmsAtFivePercent = 0;
    for (std::uint64_t seed = 0; seed < 1000; ++seed) {
        const McCompareResult r = compareSeed(seed, 0.0, 1e-4);
        alarms += !r.passed;
        alarmsAtFivePercent += r.statistic > std::sqrt(2.0 * std::log(2.0 * r.windows / 0.05));
    }
    EXPECT_EQ(alarms, 0);
    EXPECT_LE(alarmsAtFivePercent, 71);
}

TEST(McCompare, ChannelsThatShareTheirNoiseKeepTheStatedRate) {
    // R, G and B of a pixel with the same noise (a render's channels come from the same paths):
    // at 5 %, 400 unbiased renders give at most 20 + 3 sd = 33 alarms by the binomial bound.
    // Counted as independent values, the statistic would be sqrt(3) too large (all 400 alarm).
    int alarmsAtFivePercent = 0;
    for (std::uint64_t seed = 0; seed < 400; ++seed) {
        const McCompareResult r = compareSeed(seed, 0.0, 0.05, true);
        alarmsAtFivePercent += !r.passed;
    }
    EXPECT_LE(alarmsAtFivePercent, 33);
    // Shared noise carries a third of the independent channels' information: a bias √3 times
    // the 2 % one above (3.5 %) is still caught on every seed.
    for (std::uint64_t seed = 0; seed < 20; ++seed)
        EXPECT_FALSE(compareSeed(seed, 0.035, 1e-4, true).passed) << "seed " << seed;
}

TEST(McCompare, CatchesATwoPercentBiasConfinedToASixteenPixelSquareAt64Spp) {
    for (std::uint64_t seed = 0; seed < 100; ++seed) {
        const McCompareResult r = compareSeed(seed, 0.02, 1e-4);
        EXPECT_FALSE(r.passed) << "seed " << seed << ": statistic " << r.statistic
                               << " <= " << r.threshold;
        // The worst window overlaps the biased square and measures a bias near +2 %.
        EXPECT_FALSE(intersect(r.worstWindow, kBiasRegion).empty()) << "seed " << seed;
        EXPECT_GT(r.relativeBias, 0.005) << "seed " << seed;
    }
}

TEST(McCompare, ByChannelCatchesATintThatTheWholePixelsSumDilutes) {
    // A 6 % change of the red channel alone in the 16 x 16 square, channels sharing their noise:
    // compared by channel (1e-4 split over three), every seed fails; compared as whole pixels,
    // where the change is a third of the pixel's term, most pass. Unbiased renders keep the
    // stated rate by channel: at 5 %, 400 seeds give at most 20 + 3 sd = 33 alarms.
    int wholePixelAlarms = 0, unbiasedAlarms = 0;
    for (std::uint64_t seed = 0; seed < 20; ++seed) {
        const Estimate reference = render(truth(0.0, {}), 4096, kSigma, 1000000 + seed, true);
        const Estimate tinted = render(truth(0.06, kBiasRegion, 0), kSpp, kSigma, seed, true);
        const McCompareResult r =
            mcCompareByChannel(tinted.mean, tinted.variance, reference.mean, reference.variance);
        EXPECT_FALSE(r.passed) << "seed " << seed << ": statistic " << r.statistic;
        EXPECT_FALSE(intersect(r.worstWindow, kBiasRegion).empty()) << "seed " << seed;
        wholePixelAlarms +=
            !mcCompare(tinted.mean, tinted.variance, reference.mean, reference.variance).passed;
    }
    EXPECT_LT(wholePixelAlarms, 10) << wholePixelAlarms << " of 20";
    McCompareOptions fivePercent;
    fivePercent.falseAlarmRate = 0.05;
    for (std::uint64_t seed = 0; seed < 400; ++seed) {
        const Estimate reference = render(truth(0.0, {}), 4096, kSigma, 1000000 + seed, true);
        const Estimate test = render(truth(0.0, {}), kSpp, kSigma, seed, true);
        unbiasedAlarms += !mcCompareByChannel(test.mean, test.variance, reference.mean,
                                              reference.variance, fivePercent)
                               .passed;
    }
    EXPECT_LE(unbiasedAlarms, 33);
    const Estimate e = render(truth(0.0, {}), 16, 0.1, 1);
    EXPECT_THROW(mcCompareByChannel(e.mean, Image(3, 3, 3), e.mean, e.variance), Error);
}

TEST(McCompare, BadInputIsAnError) {
    const Estimate e = render(truth(0.0, {}), 16, 0.1, 1);
    Image nan = e.mean;
    nan(2, 3, 1) = std::numeric_limits<float>::quiet_NaN();
    EXPECT_THROW(mcCompare(nan, e.variance, e.mean, e.variance), Error);
    Image negative = e.variance;
    negative(0, 0, 0) = -1.0f;
    EXPECT_THROW(mcCompare(e.mean, negative, e.mean, e.variance), Error);
    EXPECT_THROW(mcCompare(e.mean, Image(3, 3, 3), e.mean, e.variance), Error);
    McCompareOptions alpha;
    alpha.falseAlarmRate = 1.0;
    EXPECT_THROW(mcCompare(e.mean, e.variance, e.mean, e.variance, alpha), Error);
    // The rate given is written as given, not as six fixed decimals ("0.000000").
    alpha.falseAlarmRate = -1e-7;
    try {
        mcCompare(e.mean, e.variance, e.mean, e.variance, alpha);
        ADD_FAILURE() << "a negative rate was taken";
    } catch (const Error& error) {
        EXPECT_NE(std::string(error.what()).find("got -1e-07"), std::string::npos) << error.what();
    }
}

TEST(Expectations, ParseBoundsAndTheMonteCarloComparison) {
    const Expectation ssim = parseExpectation("ssim >= 0.98");
    EXPECT_EQ(ssim.metric, "ssim");
    EXPECT_TRUE(ssim.atLeast);
    EXPECT_FALSE(ssim.strict);
    EXPECT_EQ(ssim.threshold, 0.98);
    const Expectation flip = parseExpectation("FLIP<0.05");
    EXPECT_EQ(flip.metric, "flip");
    EXPECT_FALSE(flip.atLeast);
    EXPECT_TRUE(flip.strict);
    EXPECT_TRUE(parseExpectation("mc").monteCarlo);
    EXPECT_EQ(parseExpectation("mc:1e-6").threshold, 1e-6);
    for (const char* bad : {"ssim=0.9", "lpips<=0.1", "psnr>=x", "mc:2", ">=1", "ssim>=nan"})
        EXPECT_THROW(parseExpectation(bad), Error) << bad;
}

TEST(Expectations, AFailedExpectationSaysWhichAndByHowMuch) {
    ComparedImage a{FrameBuffers(16, 16), false}, b{FrameBuffers(16, 16), false};
    for (float& v : a.frame.color().data()) v = 0.5f;
    for (float& v : b.frame.color().data()) v = 0.75f;
    const auto outcomes =
        checkExpectations(a, b, {parseExpectation("mse<=0.1"), parseExpectation("psnr>=20")});
    ASSERT_EQ(outcomes.size(), 2u);
    EXPECT_TRUE(outcomes[0].passed) << outcomes[0].message;
    EXPECT_FALSE(outcomes[1].passed);
    // PSNR of a 0.25 offset: 10 log10(16) = 12.04 dB, 7.96 short.
    EXPECT_NE(outcomes[1].message.find("psnr 12.04"), std::string::npos) << outcomes[1].message;
    EXPECT_NE(outcomes[1].message.find("by 7.95"), std::string::npos) << outcomes[1].message;
    // mc needs the variance layers.
    EXPECT_THROW(checkExpectations(a, b, {parseExpectation("mc")}), Error);
    // flip on display values is LDR-FLIP, on radiance HDR-FLIP.
    EXPECT_EQ(resolveMetric("flip", false), Metric::FlipLdr);
    EXPECT_EQ(resolveMetric("flip", true), Metric::FlipHdr);
}

// The auto composite's second error estimator: cross-validation on two independent halves of
// the samples (sure.h, crossValidationMap; docs/auto.md, "Error estimation by cross-validation
// on the halves"), on synthetic frames whose clean image is known.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <tuple>
#include <vector>

#include "auto/stacking.h"
#include "glint/denoise/bank.h"
#include "glint/denoise/registry.h"
#include "glint/denoise/session.h"
#include "glint/denoise/sure.h"
#include "glint/image/error.h"
#include "glint/image/metrics.h"
#include "synthetic_frames.h"

#include <tbb/task_arena.h>

namespace glint::denoise {
namespace {

// Smooth shading with a sharp disc and, for x >= w/2, a fine checkerboard (where only a tiny
// blur is right).
Image cleanImage(int w, int h) {
    Image x(w, h, 3);
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) {
            const double dx = i - 0.3 * w, dy = j - 0.5 * h;
            double v = 0.3 + 0.2 * std::sin(6.0 * i / w) * std::cos(4.0 * j / h) +
                       (dx * dx + dy * dy < 0.04 * w * w ? 0.3 : 0.0);
            if (i >= w / 2) v += ((i / 2 + j / 2) % 2 ? 0.25 : -0.25);
            for (int c = 0; c < 3; ++c) x(i, j, c) = float(v * (1.0 - 0.2 * c));
        }
    return x;
}

// The noise of one half: Gaussian, or skewed like radiance (an exponential with the same
// standard deviation, shifted to mean 0: rare large positive values), or Gaussian with
// fireflies (one value in 100 is 30 sigma higher; shifted to mean 0).
enum class Noise { Gaussian, Skewed, Fireflies };

// A frame with half buffers made of two independent halves of one "sample" each:
// A = x + n_A, B = x + n_B, colour (A + B)/2, halfColor B, sampleCount 2, halfSampleCount 1, and
// the variance layers those samples give. `halfA`/`halfB` receive the halves' colours.
FrameBuffers halvesFrame(const Image& clean, double sigma, Noise noise, std::uint32_t seed,
                         Image* halfA = nullptr, Image* halfB = nullptr) {
    const int w = clean.width(), h = clean.height();
    std::mt19937 rng(seed);
    std::normal_distribution<double> gauss(0.0, sigma);
    std::exponential_distribution<double> expo(1.0 / sigma);
    std::uniform_real_distribution<double> uniform(0.0, 1.0);
    auto draw = [&] {
        switch (noise) {
            case Noise::Gaussian:
                return gauss(rng);
            case Noise::Skewed:
                return expo(rng) - sigma;
            case Noise::Fireflies:
                return gauss(rng) + (uniform(rng) < 0.01 ? 30.0 * sigma : 0.0) - 0.3 * sigma;
        }
        return 0.0;
    };
    FrameBuffers f(w, h);
    Image a(w, h, 3), b(w, h, 3);
    for (std::size_t i = 0; i < a.data().size(); ++i) {
        a.data()[i] = float(clean.data()[i] + draw());
        b.data()[i] = float(clean.data()[i] + draw());
    }
    Image& color = f.color();
    Image& variance = f.ensure(Layer::Variance);
    for (std::size_t i = 0; i < a.data().size(); ++i) {
        color.data()[i] = float(0.5 * (double(a.data()[i]) + b.data()[i]));
        const double d = double(a.data()[i]) - b.data()[i];
        variance.data()[i] = float(0.25 * d * d);  // sample variance / n with n = 2
    }
    f.set(Layer::HalfColor, b);
    f.ensure(Layer::HalfVariance);  // one sample: 0
    for (float& v : f.ensure(Layer::SampleCount).data()) v = 2.0f;
    for (float& v : f.ensure(Layer::HalfSampleCount).data()) v = 1.0f;
    if (halfA) *halfA = a;
    if (halfB) *halfB = b;
    return f;
}

// Checks that the mean of the cross-validation map estimates the filter's mean squared error on
// a half, with a tolerance of 5 standard errors computed from the per-value differences
// between the estimate and the truth (the test calibrates itself to the noise it draws).
void expectUnbiased(const Filter& filter, const ParamValues& params, Noise noise, bool symmetric) {
    const Image clean = cleanImage(128, 96);
    Image a, b;
    const FrameBuffers f = halvesFrame(clean, 0.08, noise, 21, &a, &b);
    const auto [frameA, frameB] = splitHalves(f);
    const Rect r{0, 128, 0, 96};
    const Image outA = applyFilter(filter, frameA, params);
    const Image outB = applyFilter(filter, frameB, params);
    const Image map = crossValidationMap(a, b, outA, symmetric ? &outB : nullptr, r);
    // Per value: the estimate's term minus the true term.
    std::vector<double> diff;
    for (int y = 0; y < 96; ++y)
        for (int x = 0; x < 128; ++x) {
            double truth = 0.0;
            for (int c = 0; c < 3; ++c) {
                const double ea = double(outA(x, y, c)) - clean(x, y, c);
                const double eb = double(outB(x, y, c)) - clean(x, y, c);
                truth += symmetric ? 0.5 * (ea * ea + eb * eb) : ea * ea;
            }
            diff.push_back(double(map(x, y, 0)) - truth);
        }
    double mean = 0.0, sq = 0.0;
    for (double d : diff) mean += d;
    mean /= double(diff.size());
    for (double d : diff) sq += (d - mean) * (d - mean);
    const double standardError = std::sqrt(sq / double(diff.size() - 1) / double(diff.size()));
    const double trueMse =
        symmetric ? 0.5 * (glint::mse(outA, clean).value + glint::mse(outB, clean).value)
                  : glint::mse(outA, clean).value;
    std::printf(
        "%s, %s noise, %s: estimated MSE %.6f, true %.6f, standard error %.6f\n",
        std::string(filter.name()).c_str(), noise == Noise::Gaussian ? "Gaussian" : "skewed",
        symmetric ? "symmetric" : "one-sided", trueMse + mean / 3.0, trueMse, standardError / 3.0);
    EXPECT_LT(std::abs(mean), 5.0 * standardError) << "bias " << mean / 3.0;
    // And the estimate is informative: its error is small against the MSE itself.
    EXPECT_LT(std::abs(mean / 3.0), 0.1 * trueMse);
}

TEST(Halves, CrossValidationEstimatesAGaussiansErrorWithoutBias) {
    const Filter& gaussian = findFilter("gaussian");
    const ParamValues params = resolveParams(gaussian, {{"sigma", 1.5}});
    expectUnbiased(gaussian, params, Noise::Gaussian, true);
    expectUnbiased(gaussian, params, Noise::Gaussian, false);
}

TEST(Halves, CrossValidationNeedsNoGaussianNoiseNorALinearFilter) {
    // Skewed noise and a nonlinear filter: outside Stein's lemma, still unbiased.
    const Filter& nlmeans = findFilter("nlmeans");
    expectUnbiased(nlmeans, resolveParams(nlmeans, {}), Noise::Skewed, true);
    const Filter& bilateral = findFilter("bilateral");
    expectUnbiased(bilateral, resolveParams(bilateral, {}), Noise::Skewed, true);
}

TEST(Halves, DisplayExactComparesDisplayValues) {
    // One pixel, one channel used: A = 0.2, B = 0.5, f(A) = 0.3, f(B) = 4 (clamped to 1).
    Image a(1, 1, 3, 0.2f), b(1, 1, 3, 0.5f), fa(1, 1, 3, 0.3f), fb(1, 1, 3, 4.0f);
    auto srgb = [](double x) {
        x = std::clamp(x, 0.0, 1.0);
        return x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1.0 / 2.4) - 0.055;
    };
    const Rect r{0, 1, 0, 1};
    const double da = srgb(0.2), db = srgb(0.5), dfa = srgb(0.3), dfb = 1.0;
    const double expected =
        3.0 * 0.5 * ((dfa - db) * (dfa - db) + (dfb - da) * (dfb - da) - (da - db) * (da - db));
    EXPECT_NEAR(crossValidationMap(a, b, fa, &fb, r, nullptr, 0.0f)(0, 0, 0), expected, 1e-4);
    // Exposure +1 doubles the linear values before the transform.
    const double da2 = srgb(0.4), db2 = srgb(1.0), dfa2 = srgb(0.6);
    const double expected2 = 3.0 * ((dfa2 - db2) * (dfa2 - db2) - 0.5 * (da2 - db2) * (da2 - db2));
    EXPECT_NEAR(crossValidationMap(a, b, fa, nullptr, r, nullptr, 1.0f)(0, 0, 0), expected2, 1e-4);
    // Linear: the plain values.
    const double linear = 3.0 * 0.5 * (0.2 * 0.2 + 3.8 * 3.8 - 0.3 * 0.3);
    EXPECT_NEAR(crossValidationMap(a, b, fa, &fb, r)(0, 0, 0), linear, 1e-5);
}

double srgbOf(double x) {
    x = std::clamp(x, 0.0, 1.0);
    return x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1.0 / 2.4) - 0.055;
}

TEST(Halves, SecantWeighsEachOutputBetweenItAndTheCentre) {
    // One pixel: A = 0.2, B = 0.5, f(A) = 0.3, f(B) = 4 (clamped), centre m = 0.6.
    Image a(1, 1, 3, 0.2f), b(1, 1, 3, 0.5f), fa(1, 1, 3, 0.3f), fb(1, 1, 3, 4.0f);
    const Image m(1, 1, 3, 0.6f);
    const Rect r{0, 1, 0, 1};
    const double sa = (srgbOf(0.3) - srgbOf(0.6)) / (0.3 - 0.6);
    const double sb = (1.0 - srgbOf(0.6)) / (4.0 - 0.6);
    const double noise = 0.5 * 0.3 * 0.3;
    const double expected =
        3.0 * 0.5 * (sa * sa * (0.2 * 0.2 - noise) + sb * sb * (3.8 * 3.8 - noise));
    EXPECT_NEAR(secantCrossValidationMap(a, b, fa, &fb, r, m)(0, 0, 0), expected, 1e-4);
    EXPECT_NEAR(secantCrossValidationMap(a, b, fa, nullptr, r, m)(0, 0, 0),
                3.0 * sa * sa * (0.2 * 0.2 - noise), 1e-4);
    // An output equal to the centre: the slope there (sRGB at 0.6).
    const double slope = 1.055 / 2.4 * std::pow(0.6, 1.0 / 2.4 - 1.0);
    EXPECT_NEAR(secantCrossValidationMap(a, b, m, nullptr, r, m)(0, 0, 0),
                3.0 * slope * slope * (0.6 - 0.5) * (0.6 - 0.5) - 3.0 * slope * slope * noise,
                1e-4);
    // Output and centre both above the clamp: they display alike, weight 0.
    const Image two(1, 1, 3, 2.0f), three(1, 1, 3, 3.0f);
    EXPECT_EQ(secantCrossValidationMap(a, b, two, nullptr, r, three)(0, 0, 0), 0.0f);
    // Exposure +1 doubles the linear values before the transform.
    const double sa2 = (srgbOf(0.6) - srgbOf(1.2)) / (0.3 - 0.6);
    EXPECT_NEAR(secantCrossValidationMap(a, b, fa, nullptr, r, m, 1.0f)(0, 0, 0),
                3.0 * sa2 * sa2 * (0.2 * 0.2 - noise), 1e-4);
}

// A highlight above the display's clamp (1.6, a disc of radius 20) on a mid background (0.3),
// 128×96, with halves of the given noise (sigma 0.05), both filtered by a Gaussian of `sigma`.
struct Highlight {
    static constexpr int w = 128, h = 96;
    Image clean{w, h, 3}, a, b, outA, outB;
    Highlight(Noise noise, std::uint32_t seed, double sigma) {
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const double dx = x - 64.0, dy = y - 48.0;
                for (int c = 0; c < 3; ++c)
                    clean(x, y, c) = dx * dx + dy * dy < 20.0 * 20.0 ? 1.6f : 0.3f;
            }
        const FrameBuffers f = halvesFrame(clean, 0.05, noise, seed, &a, &b);
        const auto [frameA, frameB] = splitHalves(f);
        const Filter& gaussian = findFilter("gaussian");
        const ParamValues params = resolveParams(gaussian, {{"sigma", sigma}});
        outA = applyFilter(gaussian, frameA, params);
        outB = applyFilter(gaussian, frameB, params);
    }
    // The true display error of f(A) and f(B) at (x, y), averaged, summed over channels.
    double displayError(int x, int y) const {
        double t = 0.0;
        for (int c = 0; c < 3; ++c) {
            const double dx = srgbOf(clean(x, y, c));
            const double ea = srgbOf(outA(x, y, c)) - dx, eb = srgbOf(outB(x, y, c)) - dx;
            t += 0.5 * (ea * ea + eb * eb);
        }
        return t;
    }
};

TEST(Halves, SecantEstimatesTheDisplayErrorOfABlurredHighlight) {
    // A highlight above the display's clamp (1.6) on a mid background (0.3) with Gaussian
    // noise; a Gaussian of sigma 2 blurs the highlight's rim below 1. With the clean image as the
    // centre, the secant map's mean estimates the true display MSE of f(A) and f(B) within 5
    // standard errors (computed from the per-value differences, as in expectUnbiased) and 10 %;
    // the slope at the centre (0 inside the highlight, steep outside) misses it by far more.
    const Highlight hl(Noise::Gaussian, 33, 2.0);
    const Image &clean = hl.clean, &a = hl.a, &b = hl.b, &outA = hl.outA, &outB = hl.outB;
    const int w = hl.w, h = hl.h;
    const Rect r{0, w, 0, h};
    const Image secant = secantCrossValidationMap(a, b, outA, &outB, r, clean);
    Image slope2(w, h, 3);
    for (std::size_t i = 0; i < clean.data().size(); ++i) {
        const double v = clean.data()[i];
        const double s = v >= 1.0 ? 0.0 : 1.055 / 2.4 * std::pow(v, 1.0 / 2.4 - 1.0);
        slope2.data()[i] = float(s * s);
    }
    const Image tangent = crossValidationMap(a, b, outA, &outB, r, &slope2);
    std::vector<double> diff;
    double truth = 0.0, tangentMean = 0.0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const double t = hl.displayError(x, y);
            truth += t;
            tangentMean += tangent(x, y, 0);
            diff.push_back(double(secant(x, y, 0)) - t);
        }
    const double n = double(diff.size());
    truth /= n;
    tangentMean /= n;
    double mean = 0.0, sq = 0.0;
    for (double d : diff) mean += d;
    mean /= n;
    for (double d : diff) sq += (d - mean) * (d - mean);
    const double standardError = std::sqrt(sq / (n - 1.0) / n);
    std::printf("display MSE %.6f: secant %.6f (standard error %.6f), tangent %.6f\n", truth,
                truth + mean, standardError, tangentMean);
    EXPECT_LT(std::abs(mean), 5.0 * standardError);
    EXPECT_LT(std::abs(mean), 0.1 * truth);
    EXPECT_GT(std::abs(tangentMean - truth), 0.3 * truth);
}

TEST(Halves, TheCentredSecantFormIsTheUnbiasedOneLessTheCentresOwnTerm) {
    // The pixel of SecantWeighsEachOutputBetweenItAndTheCentre: A = 0.2, B = 0.5, f(A) = 0.3,
    // f(B) = 4, m = 0.6. Centred, each side is s² (f − m)(f + m − 2·other half).
    Image a(1, 1, 3, 0.2f), b(1, 1, 3, 0.5f), fa(1, 1, 3, 0.3f), fb(1, 1, 3, 4.0f);
    const Image m(1, 1, 3, 0.6f);
    const Rect r{0, 1, 0, 1};
    const double sa = (srgbOf(0.3) - srgbOf(0.6)) / (0.3 - 0.6);
    const double sb = (1.0 - srgbOf(0.6)) / (4.0 - 0.6);
    const double centred =
        3.0 * 0.5 * (sa * sa * (0.3 - 0.6) * (0.3 + 0.6 - 1.0) + sb * sb * 3.4 * (4.6 - 0.4));
    const double noise = 0.5 * 0.3 * 0.3;
    const double unbiased =
        3.0 * 0.5 * (sa * sa * (0.2 * 0.2 - noise) + sb * sb * (3.8 * 3.8 - noise));
    double mean = -1.0;
    EXPECT_NEAR(
        secantCrossValidationMap(a, b, fa, &fb, r, m, 0.0f, SecantForm::Centred, &mean)(0, 0, 0),
        centred, 1e-4);
    // The mean per pixel and channel of the unbiased form, whatever the form asked for.
    EXPECT_NEAR(mean, unbiased / 3.0, 1e-5);
    EXPECT_NEAR(
        secantCrossValidationMap(a, b, fa, &fb, r, m, 0.0f, SecantForm::Unbiased, &mean)(0, 0, 0),
        unbiased, 1e-4);
    EXPECT_NEAR(mean, unbiased / 3.0, 1e-5);
    EXPECT_NEAR(
        secantCrossValidationMap(a, b, fa, nullptr, r, m, 0.0f, SecantForm::Centred)(0, 0, 0),
        3.0 * sa * sa * (0.3 - 0.6) * (0.3 + 0.6 - 1.0), 1e-4);
    // An output at the centre: 0, however noisy the other half.
    EXPECT_EQ(secantCrossValidationMap(a, b, m, nullptr, r, m, 0.0f, SecantForm::Centred)(0, 0, 0),
              0.0f);
}

TEST(Halves, TheCentredSecantFormEstimatesTheSameErrorWithFarLessNoise) {
    // The highlight of SecantEstimatesTheDisplayErrorOfABlurredHighlight with fireflies (one
    // value in 100 is 30 sigma high) and the clean image as the centre, where the centre's own
    // error is 0 and both forms estimate the display MSE of f(A) and f(B). Measured (fixed
    // seed): truth 0.00598, centred 0.00606 with a per-pixel deviation variance of 2.2e-4;
    // the unbiased form 0.0133 with 1.3e-3 (a firefly in A raises f(A), which lowers the weight
    // on the ½(A − B)² it subtracts: it is unbiased only if the weight does not follow A).
    // Asserted: the centred mean within 5 standard errors and 10 % of the truth, and less than
    // a third of the unbiased form's variance.
    const Highlight hl(Noise::Fireflies, 35, 1.0);
    const Image &clean = hl.clean, &a = hl.a, &b = hl.b, &outA = hl.outA, &outB = hl.outB;
    const int w = hl.w, h = hl.h;
    const Rect r{0, w, 0, h};
    double unbiasedMean = 0.0;
    const Image centred = secantCrossValidationMap(a, b, outA, &outB, r, clean, 0.0f,
                                                   SecantForm::Centred, &unbiasedMean);
    const Image unbiased = secantCrossValidationMap(a, b, outA, &outB, r, clean);
    std::vector<double> dc, du;
    double truth = 0.0, unbiasedMapMean = 0.0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const double t = hl.displayError(x, y);
            truth += t;
            unbiasedMapMean += unbiased(x, y, 0);
            dc.push_back(double(centred(x, y, 0)) - t);
            du.push_back(double(unbiased(x, y, 0)) - t);
        }
    const double n = double(dc.size());
    truth /= n;
    unbiasedMapMean /= n;
    auto meanVar = [&](const std::vector<double>& d) {
        double mean = 0.0, sq = 0.0;
        for (double v : d) mean += v;
        mean /= n;
        for (double v : d) sq += (v - mean) * (v - mean);
        return std::make_pair(mean, sq / (n - 1.0));
    };
    const auto [meanC, varC] = meanVar(dc);
    const auto [meanU, varU] = meanVar(du);
    std::printf("display MSE %.6f: centred %.6f (variance %.3g), unbiased %.6f (variance %.3g)\n",
                truth, truth + meanC, varC, truth + meanU, varU);
    EXPECT_LT(std::abs(meanC), 5.0 * std::sqrt(varC / n));
    EXPECT_LT(std::abs(meanC), 0.1 * truth);
    EXPECT_LT(varC, varU / 3.0);
    // unbiasedMean is the unbiased map's mean per channel (the map sums the three channels).
    EXPECT_NEAR(unbiasedMean, unbiasedMapMean / 3.0, 1e-6 * std::abs(unbiasedMapMean));
}

FilterBank gaussianBank(const FrameBuffers& f, const std::vector<double>& sigmas) {
    std::vector<BankMember> members;
    std::vector<Image> results;
    for (double s : sigmas) {
        members.push_back(
            {"gaussian", resolveParams(findFilter("gaussian"), {{"sigma", s}}), false});
        results.push_back(applyFilter(findFilter("gaussian"), f, members.back().params));
    }
    return FilterBank(std::move(members), std::move(results), Rect{0, f.width(), 0, f.height()},
                      f.width(), f.height(), hashFrame(f));
}

TEST(Halves, SelectionPicksTheMemberWithTheSmallestTrueErrorWhereUnambiguous) {
    const Image clean = cleanImage(128, 96);
    const FrameBuffers f = halvesFrame(clean, 0.08, Noise::Skewed, 5);
    const FilterBank bank = gaussianBank(f, {0.4, 1.0, 3.0});
    AutoOptions o;
    o.space = SureSpace::Linear;
    o.window = 3;
    o.confidence = 0.0;
    o.temperature = 0.0;
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

TEST(Halves, AutoUsesSureWithoutHalfBuffersAndRefusesHalvesNamingTheLayer) {
    const FrameBuffers plain = testing::syntheticFrame(24, 20, 0.05f);
    EXPECT_EQ(resolveEstimator(AutoEstimator::Auto, plain), AutoEstimator::Sure);
    const FilterBank bank = gaussianBank(plain, {1.0, 2.0});
    EXPECT_EQ(autoComposite(bank, plain).estimator, AutoEstimator::Sure);
    AutoOptions o;
    o.estimator = AutoEstimator::Halves;
    try {
        checkAutoInput(plain, AutoEstimator::Halves, "plain.exr");
        FAIL() << "no error";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::Format);
        EXPECT_EQ(e.file(), "plain.exr");
        EXPECT_EQ(e.where(), "layer 'halfColor'");
        EXPECT_NE(e.message().find("--half-buffers"), std::string::npos) << e.what();
    }
    EXPECT_THROW(autoComposite(bank, plain, o), Error);
    EXPECT_EQ(parseAutoEstimator("halves"), AutoEstimator::Halves);
    EXPECT_THROW(parseAutoEstimator("stein"), Error);
}

TEST(Halves, NanInTheHalfColourOrAMissingHalfLayerIsRefused) {
    const Image clean = cleanImage(24, 20);
    FrameBuffers f = halvesFrame(clean, 0.05, Noise::Gaussian, 3);
    f.layer(Layer::HalfColor)(5, 3, 2) = std::nanf("");
    try {
        checkAutoInput(f, AutoEstimator::Auto, "in.exr");
        FAIL() << "no error";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::Numeric);
        EXPECT_EQ(e.where(), "pixel (5, 3), channel halfColor.B");
    }
    FrameBuffers g = halvesFrame(clean, 0.05, Noise::Gaussian, 3);
    g.remove(Layer::HalfSampleCount);
    try {
        checkAutoInput(g, AutoEstimator::Halves, "in.exr");
        FAIL() << "no error";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::Format);
        EXPECT_EQ(e.where(), "layer 'halfSampleCount'");
    }
}

TEST(Halves, SameResultForAnyThreadCountAndOneSidedDiffers) {
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
    o.symmetric = false;
    EXPECT_NE(autoComposite(bank, f, o).estimatedMse, one.estimatedMse);
}

TEST(Halves, AShortlistFiltersOnlyItsMembersOnBothHalvesAndChoosesAmongThem) {
    const Image clean = cleanImage(96, 64);
    const FrameBuffers f = halvesFrame(clean, 0.08, Noise::Skewed, 13);
    const FilterBank bank = gaussianBank(f, {0.3, 0.6, 1.0, 1.5, 2.5, 4.0});
    AutoOptions all, oneSided, two;
    all.shortlist = 0;
    oneSided.symmetric = false;
    two.shortlist = 2;
    const AutoResult full = autoComposite(bank, f, all);
    const AutoResult first = autoComposite(bank, f, oneSided);
    AutoResult one, twoThreads;
    {
        tbb::task_arena arena(1);
        arena.execute([&] { one = autoComposite(bank, f, two); });
    }
    {
        tbb::task_arena arena(2);
        arena.execute([&] { twoThreads = autoComposite(bank, f, two); });
    }
    // At most the two shortlisted members carry weight, and the best member is one of them.
    ASSERT_GE(one.layers.size(), 1u);
    ASSERT_LE(one.layers.size(), 2u);
    std::vector<int> listed;
    for (std::size_t m = 0; m < bank.size(); ++m) {
        // Shortlisted members have the symmetric estimate (up to float rounding of the two
        // sides' maps), the others keep their one-sided one.
        const double sym = full.estimatedMse[m], single = first.estimatedMse[m];
        if (std::abs(one.estimatedMse[m] - sym) <= 1e-5 * std::abs(sym) &&
            one.estimatedMse[m] != single)
            listed.push_back(int(m));
        else
            EXPECT_EQ(one.estimatedMse[m], single) << "member " << m;
    }
    EXPECT_EQ(listed.size(), 2u);
    for (const AutoLayer& layer : one.layers)
        EXPECT_NE(std::find(listed.begin(), listed.end(), layer.member), listed.end());
    EXPECT_NE(std::find(listed.begin(), listed.end(), one.bestMember), listed.end());
    // Deterministic for any thread count; a shortlist as large as the bank is the full form.
    for (std::size_t i = 0; i < one.composite.data().size(); ++i)
        ASSERT_EQ(one.composite.data()[i], twoThreads.composite.data()[i]);
    AutoOptions everyone;
    everyone.shortlist = int(bank.size());
    EXPECT_EQ(autoComposite(bank, f, everyone).estimatedMse, full.estimatedMse);
    AutoOptions bad;
    bad.shortlist = -1;
    EXPECT_THROW(autoComposite(bank, f, bad), Error);
}

TEST(Halves, TheSecantIsTheDefaultDisplaySpaceAndTheTangentCanBeAskedFor) {
    const Image clean = cleanImage(64, 48);
    const FrameBuffers f = halvesFrame(clean, 0.08, Noise::Skewed, 9);
    const FilterBank bank = gaussianBank(f, {0.5, 1.0, 2.0, 4.0});
    AutoOptions secant, tangent;
    secant.space = SureSpace::Display;
    tangent.space = SureSpace::DisplayTangent;
    const AutoResult byDefault = autoComposite(bank, f);
    EXPECT_EQ(autoComposite(bank, f, secant).estimatedMse, byDefault.estimatedMse);
    EXPECT_NE(autoComposite(bank, f, tangent).estimatedMse, byDefault.estimatedMse);
    for (SureSpace space : {SureSpace::Display, SureSpace::DisplayTangent, SureSpace::DisplayExact,
                            SureSpace::Linear})
        EXPECT_EQ(parseSureSpace(sureSpaceName(space)), space);
    EXPECT_THROW(parseSureSpace("gamma"), Error);
}

TEST(Halves, AFinerWindowKeepsASmallFeatureTheFullWindowSmoothsOver) {
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
    full.finer = 0;
    finer.finer = 2;
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
    EXPECT_EQ(autoDefaults(AutoEstimator::Halves).finer, 1);
    EXPECT_EQ(autoDefaults(AutoEstimator::Sure).finer, 0);
    for (int bad : {-1, 7}) {
        AutoOptions o;
        o.finer = bad;
        EXPECT_THROW(autoComposite(bank, f, o), Error) << bad;
    }
}

TEST(Halves, TheBankMedianIsTheMiddleValueOfEveryPixelAndChannel) {
    // A row of 37 pixels is 111 values, not a multiple of the 8 the network sorts at once; the
    // member counts include 1, even ones, odd ones and 70 (the default bank's).
    const Image clean = cleanImage(37, 9);
    const FrameBuffers f = halvesFrame(clean, 0.1, Noise::Skewed, 29);
    for (int n : {1, 2, 5, 8, 13, 70}) {
        std::vector<double> sigmas;
        for (int i = 0; i < n; ++i) sigmas.push_back(0.3 + 0.05 * i);
        const FilterBank bank = gaussianBank(f, sigmas);
        const Image median = bankMedian(bank);
        ASSERT_EQ(median.width(), 37);
        ASSERT_EQ(median.channels(), 3);
        for (std::size_t i = 0; i < median.data().size(); ++i) {
            std::vector<float> values;
            for (std::size_t m = 0; m < bank.size(); ++m)
                values.push_back(bank.result(m).data()[i]);
            std::nth_element(values.begin(), values.begin() + n / 2, values.end());
            ASSERT_EQ(median.data()[i], values[std::size_t(n / 2)]) << n << " members, value " << i;
        }
    }
    EXPECT_THROW(bankMedian(gaussianBank(f, {})), Error);
}

// The weight plane of `member` in an auto result (zero where the member has no layer).
Image planeOf(const AutoResult& r, int member) {
    for (const AutoLayer& l : r.layers)
        if (l.member == member) return l.weights;
    return Image(r.choice.width(), r.choice.height(), 1);
}

TEST(Halves, FeatheringBoxAveragesTheWeightsWhereNothingIsGated) {
    // With a gate no display difference reaches (display values lie in [0, 1]), every member's
    // feathered weights are its unfeathered weights box-averaged over the feather radius: they
    // already sum to 1, so the renormalisation changes them by float rounding only.
    const Image clean = cleanImage(96, 72);
    const FrameBuffers f = halvesFrame(clean, 0.08, Noise::Gaussian, 21);
    const FilterBank bank = gaussianBank(f, {0.4, 1.0, 3.0});
    AutoOptions plain, feathered;
    plain.feather = 0;
    feathered.feather = 3;
    feathered.featherGate = 10.0;
    plain.stack = feathered.stack = 0;  // the composite is then the blend of the weights
    const AutoResult a = autoComposite(bank, f, plain), b = autoComposite(bank, f, feathered);
    ASSERT_GE(a.layers.size(), 2u);
    long blended = 0, blendedBefore = 0;
    for (std::size_t m = 0; m < bank.size(); ++m) {
        const Image expected = boxSmooth(planeOf(a, int(m)), 3);
        const Image got = planeOf(b, int(m));
        for (std::size_t p = 0; p < got.data().size(); ++p) {
            ASSERT_NEAR(got.data()[p], expected.data()[p], 1e-5f) << "member " << m << " " << p;
            blended += got.data()[p] > 0.01f && got.data()[p] < 0.99f;
            const float before = planeOf(a, int(m)).data()[p];
            blendedBefore += before > 0.01f && before < 0.99f;
        }
    }
    // The choice now changes over a few pixels: more pixels blend members than before.
    EXPECT_GT(blended, blendedBefore);
    // The composite is the blend of the feathered weights.
    Image blend(96, 72, 3);
    for (const AutoLayer& l : b.layers)
        for (int y = 0; y < 72; ++y)
            for (int x = 0; x < 96; ++x)
                for (int c = 0; c < 3; ++c)
                    blend(x, y, c) +=
                        l.weights(x, y, 0) * bank.result(std::size_t(l.member))(x, y, c);
    for (std::size_t i = 0; i < blend.data().size(); ++i)
        ASSERT_NEAR(blend.data()[i], b.composite.data()[i], 1e-5f);
    // The halves feather by 5 pixels unless told otherwise (docs/auto.md, "Tuning"), SURE by 4.
    EXPECT_EQ(autoDefaults(AutoEstimator::Halves).feather, 5);
    EXPECT_EQ(autoDefaults(AutoEstimator::Sure).feather, 4);
    for (int bad : {-1, 33}) {
        AutoOptions o;
        o.feather = bad;
        EXPECT_THROW(autoComposite(bank, f, o), Error) << bad;
    }
    for (double bad : {0.0, -1.0, std::nan(""), HUGE_VAL}) {
        AutoOptions o;
        o.featherGate = bad;
        EXPECT_THROW(autoComposite(bank, f, o), Error) << bad;
    }
}

TEST(Halves, TheFeatherGateKeepsALightFromTheBlurChosenAroundIt) {
    // A small light (3×3 pixels of 20, far above the display's clamp) on a dark floor (0.05):
    // the wide Gaussian is right on the floor and turns the light into a saturated disc of
    // radius about 4; the narrow one keeps it. Feathering over 8 pixels without a gate spreads
    // the wide member's weight into the ring the narrow one wins around the light; the gate
    // (0.2 by default) keeps it out wherever it is that far from the unfeathered composite.
    // Fixed seed; measured without stacking, the display error within 8 pixels of the light:
    // unfeathered 3.61, gated 3.74, ungated 13.5. Asserted: gated at most 1.1× unfeathered,
    // under half ungated. (With the default stacking on top: 2.99, 3.44 and 9.13.)
    const int w = 96, h = 72;
    Image clean(w, h, 3, 0.05f);
    for (int y = 35; y < 38; ++y)
        for (int x = 47; x < 50; ++x)
            for (int c = 0; c < 3; ++c) clean(x, y, c) = 20.0f;
    const FrameBuffers f = halvesFrame(clean, 0.03, Noise::Gaussian, 23);
    const FilterBank bank = gaussianBank(f, {0.3, 3.0});
    AutoOptions plain, gated, ungated;
    plain.stack = gated.stack = ungated.stack = 0;  // the feathering alone
    plain.feather = 0;
    gated.feather = 8;
    ungated.feather = 8;
    ungated.featherGate = 10.0;
    auto nearError = [&](const AutoResult& r) {
        double s = 0.0;
        for (int y = 36 - 8; y <= 36 + 8; ++y)
            for (int x = 48 - 8; x <= 48 + 8; ++x)
                for (int c = 0; c < 3; ++c) {
                    const double d = srgbOf(r.composite(x, y, c)) - srgbOf(clean(x, y, c));
                    s += d * d;
                }
        return s;
    };
    const double e0 = nearError(autoComposite(bank, f, plain));
    const double eg = nearError(autoComposite(bank, f, gated));
    const double eu = nearError(autoComposite(bank, f, ungated));
    std::printf(
        "display squared error near the light: unfeathered %.4f, gated %.4f, "
        "ungated %.4f\n",
        e0, eg, eu);
    EXPECT_LE(eg, 1.1 * e0);
    EXPECT_LT(eg, 0.5 * eu);
}

// The stacking's inputs for one configuration: clean x (cleanImage + ½); halves A = x + n_A, B = x
// + n_B (Gaussian, sigma); the composite c = x + u (u a smooth error); one member whose result is
// x + k·u on all the samples and on each half (plus that half's noise, a tenth of it, as a
// filter leaves), and the composite's own results on the halves likewise.
struct StackCase {
    Image clean, composite, blendA, blendB, full, onA, onB, halfA, halfB;
};

StackCase stackCase(int w, int h, double k, double sigma, std::uint32_t seed, double offset = 0.0) {
    StackCase s;
    s.clean = cleanImage(w, h);
    for (float& v : s.clean.data()) v += 0.5f;  // positive, so that the clamp at 0 stays out
    for (Image* i :
         {&s.composite, &s.blendA, &s.blendB, &s.full, &s.onA, &s.onB, &s.halfA, &s.halfB})
        *i = Image(w, h, 3);
    std::mt19937 rng(seed);
    std::normal_distribution<double> gauss(0.0, sigma);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < 3; ++c) {
                const double v = s.clean(x, y, c);
                const double u = offset + 0.08 * std::sin(0.2 * x + 0.1 * c) * std::cos(0.15 * y);
                const double na = gauss(rng), nb = gauss(rng);
                s.halfA(x, y, c) = float(v + na);
                s.halfB(x, y, c) = float(v + nb);
                s.composite(x, y, c) = float(v + u);
                s.blendA(x, y, c) = float(v + u + 0.1 * na);
                s.blendB(x, y, c) = float(v + u + 0.1 * nb);
                s.full(x, y, c) = float(v + k * u);
                s.onA(x, y, c) = float(v + k * u + 0.1 * na);
                s.onB(x, y, c) = float(v + k * u + 0.1 * nb);
            }
    return s;
}

const double kFloor = AutoOptions{}.stackFloor;

Image stackOf(const StackCase& s, int radius, double ridge, int smooth = 0, double floor = kFloor) {
    return detail::stackComposite(s.composite, s.blendA, s.blendB, {{&s.full, &s.onA, &s.onB}},
                                  s.halfA, s.halfB, Image{}, radius, ridge, floor, smooth);
}

TEST(Halves, StackingFindsTheCombinationBetweenOrBeyondTheMembers) {
    // A member at x − u: the best is half-way (a = ½); at x + 2u: beyond the composite, away
    // from the member (a = −1). Either way the window's ridge regression of each half on the
    // other finds it, shrunk by the floor (0.1) to a/1.1 at most and a little more by the
    // noise's ridge (σ² = 4·10⁻⁴ per value against u² ≈ 1.6·10⁻³): the squared error falls to
    // (1 − 1/1.1)² ≈ 0.8 % at best; measured 1.4 % (member at x − u) and 3.6 % (at x + 2u,
    // which differs from the composite by u only, so the noise weighs more); asserted: below
    // 6 %.
    for (double k : {-1.0, 2.0}) {
        const StackCase s = stackCase(80, 60, k, 0.02, 21);
        const double before = glint::mse(s.composite, s.clean).value;
        const double after = glint::mse(stackOf(s, 8, 1.0), s.clean).value;
        std::printf("member at x + %gu: squared error %.3g, the composite's %.3g (%.1f %%)\n", k,
                    after, before, 100.0 * after / before);
        EXPECT_LT(after, 0.06 * before)
            << "member at x + " << k << "u: " << after << " against " << before;
        // An overwhelming ridge keeps the composite.
        const Image kept = stackOf(s, 8, 1e9);
        for (std::size_t i = 0; i < kept.data().size(); ++i)
            ASSERT_NEAR(kept.data()[i], s.composite.data()[i], 1e-5);
    }
}

// One member's stacking coefficient at (x, y): r / (G + ridge·v + floor·G) from window
// sums computed by brute force (double; truncated at the border).
double bruteCoefficient(const StackCase& s, int x, int y, int radius, double ridge) {
    const int w = s.composite.width(), h = s.composite.height();
    double g = 0.0, r = 0.0, v = 0.0;
    int n = 0;
    for (int yy = std::max(0, y - radius); yy <= std::min(h - 1, y + radius); ++yy)
        for (int xx = std::max(0, x - radius); xx <= std::min(w - 1, x + radius); ++xx, ++n)
            for (int c = 0; c < 3; ++c) {
                const double da = double(s.onA(xx, yy, c)) - s.blendA(xx, yy, c);
                const double db = double(s.onB(xx, yy, c)) - s.blendB(xx, yy, c);
                const double a = s.halfA(xx, yy, c), b = s.halfB(xx, yy, c);
                g += da * da + db * db;
                r += da * (b - s.blendA(xx, yy, c)) + db * (a - s.blendB(xx, yy, c));
                v += 0.5 * (a - b) * (a - b);
            }
    g /= n, r /= n, v /= n;
    return r / (g + ridge * v + kFloor * g);
}

// The stacking on 1 and on 2 threads, asserted bit-identical; returns it.
Image stackOnOneAndTwoThreads(const StackCase& s, int radius, double ridge, int smooth) {
    Image one, two;
    {
        tbb::task_arena arena(1);
        arena.execute([&] { one = stackOf(s, radius, ridge, smooth); });
    }
    {
        tbb::task_arena arena(2);
        arena.execute([&] { two = stackOf(s, radius, ridge, smooth); });
    }
    for (std::size_t i = 0; i < one.data().size(); ++i) EXPECT_EQ(one.data()[i], two.data()[i]);
    return one;
}

// Asserts that `out` at (x, y) is the composite corrected by coefficient a, clamped at 0.
void expectCorrected(const Image& out, const StackCase& s, int x, int y, double a) {
    for (int c = 0; c < 3; ++c) {
        const double base = s.composite(x, y, c);
        const double expected = std::max(0.0, base + a * (s.full(x, y, c) - base));
        ASSERT_NEAR(out(x, y, c), expected, 1e-5 * std::abs(expected) + 1e-7)
            << "at " << x << "," << y << " channel " << c;
    }
}

TEST(Halves, StackingIsTheWindowsRidgeSolutionAcrossTilesAndThreads) {
    // One member: a = r / (G + ridge·v + floor·G) with the window sums computed here by
    // brute force (double; truncated at the border). 150 rows: two tiles of rows (128 each).
    const int w = 23, h = 150, radius = 5;
    const double ridge = 0.7;
    const StackCase s = stackCase(w, h, -1.0, 0.1, 5);
    const Image one = stackOnOneAndTwoThreads(s, radius, ridge, 0);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            expectCorrected(one, s, x, y, bruteCoefficient(s, x, y, radius, ridge));
        }
}

TEST(Halves, SmoothedStackingAppliesTheCoefficientsAveragedOverTheWindowsAround) {
    // With smooth = 3, each pixel's coefficient is the box average over 7×7 pixels (truncated
    // at the border) of the brute-force coefficients fitted around each of them; the same for
    // 1 and 2 threads, across two tiles of rows.
    const int w = 21, h = 140, radius = 2, smooth = 3;
    const double ridge = 0.5;
    const StackCase s = stackCase(w, h, -1.0, 0.1, 8);
    const Image one = stackOnOneAndTwoThreads(s, radius, ridge, smooth);
    std::vector<double> fitted(std::size_t(w) * std::size_t(h));
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            fitted[std::size_t(y) * std::size_t(w) + std::size_t(x)] =
                bruteCoefficient(s, x, y, radius, ridge);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            double a = 0.0;
            int n = 0;
            for (int yy = std::max(0, y - smooth); yy <= std::min(h - 1, y + smooth); ++yy)
                for (int xx = std::max(0, x - smooth); xx <= std::min(w - 1, x + smooth); ++xx, ++n)
                    a += fitted[std::size_t(yy) * std::size_t(w) + std::size_t(xx)];
            expectCorrected(one, s, x, y, a / n);
        }
}

TEST(Halves, SmoothingTheStackingsCoefficientsLowersTheErrorOfSmallWindows) {
    // The composite's error u = 0.1 + 0.08·sin·cos never vanishes, so the best coefficient is
    // ½ everywhere (the member at x − u). Over 3×3 pixels of noisy halves (σ 0.3) and with only
    // the floor as ridge, each pixel's own fit follows the noise; averaged over the 9×9 fits
    // around it, far less. Measured: squared error 1.23·10⁻³ (own fits) against 0.21·10⁻³
    // (smoothed), the composite's 11.5·10⁻³; asserted: smoothed below half the own fits'.
    // With the noise's ridge as well (0.5, the default) the own fits are shrunk toward 0
    // instead, and smoothing gains less (printed, not asserted): it pays most where the ridge
    // is light (docs/auto.md, "Stacking").
    const StackCase s = stackCase(96, 80, -1.0, 0.3, 13, 0.1);
    const double before = glint::mse(s.composite, s.clean).value;
    const double own = glint::mse(stackOf(s, 1, 0.0, 0), s.clean).value;
    const double smoothed = glint::mse(stackOf(s, 1, 0.0, 4), s.clean).value;
    std::printf(
        "squared error: composite %.3g, own fits %.3g, smoothed %.3g; with ridge 0.5: "
        "own fits %.3g, smoothed %.3g\n",
        before, own, smoothed, glint::mse(stackOf(s, 1, 0.5, 0), s.clean).value,
        glint::mse(stackOf(s, 1, 0.5, 4), s.clean).value);
    EXPECT_LT(smoothed, 0.5 * own) << smoothed << " against " << own;
    EXPECT_LT(own, before);
}

TEST(Halves, StackingKeepsTheCompositeWhereNothingDiffersAndClampsAtZero) {
    // Halves without noise and members equal to the blend on them: the window's system is zero,
    // so every pixel keeps the composite, bit for bit, though the member's result on all the
    // samples differs from it.
    StackCase flat = stackCase(40, 30, 2.0, 0.0, 3);
    flat.onA = flat.blendA;
    flat.onB = flat.blendB;
    for (float& v : flat.full.data()) v += 1.0f;
    const Image kept = stackOf(flat, 4, 1.0);
    for (std::size_t i = 0; i < kept.data().size(); ++i)
        ASSERT_EQ(kept.data()[i], flat.composite.data()[i]);
    // The member at x + 2u gets a negative coefficient (near −1, from the halves); 3 more on
    // all the samples pushes c + a (f − c) below 0 wherever a < −0.3: clamped at 0, never
    // below.
    StackCase beyond = stackCase(40, 30, 2.0, 0.02, 3);
    for (float& v : beyond.full.data()) v += 3.0f;
    const Image clamped = stackOf(beyond, 4, 1.0);
    long zeros = 0;
    for (float v : clamped.data()) {
        ASSERT_GE(v, 0.0f);
        zeros += v == 0.0f;
    }
    EXPECT_GT(zeros, long(clamped.data().size() / 2)) << zeros;
}

TEST(Halves, StackingNeedsBothHalvesAndASessionCannotStartFromIt) {
    const Image clean = cleanImage(64, 48);
    const FrameBuffers f = halvesFrame(clean, 0.08, Noise::Gaussian, 17);
    const FilterBank bank = gaussianBank(f, {0.5, 1.0, 2.0, 4.0});
    AutoOptions o;
    o.stack = 3;
    o.stackWindow = 6;
    AutoOptions off;
    off.stack = 0;
    const AutoResult plain = autoComposite(bank, f, off);
    AutoResult one, two;
    {
        tbb::task_arena arena(1);
        arena.execute([&] { one = autoComposite(bank, f, o); });
    }
    {
        tbb::task_arena arena(2);
        arena.execute([&] { two = autoComposite(bank, f, o); });
    }
    EXPECT_EQ(plain.stacked, 0);
    EXPECT_EQ(one.stacked, 3);
    // The halves stack 6 members unless told otherwise (one-sided and SURE: none; docs/auto.md,
    // "Tuning").
    EXPECT_EQ(autoDefaults(AutoEstimator::Halves).stack, 6);
    EXPECT_EQ(autoDefaults(AutoEstimator::Sure).stack, 0);
    AutoOptions oneSided;
    oneSided.symmetric = false;
    EXPECT_EQ(autoComposite(bank, f, oneSided).stacked, 0);
    EXPECT_EQ(autoComposite(bank, f).stacked, 4);  // all four members have weight
    for (std::size_t i = 0; i < one.composite.data().size(); ++i) {
        ASSERT_EQ(one.composite.data()[i], two.composite.data()[i]);
        ASSERT_TRUE(std::isfinite(one.composite.data()[i]) && one.composite.data()[i] >= 0.0f);
    }
    // The blend it corrected is the plain one: same layers, a different composite.
    ASSERT_EQ(one.layers.size(), plain.layers.size());
    for (std::size_t l = 0; l < one.layers.size(); ++l) {
        EXPECT_EQ(one.layers[l].member, plain.layers[l].member);
        const auto& a = one.layers[l].weights.data();
        const auto& b = plain.layers[l].weights.data();
        EXPECT_TRUE(std::equal(a.begin(), a.end(), b.begin(), b.end()));
    }
    EXPECT_FALSE(std::equal(one.composite.data().begin(), one.composite.data().end(),
                            plain.composite.data().begin(), plain.composite.data().end()));
    // Not a blend of the members: a session refuses to start from it, and stays empty.
    Session session(f);
    EXPECT_THROW(startFromAuto(session, bank, one), Error);
    EXPECT_EQ(session.layerCount(), 0u);
    // SURE (no half buffers) and one-sided halves are refused, naming --stack.
    const FrameBuffers plainFrame = testing::syntheticFrame(24, 20, 0.05f);
    const FilterBank plainBank = gaussianBank(plainFrame, {1.0, 2.0});
    AutoOptions sided = o;
    sided.symmetric = false;
    for (const auto& [frame, b, opts] :
         {std::tuple{&plainFrame, &plainBank, o}, std::tuple{&f, &bank, sided}}) {
        try {
            autoComposite(*b, *frame, opts);
            FAIL() << "no error";
        } catch (const Error& e) {
            EXPECT_EQ(e.kind(), ErrorKind::InvalidArgument);
            EXPECT_EQ(e.where(), "--stack") << e.what();
        }
    }
    // Absurd values are refused, naming the option.
    AutoOptions bad;
    bad.stack = 17;
    EXPECT_THROW(validate(bad), Error);
    bad = {};
    bad.stackWindow = 0;
    EXPECT_THROW(validate(bad), Error);
    bad = {};
    bad.stackRidge = std::nan("");
    EXPECT_THROW(validate(bad), Error);
    bad = {};
    bad.stackRidge = -1.0;
    EXPECT_THROW(validate(bad), Error);
    for (int smooth : {-1, 65}) {
        bad = {};
        bad.stackSmooth = smooth;
        try {
            validate(bad);
            ADD_FAILURE() << "stack smooth " << smooth << " accepted";
        } catch (const Error& e) {
            EXPECT_EQ(e.where(), "--stack-smooth") << e.what();
        }
    }
}

// The stacking's feature regressors (docs/auto.md, "Stacking").
TEST(Halves, FeatureRegressorsAreTheBaseTimesTheFeaturesLocalDeviation) {
    // Every value against the formula with the window's mean computed here by brute force
    // (truncated at the border): the albedo's relative deviation per colour channel, each
    // normal axis's absolute one in every channel; a NaN feature counts as 0 in the means and
    // as no deviation where it is.
    const int w = 23, h = 17, radius = 3;
    std::mt19937 rng(31);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    Image base(w, h, 3), albedo(w, h, 3), normal(w, h, 3);
    for (float& v : base.data()) v = float(0.1 + u(rng));
    for (float& v : albedo.data()) v = float(u(rng));
    for (float& v : normal.data()) v = float(2.0 * u(rng) - 1.0);
    albedo(5, 6, 1) = std::nanf("");
    const std::vector<Image> out = detail::featureRegressors(base, &albedo, &normal, radius);
    ASSERT_EQ(out.size(), 4u);
    const auto mean = [&](const Image& f, int x, int y, int c) {
        double sum = 0.0;
        int n = 0;
        for (int yy = std::max(0, y - radius); yy <= std::min(h - 1, y + radius); ++yy)
            for (int xx = std::max(0, x - radius); xx <= std::min(w - 1, x + radius); ++xx, ++n)
                sum += std::isfinite(f(xx, yy, c)) ? f(xx, yy, c) : 0.0f;
        return sum / n;
    };
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < 3; ++c) {
                const double b = base(x, y, c);
                double delta = (albedo(x, y, c) - mean(albedo, x, y, c)) /
                               (std::abs(mean(albedo, x, y, c)) + detail::kStackAlbedoFloor);
                if (!std::isfinite(delta)) delta = 0.0;
                ASSERT_NEAR(out[0](x, y, c), b * (1.0 + delta), 1e-5 * (1.0 + std::abs(b * delta)))
                    << "albedo at " << x << "," << y << " channel " << c;
                for (int axis = 0; axis < 3; ++axis)
                    ASSERT_NEAR(out[std::size_t(1 + axis)](x, y, c),
                                b * (1.0 + normal(x, y, axis) - mean(normal, x, y, axis)), 1e-5)
                        << "normal " << axis << " at " << x << "," << y << " channel " << c;
            }
    EXPECT_EQ(out[0](5, 6, 1), base(5, 6, 1));  // the NaN: no deviation
    EXPECT_EQ(detail::featureRegressors(base, nullptr, &normal, radius).size(), 3u);
    EXPECT_EQ(detail::featureRegressors(base, &albedo, nullptr, radius).size(), 1u);
    EXPECT_TRUE(detail::featureRegressors(base, nullptr, nullptr, radius).empty());
}

// The mean of an image over (2·radius + 1)² pixels, truncated at the border (brute force).
Image boxBlurred(const Image& image, int radius) {
    const int w = image.width(), h = image.height();
    Image out(w, h, image.channels());
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < image.channels(); ++c) {
                double sum = 0.0;
                int n = 0;
                for (int yy = std::max(0, y - radius); yy <= std::min(h - 1, y + radius); ++yy)
                    for (int xx = std::max(0, x - radius); xx <= std::min(w - 1, x + radius);
                         ++xx, ++n)
                        sum += image(xx, yy, c);
                out(x, y, c) = float(sum / n);
            }
    return out;
}

TEST(Halves, StackingOnTheAlbedoPutsBackTheEdgesTheBlendSmoothsOver) {
    // Clean x = albedo · shading, with albedo stripes (0.2 and 0.8, 8 pixels wide) and smooth
    // shading; halves x + n (σ 0.05). The blend is x box-blurred over 5×5 (on each half: the
    // half blurred), the one member over 9×9: every combination of the two still blurs the
    // stripes' edges. With the albedo's regressor (noise-free, as on a scene without depth of
    // field or motion blur) the fit puts the edges back: the squared error falls below a
    // quarter of the members-only stacking's (measured: 0.08 of it, 0.07 of the blend's).
    const int w = 64, h = 48;
    Image albedo(w, h, 3), clean(w, h, 3), halfA(w, h, 3), halfB(w, h, 3);
    std::mt19937 rng(41);
    std::normal_distribution<double> noise(0.0, 0.05);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < 3; ++c) {
                const double a = (x / 8) % 2 ? 0.8 : 0.2;
                const double shading =
                    0.6 + 0.3 * std::sin(0.05 * x + 0.1 * c) * std::cos(0.07 * y);
                albedo(x, y, c) = float(a);
                clean(x, y, c) = float(a * shading);
                halfA(x, y, c) = float(a * shading + noise(rng));
                halfB(x, y, c) = float(a * shading + noise(rng));
            }
    Image full(w, h, 3);
    for (std::size_t i = 0; i < full.data().size(); ++i)
        full.data()[i] = 0.5f * (halfA.data()[i] + halfB.data()[i]);
    const Image composite = boxBlurred(full, 2), blendA = boxBlurred(halfA, 2),
                blendB = boxBlurred(halfB, 2);
    const Image memberFull = boxBlurred(full, 4), memberA = boxBlurred(halfA, 4),
                memberB = boxBlurred(halfB, 4);
    const AutoOptions o;
    std::vector<detail::StackMember> members{{&memberFull, &memberA, &memberB}};
    const auto stackWith = [&](const std::vector<detail::StackMember>& m) {
        return detail::stackComposite(composite, blendA, blendB, m, halfA, halfB, Image{},
                                      o.stackWindow, o.stackRidge, o.stackFloor, o.stackSmooth);
    };
    const double blended = glint::mse(composite, clean).value;
    const double membersOnly = glint::mse(stackWith(members), clean).value;
    const std::vector<Image> onFull =
        detail::featureRegressors(composite, &albedo, nullptr, o.stackFeatureWindow);
    const std::vector<Image> onA =
        detail::featureRegressors(blendA, &albedo, nullptr, o.stackFeatureWindow);
    const std::vector<Image> onB =
        detail::featureRegressors(blendB, &albedo, nullptr, o.stackFeatureWindow);
    members.push_back({&onFull[0], &onA[0], &onB[0]});
    const double withAlbedo = glint::mse(stackWith(members), clean).value;
    std::printf("squared error: blend %.3g, stacked on the members %.3g, and on the albedo %.3g\n",
                blended, membersOnly, withAlbedo);
    EXPECT_LT(membersOnly, blended);
    EXPECT_LT(withAlbedo, 0.25 * membersOnly) << withAlbedo << " against " << membersOnly;
}

// A halves frame (halvesFrame) with albedo and normal layers and their halves (the same in
// both: noise-free features).
FrameBuffers withFeatures(FrameBuffers f) {
    Image albedo(f.width(), f.height(), 3), normal(f.width(), f.height(), 3);
    for (int y = 0; y < f.height(); ++y)
        for (int x = 0; x < f.width(); ++x)
            for (int c = 0; c < 3; ++c) {
                albedo(x, y, c) = (x / 6) % 2 ? 0.7f : 0.3f;
                normal(x, y, c) = c == 2 ? 1.0f : float(0.2 * std::sin(0.3 * (x + y)));
            }
    f.set(Layer::Albedo, albedo);
    f.set(Layer::HalfAlbedo, albedo);
    f.set(Layer::Normal, normal);
    f.set(Layer::HalfNormal, normal);
    return f;
}

TEST(Halves, TheStackingTakesTheFeaturesTheInputHasAndNamesOneAskedForThatIsMissing) {
    const Image clean = cleanImage(64, 48);
    const FrameBuffers bare = halvesFrame(clean, 0.08, Noise::Gaussian, 17);
    const FrameBuffers f = withFeatures(bare);
    const FilterBank bank = gaussianBank(f, {0.5, 1.0, 2.0, 4.0});
    const FilterBank bareBank = gaussianBank(bare, {0.5, 1.0, 2.0, 4.0});
    // Unset: the features the input has (the albedo's 1 regressor, the normal's 3).
    AutoResult one, two;
    {
        tbb::task_arena arena(1);
        arena.execute([&] { one = autoComposite(bank, f); });
    }
    {
        tbb::task_arena arena(2);
        arena.execute([&] { two = autoComposite(bank, f); });
    }
    EXPECT_EQ(one.stackFeatures, 4);
    EXPECT_EQ(one.stacked, 4);  // the members: all four have weight
    for (std::size_t i = 0; i < one.composite.data().size(); ++i)
        ASSERT_EQ(one.composite.data()[i], two.composite.data()[i]);
    EXPECT_EQ(autoComposite(bareBank, bare).stackFeatures, 0);
    AutoOptions o;
    o.stackNormal = false;
    EXPECT_EQ(autoComposite(bank, f, o).stackFeatures, 1);
    o.stackAlbedo = false;
    const AutoResult none = autoComposite(bank, f, o);
    EXPECT_EQ(none.stackFeatures, 0);
    EXPECT_FALSE(std::equal(none.composite.data().begin(), none.composite.data().end(),
                            one.composite.data().begin(), one.composite.data().end()));
    // Without the stacking, no features either.
    AutoOptions off;
    off.stack = 0;
    EXPECT_EQ(autoComposite(bank, f, off).stackFeatures, 0);
    // Asked for but missing: the layer is named.
    for (Layer missing : {Layer::Albedo, Layer::HalfNormal}) {
        FrameBuffers g = f;
        g.remove(missing);
        if (missing == Layer::Albedo) g.remove(Layer::HalfAlbedo);
        const FilterBank gBank = gaussianBank(g, {1.0, 2.0});
        AutoOptions asked;
        asked.stackAlbedo = asked.stackNormal = true;
        try {
            autoComposite(gBank, g, asked);
            ADD_FAILURE() << "no error without " << layerDisplayName(missing);
        } catch (const Error& e) {
            EXPECT_EQ(e.kind(), ErrorKind::Format);
            EXPECT_EQ(e.where(), "layer '" + std::string(layerDisplayName(missing)) + "'")
                << e.what();
        }
    }
    // Absurd windows are refused, naming the option.
    for (int window : {0, 65}) {
        AutoOptions bad;
        bad.stackFeatureWindow = window;
        try {
            validate(bad);
            ADD_FAILURE() << "stack feature window " << window << " accepted";
        } catch (const Error& e) {
            EXPECT_EQ(e.where(), "--stack-feature-window") << e.what();
        }
    }
}

}  // namespace
}  // namespace glint::denoise

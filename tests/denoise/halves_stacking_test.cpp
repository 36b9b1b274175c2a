// The automatic selection's stacking (docs/auto.md, "Stacking"): the regression on synthetic
// cases whose solution is known, and the stage within autoComposite.
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

const double kFloor = autoTuningDefaults(AutoEstimator::Halves).at("stackFloor");

Image stackOf(const StackCase& s, int radius, double ridge, int smooth = 0, double floor = kFloor) {
    return detail::stackComposite(s.composite, s.blendA, s.blendB, {{&s.full, &s.onA, &s.onB}},
                                  s.halfA, s.halfB, Image{}, radius, ridge, floor, smooth);
}

TEST(AutoStacking, StackingFindsTheCombinationBetweenOrBeyondTheMembers) {
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

TEST(AutoStacking, StackingIsTheWindowsRidgeSolutionAcrossTilesAndThreads) {
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

TEST(AutoStacking, SmoothedStackingAppliesTheCoefficientsAveragedOverTheWindowsAround) {
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

TEST(AutoStacking, SmoothingTheStackingsCoefficientsLowersTheErrorOfSmallWindows) {
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

TEST(AutoStacking, StackingKeepsTheCompositeWhereNothingDiffersAndClampsAtZero) {
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

TEST(AutoStacking, ACorrectionThatMovesADisplayValueByMoreThanTheGateIsNotApplied) {
    // A dark composite (0.005) and one member that the halves endorse everywhere (both halves and
    // its results on them are its result): the fit gives it a ≈ 1/1.1 (the floor). Its result is
    // 0.005 plus 2 in one 3 × 3 block (a light smoothed into its dark neighbours) and plus 0.01
    // in another. With the gate at 0.2 (auto passes the feather gate) the block of 2, a display
    // move of about 0.9, keeps the composite bit for bit; the block of 0.01 (a move of about
    // 0.07) is corrected as without the gate. (The composite is positive: a gated pixel keeps
    // it clamped at 0.)
    const int w = 24, h = 16;
    Image c(w, h, 3, 0.005f), f(w, h, 3, 0.005f);
    for (int y = 6; y < 9; ++y)
        for (int x = 4; x < 7; ++x)
            for (int ch = 0; ch < 3; ++ch) {
                f(x, y, ch) += 2.0f;
                f(x + 12, y, ch) += 0.01f;
            }
    const auto stacked = [&](double gate) {
        return detail::stackComposite(c, c, c, {{&f, &f, &f}}, f, f, Image{}, 2, 0.5, kFloor, 0,
                                      nullptr, detail::StackGate{gate, 0.0f});
    };
    const Image open = stacked(0.0), gated = stacked(0.2);
    EXPECT_GT(open(5, 7, 0), 1.0f);
    EXPECT_EQ(gated(5, 7, 0), c(5, 7, 0));
    EXPECT_GT(open(17, 7, 0), 0.012f);
    EXPECT_EQ(gated(17, 7, 0), open(17, 7, 0));
    // Every pixel either keeps the composite or is the ungated correction.
    for (std::size_t i = 0; i < gated.data().size(); ++i)
        ASSERT_TRUE(gated.data()[i] == c.data()[i] || gated.data()[i] == open.data()[i]) << i;
}

TEST(AutoStacking, ACorrectionPastTheRendersNoiseWhereTheCompositeAgreesWithItIsNotApplied) {
    // A composite of 0.005 and one member at 0.015, which the halves endorse (both halves and its
    // results on them are its result) except at two pixels where both halves are the composite:
    // the windows around them still fit a ≈ 1/1.1, so the correction moves them by about 0.009
    // (a model fitted in another part of its windows). With the noise gate at 3 standard errors:
    //  - (4, 8), σ = 0.001 (variance 1e-6): the move is past 3σ and the composite agrees with
    //    the render's mean there, so it keeps the composite, bit for bit;
    //  - (12, 8), σ = 0.01: the move is within 3σ, so it is corrected as without the gate;
    //  - everywhere else the render's mean is the member's 0.015: the composite is 0.01 from it,
    //    farther than the move, so every pixel is corrected as without the gate.
    const int w = 24, h = 16;
    Image c(w, h, 3, 0.005f), f(w, h, 3, 0.015f), a = f, b = f, variance(w, h, 3, 1e-6f);
    for (int ch = 0; ch < 3; ++ch) {
        a(4, 8, ch) = b(4, 8, ch) = c(4, 8, ch);
        a(12, 8, ch) = b(12, 8, ch) = c(12, 8, ch);
        variance(12, 8, ch) = 1e-4f;
    }
    const auto stacked = [&](double sigmas, const Image* var, const Image& halfA,
                             const Image& halfB) {
        return detail::stackComposite(c, c, c, {{&f, &halfA, &halfB}}, halfA, halfB, Image{}, 2,
                                      0.5, kFloor, 0, nullptr,
                                      detail::StackGate{0.0, 0.0f, sigmas, var});
    };
    const Image open = stacked(0.0, &variance, a, b), gated = stacked(3.0, &variance, a, b);
    EXPECT_GT(open(4, 8, 0), 0.011f);
    EXPECT_GT(open(12, 8, 0), 0.011f);
    EXPECT_EQ(gated(4, 8, 0), c(4, 8, 0));
    for (std::size_t i = 0; i < gated.data().size(); ++i)
        if (i / 3 != std::size_t(8 * w + 4)) {
            ASSERT_EQ(gated.data()[i], open.data()[i]) << i;
        }
    // Without the variance the standard error is |A − B| / 2: at (4, 8) 0, so the move is past
    // it; at (12, 8) halves of 0.005 ± 0.01 (the same mean) give 0.01, so the move is within 3σ.
    Image a2 = a, b2 = b;
    for (int ch = 0; ch < 3; ++ch) a2(12, 8, ch) += 0.01f, b2(12, 8, ch) -= 0.01f;
    const Image open2 = stacked(0.0, nullptr, a2, b2), gated2 = stacked(3.0, nullptr, a2, b2);
    EXPECT_GT(open2(4, 8, 0), 0.011f);
    EXPECT_EQ(gated2(4, 8, 0), c(4, 8, 0));
    EXPECT_GT(open2(12, 8, 0), 0.011f);
    EXPECT_EQ(gated2(12, 8, 0), open2(12, 8, 0));
}

TEST(AutoStacking, StackingNeedsBothHalvesAndASessionStartsFromItWithItsCorrection) {
    const Image clean = cleanImage(64, 48);
    const FrameBuffers f = halvesFrame(clean, 0.08, Noise::Gaussian, 17);
    const FilterBank bank = gaussianBank(f, {0.5, 1.0, 2.0, 4.0});
    AutoOptions o;
    o.tuning["stack"] = 3;
    o.tuning["stackWindow"] = 6;
    AutoOptions off;
    off.tuning["stack"] = 0;
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
    EXPECT_EQ(autoTuningDefaults(AutoEstimator::Halves).at("stack"), 6);
    EXPECT_EQ(autoTuningDefaults(AutoEstimator::Sure).at("stack"), 0);
    AutoOptions oneSided;
    oneSided.tuning["oneSided"] = 1;
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
    // Not a blend of the members: a session starts from it with the members as layers and auto's
    // correction on top, and is the stacked composite bit for bit; every edit can be undone.
    Session session(f);
    const std::size_t edits = startFromAuto(session, bank, one);
    ASSERT_EQ(session.layerCount(), one.layers.size() + 1);
    EXPECT_EQ(edits, 2 * session.layerCount());
    const SessionLayer& correction = session.layer(one.layers.size());
    ASSERT_TRUE(correction.correction);
    EXPECT_EQ(correction.filter, kAutoCorrection);
    EXPECT_TRUE(std::equal(session.composite().data().begin(), session.composite().data().end(),
                           one.composite.data().begin(), one.composite.data().end()));
    for (std::size_t i = 0; i < edits; ++i) session.undo();
    EXPECT_EQ(session.layerCount(), 0u);
    EXPECT_TRUE(std::equal(session.composite().data().begin(), session.composite().data().end(),
                           f.color().data().begin(), f.color().data().end()));
    // SURE (no half buffers) and one-sided halves are refused, naming --stack.
    const FrameBuffers plainFrame = testing::syntheticFrame(24, 20, 0.05f);
    const FilterBank plainBank = gaussianBank(plainFrame, {1.0, 2.0});
    AutoOptions sided = o;
    sided.tuning["oneSided"] = 1;
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
    bad.tuning["stack"] = 17;
    EXPECT_THROW(validate(bad), Error);
    bad = {};
    bad.tuning["stackWindow"] = 0;
    EXPECT_THROW(validate(bad), Error);
    bad = {};
    bad.tuning["stackRidge"] = std::nan("");
    EXPECT_THROW(validate(bad), Error);
    bad = {};
    bad.tuning["stackRidge"] = -1.0;
    EXPECT_THROW(validate(bad), Error);
    for (int smooth : {-1, 65}) {
        bad = {};
        bad.tuning["stackSmooth"] = smooth;
        try {
            validate(bad);
            ADD_FAILURE() << "stack smooth " << smooth << " accepted";
        } catch (const Error& e) {
            EXPECT_EQ(e.where(), "--stack-smooth") << e.what();
        }
    }
}

// The stacking's feature regressors (docs/auto.md, "Stacking").
TEST(AutoStacking, FeatureRegressorsAreTheBaseTimesTheFeaturesLocalDeviation) {
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

// featureRegressorStrips gives featureRegressors' values, value for value, strip after strip of
// any height, in row order: the pipeline writes each strip to its spill and never holds the
// regressors over the frame (issue 47: 1 GB at 4K with their box sums).
TEST(AutoStacking, FeatureRegressorsStripByStripAreTheWholeFramesValues) {
    const int w = 19, h = 41, radius = 3;
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    Image base(w, h, 3), albedo(w, h, 3), normal(w, h, 3);
    for (float& v : base.data()) v = float(0.1 + u(rng));
    for (float& v : albedo.data()) v = float(u(rng));
    for (float& v : normal.data()) v = float(2.0 * u(rng) - 1.0);
    albedo(4, 30, 2) = std::nanf("");
    const std::vector<Image> whole = detail::featureRegressors(base, &albedo, &normal, radius);
    for (int rows : {1, 7, 41, 64}) {
        SCOPED_TRACE("strips of " + std::to_string(rows) + " rows");
        std::vector<Image> got(whole.size(), Image(w, h, 3, -1.0f));
        int next = 0;
        detail::featureRegressorStrips(base, &albedo, &normal, radius, rows,
                                       [&](int y0, std::vector<Image>& strip) {
                                           EXPECT_EQ(y0, next);
                                           ASSERT_EQ(strip.size(), whole.size());
                                           EXPECT_LE(strip[0].height(), rows);
                                           for (std::size_t q = 0; q < strip.size(); ++q)
                                               for (int y = 0; y < strip[q].height(); ++y)
                                                   for (int x = 0; x < w; ++x)
                                                       for (int c = 0; c < 3; ++c)
                                                           got[q](x, y0 + y, c) = strip[q](x, y, c);
                                           next = y0 + strip[0].height();
                                       });
        EXPECT_EQ(next, h);
        for (std::size_t q = 0; q < whole.size(); ++q)
            for (std::size_t i = 0; i < whole[q].data().size(); ++i)
                ASSERT_EQ(got[q].data()[i], whole[q].data()[i]) << "regressor " << q << " at " << i;
    }
}

// With smoothing, the coefficients are averaged behind the regression, tile after tile: the
// results on all the samples are loaded for the rows it has passed before the regression loads
// its last tile, each row once and in order, so that the coefficients over the whole region
// are never held (issue 47: 330 MB at 4K). The floats are the stacking's over held images.
TEST(AutoStacking, TheSmoothingRunsBehindTheRegressionReadingEachRowOnce) {
    const int w = 9, h = 300, radius = 2, smooth = 3;  // three tiles of rows
    const double ridge = 0.5;
    const StackCase s = stackCase(w, h, -1.0, 0.1, 12);
    struct Load {
        int y0, y1;
        bool full, halves;
    };
    std::vector<Load> loads;
    const detail::LoadStackRows load = [&](int y0, int y1, bool full, bool halves,
                                           detail::StackRows& rows) {
        loads.push_back({y0, y1, full, halves});
        const Rect rect{0, w, y0, y1};
        rows = detail::StackRows{};
        if (full) rows.full.push_back(s.full.crop(rect));
        if (halves) rows.onA.push_back(s.onA.crop(rect)), rows.onB.push_back(s.onB.crop(rect));
    };
    const Image byRows = detail::stackComposite(s.composite, s.blendA, s.blendB, 1, load, s.halfA,
                                                s.halfB, Image{}, radius, ridge, kFloor, smooth);
    const Image held = stackOf(s, radius, ridge, smooth);
    for (std::size_t i = 0; i < held.data().size(); ++i)
        ASSERT_EQ(byRows.data()[i], held.data()[i]) << i;
    int next = 0;
    std::size_t firstFull = loads.size(), lastHalves = 0;
    for (std::size_t i = 0; i < loads.size(); ++i) {
        if (loads[i].halves) lastHalves = i;
        if (!loads[i].full) continue;
        firstFull = std::min(firstFull, i);
        EXPECT_EQ(loads[i].y0, next);
        next = loads[i].y1;
    }
    EXPECT_EQ(next, h);
    EXPECT_LT(firstFull, lastHalves);
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

TEST(AutoStacking, StackingOnTheAlbedoPutsBackTheEdgesTheBlendSmoothsOver) {
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
    const ParamValues o = autoTuningDefaults(AutoEstimator::Halves);
    const int window = int(o.at("stackWindow")), smooth = int(o.at("stackSmooth")),
              featureWindow = int(o.at("stackFeatureWindow"));
    std::vector<detail::StackMember> members{{&memberFull, &memberA, &memberB}};
    const auto stackWith = [&](const std::vector<detail::StackMember>& m) {
        return detail::stackComposite(composite, blendA, blendB, m, halfA, halfB, Image{}, window,
                                      o.at("stackRidge"), o.at("stackFloor"), smooth);
    };
    const double blended = glint::mse(composite, clean).value;
    const double membersOnly = glint::mse(stackWith(members), clean).value;
    const std::vector<Image> onFull =
        detail::featureRegressors(composite, &albedo, nullptr, featureWindow);
    const std::vector<Image> onA =
        detail::featureRegressors(blendA, &albedo, nullptr, featureWindow);
    const std::vector<Image> onB =
        detail::featureRegressors(blendB, &albedo, nullptr, featureWindow);
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

TEST(AutoStacking, TheStackingTakesTheFeaturesTheInputHasAndNamesOneAskedForThatIsMissing) {
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
    o.tuning["stackNormal"] = 2;  // off
    EXPECT_EQ(autoComposite(bank, f, o).stackFeatures, 1);
    o.tuning["stackAlbedo"] = 2;  // off
    const AutoResult none = autoComposite(bank, f, o);
    EXPECT_EQ(none.stackFeatures, 0);
    EXPECT_FALSE(std::equal(none.composite.data().begin(), none.composite.data().end(),
                            one.composite.data().begin(), one.composite.data().end()));
    // Without the stacking, no features either.
    AutoOptions off;
    off.tuning["stack"] = 0;
    EXPECT_EQ(autoComposite(bank, f, off).stackFeatures, 0);
    // Asked for but missing: the layer is named.
    for (Layer missing : {Layer::Albedo, Layer::HalfNormal}) {
        FrameBuffers g = f;
        g.remove(missing);
        if (missing == Layer::Albedo) g.remove(Layer::HalfAlbedo);
        const FilterBank gBank = gaussianBank(g, {1.0, 2.0});
        AutoOptions asked;
        asked.tuning["stackAlbedo"] = asked.tuning["stackNormal"] = 1;  // on
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
        bad.tuning["stackFeatureWindow"] = window;
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

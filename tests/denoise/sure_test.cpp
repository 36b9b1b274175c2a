// Per-pixel SURE, Monte-Carlo divergence and the auto composite (sure.h) on synthetic images with
// Gaussian noise of known per-pixel variance.
#include "glint/denoise/auto.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <cmath>
#include <limits>
#include <random>

#include "auto/choice.h"
#include "auto/sure_estimator.h"
#include "glint/denoise/bank.h"
#include "glint/denoise/registry.h"
#include "glint/denoise/session.h"
#include "glint/image/error.h"
#include "glint/image/metrics.h"
#include "synthetic_frames.h"

namespace glint::denoise {
namespace {

// A clean image: smooth shading with a sharp disc and, for x >= w/2 when `texture`, a fine
// checkerboard (where only a tiny blur is right).
Image cleanImage(int w, int h, bool texture) {
    Image x(w, h, 3);
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) {
            const double dx = i - 0.3 * w, dy = j - 0.5 * h;
            const bool disc = dx * dx + dy * dy < 0.04 * w * w;
            double v =
                0.3 + 0.2 * std::sin(6.0 * i / w) * std::cos(4.0 * j / h) + (disc ? 0.3 : 0.0);
            if (texture && i >= w / 2) v += ((i / 2 + j / 2) % 2 ? 0.25 : -0.25);
            x(i, j, 0) = float(v);
            x(i, j, 1) = float(0.8 * v + 0.05);
            x(i, j, 2) = float(0.6 * v + 0.1);
        }
    return x;
}

// A frame y = x + n with n ~ N(0, σ²(p)), σ varying smoothly over the image from sigmaLo to
// sigmaHi (known, written as the variance layer). Fixed seed.
FrameBuffers noisyFrame(const Image& clean, double sigmaLo, double sigmaHi, std::uint32_t seed) {
    const int w = clean.width(), h = clean.height();
    FrameBuffers f(w, h);
    std::mt19937 rng(seed);
    std::normal_distribution<double> n01(0.0, 1.0);
    Image& y = f.color();
    Image& var = f.ensure(Layer::Variance);
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) {
            const double sigma = sigmaLo + (sigmaHi - sigmaLo) * double(j) / double(h - 1);
            for (int c = 0; c < 3; ++c) {
                y(i, j, c) = float(clean(i, j, c) + sigma * n01(rng));
                var(i, j, c) = float(sigma * sigma);
            }
        }
    return f;
}

double meanOf(const Image& im) {
    double s = 0.0;
    for (float v : im.data()) s += v;
    return s / double(im.data().size());
}

// Per-channel mean of a SURE map (summed over RGB).
double sureMse(const Image& sure) {
    return meanOf(sure) / 3.0;
}

// Per-channel mean of (f − y)² − σ²: SURE without its divergence term.
double naiveMse(const FrameBuffers& f, const Image& out) {
    double s = 0.0;
    const Image& var = f.layer(Layer::Variance);
    for (std::size_t i = 0; i < out.data().size(); ++i) {
        const double d = double(out.data()[i]) - double(f.color().data()[i]);
        s += d * d - double(var.data()[i]);
    }
    return s / double(out.data().size());
}

// Tolerance of the SURE tests. On N values with noise variance σ̄² (mean over the image), SURE's
// error (f − y)² − σ² − (f − x)² + ... has a standard deviation of about σ̄² sqrt(2 / N) plus the
// Monte-Carlo divergence's; for N = 3·128·128 that is 0.0064 σ̄². We allow 0.04 σ̄² (> 5 standard
// deviations), while leaving out the divergence term is off by 2 σ̄² · mean centre weight
// (≈ 0.14 σ̄² for σ = 1.5), so a wrong divergence fails.
constexpr double kSureTolerance = 0.04;

TEST(Sure, MonteCarloEstimateOfAGaussiansMseMatchesTheTrueMse) {
    const Image clean = cleanImage(128, 128, false);
    const FrameBuffers f = noisyFrame(clean, 0.03, 0.1, 11);
    const double meanVar = meanOf(f.layer(Layer::Variance));
    const Filter& gaussian = findFilter("gaussian");
    for (double sigma : {0.8, 1.5, 3.0}) {
        detail::SureOptions o;
        o.analyticDivergence = false;
        const detail::SureEstimate e = detail::estimateSure(gaussian, f, {{"sigma", sigma}}, o);
        EXPECT_FALSE(e.analytic);
        const double truth = glint::mse(e.output, clean).value;
        const double estimate = sureMse(e.sure);
        EXPECT_NEAR(estimate, truth, kSureTolerance * meanVar)
            << "sigma " << sigma << ": SURE " << estimate << ", true MSE " << truth;
        // Without the divergence the estimate is off by far more than the tolerance (2 σ̄² times
        // the centre weight 1/(2π sigma²): 0.50 σ̄² at sigma 0.8, 0.14 σ̄² at 1.5).
        if (sigma < 2.0) {
            EXPECT_GT(std::fabs(naiveMse(f, e.output) - truth), 2.0 * kSureTolerance * meanVar);
        }
    }
}

TEST(Sure, MonteCarloEstimateOfNonlinearFiltersMseMatchesTheTrueMse) {
    const Image clean = cleanImage(128, 128, true);
    const FrameBuffers f = noisyFrame(clean, 0.03, 0.1, 12);
    const double meanVar = meanOf(f.layer(Layer::Variance));
    struct Case {
        const char* filter;
        ParamValues params;
    };
    const Case cases[] = {{"bilateral", {{"sigmaS", 2.0}, {"sigmaR", 0.15}}},
                          {"nlmeans", {{"strength", 0.6}}}};
    for (const Case& c : cases)
        for (double epsilon : {0.003, 0.01, 0.1}) {
            detail::SureOptions o;
            o.epsilon = epsilon;
            const detail::SureEstimate e =
                detail::estimateSure(findFilter(c.filter), f, c.params, o);
            const double truth = glint::mse(e.output, clean).value;
            EXPECT_NEAR(sureMse(e.sure), truth, kSureTolerance * meanVar)
                << c.filter << " epsilon " << epsilon << ": SURE " << sureMse(e.sure)
                << ", true MSE " << truth;
        }
}

TEST(Sure, MonteCarloEstimateOfTheLearnedFiltersMseMatchesTheTrueMse) {
    // unet (OIDN's network, a black box to SURE: no divergence of its own) on the same kind of
    // frame, colour alone; its divergence by Monte Carlo from one more run on the perturbed input.
    const Image clean = cleanImage(128, 128, true);
    const FrameBuffers f = noisyFrame(clean, 0.03, 0.1, 14);
    const double meanVar = meanOf(f.layer(Layer::Variance));
    for (double epsilon : {0.01, 0.1}) {
        detail::SureOptions o;
        o.epsilon = epsilon;
        const detail::SureEstimate e = detail::estimateSure(findFilter("unet"), f, {}, o);
        EXPECT_FALSE(e.analytic);
        const double truth = glint::mse(e.output, clean).value;
        EXPECT_NEAR(sureMse(e.sure), truth, kSureTolerance * meanVar)
            << "epsilon " << epsilon << ": SURE " << sureMse(e.sure) << ", true MSE " << truth;
        // Without the divergence it would be far off.
        EXPECT_GT(std::fabs(naiveMse(f, e.output) - truth), 2.0 * kSureTolerance * meanVar);
    }
}

TEST(Sure, AnalyticDivergenceOfTheGaussianMatchesMonteCarlo) {
    const Image clean = cleanImage(96, 96, false);
    const FrameBuffers f = noisyFrame(clean, 0.05, 0.05, 13);
    const Filter& gaussian = findFilter("gaussian");
    const ParamValues p{{"sigma", 1.5}};
    detail::SureOptions analytic, mc;
    mc.analyticDivergence = false;
    const detail::SureEstimate a = detail::estimateSure(gaussian, f, p, analytic);
    const detail::SureEstimate m = detail::estimateSure(gaussian, f, p, mc);
    ASSERT_TRUE(a.analytic);
    ASSERT_FALSE(m.analytic);
    // The analytic divergence is the normalised centre weight: 1/(2π σ²) inside (up to the
    // truncation at 3σ), larger where the kernel is cut by the border.
    EXPECT_NEAR(a.divergence(48, 48, 0), 1.0 / (2.0 * M_PI * 1.5 * 1.5), 0.003);
    // In the corner both 1D kernels are cut in half: about (1 / 0.63)² = 2.5 times larger.
    EXPECT_GT(a.divergence(0, 0, 0), 2.0f * a.divergence(48, 48, 0));
    // Averages of the per-pixel Monte-Carlo estimate over a block. Its per-value standard
    // deviation is about sqrt(Σ_{q≠p} w_q²) ≈ 1/(sqrt(4π) σ) = 0.19; we allow 5 standard
    // deviations of the block mean (values taken as independent).
    auto blockMeans = [](const Image& d, int x0, int x1, int y0, int y1) {
        double s = 0.0;
        for (int y = y0; y < y1; ++y)
            for (int x = x0; x < x1; ++x)
                for (int c = 0; c < 3; ++c) s += d(x, y, c);
        return s / double((x1 - x0) * (y1 - y0) * 3);
    };
    struct Block {
        int x0, x1, y0, y1;
    };
    for (const Block& b : {Block{10, 86, 10, 86}, Block{0, 6, 0, 6}, Block{90, 96, 40, 60}}) {
        const double n = double((b.x1 - b.x0) * (b.y1 - b.y0) * 3);
        const double tol = 5.0 * 0.19 / std::sqrt(n);
        EXPECT_NEAR(blockMeans(m.divergence, b.x0, b.x1, b.y0, b.y1),
                    blockMeans(a.divergence, b.x0, b.x1, b.y0, b.y1), tol)
            << "block " << b.x0 << ".." << b.x1 << " x " << b.y0 << ".." << b.y1;
    }
    // Both SURE estimates agree with the true MSE.
    const double meanVar = 0.05 * 0.05;
    EXPECT_NEAR(sureMse(a.sure), glint::mse(a.output, clean).value, kSureTolerance * meanVar);
    EXPECT_NEAR(sureMse(m.sure), sureMse(a.sure), kSureTolerance * meanVar);
}

// A bank of `params` gaussians (and optionally a bilateral) over `f`.
FilterBank gaussianBank(const FrameBuffers& f, const std::vector<double>& sigmas,
                        bool withBilateral = false) {
    std::vector<BankMember> members;
    std::vector<Image> results;
    for (double s : sigmas) members.push_back({"gaussian", {{"sigma", s}}, false});
    if (withBilateral)
        members.push_back({"bilateral", resolveParams(findFilter("bilateral"), {}), true});
    for (BankMember& m : members) {
        m.params = resolveParams(findFilter(m.filter), m.params);
        results.push_back(applyFilter(findFilter(m.filter), f, m.params));
    }
    return FilterBank(std::move(members), std::move(results), Rect{0, f.width(), 0, f.height()},
                      f.width(), f.height(), hashFrame(f));
}

// A colour of 1e32 where the output is 0.3: (f - y)^2 = 1e64 is past a float, so the SURE map
// holds the largest float there (as the halves' maps do), not +inf.
TEST(Sure, AnErrorPastAFloatIsTheLargestFloatNotInfinity) {
    Image noisy(2, 1, 3, 0.3f);
    noisy(1, 0, 0) = 1e32f;
    const Image variance(2, 1, 3, 0.01f), output(2, 1, 3, 0.3f), divergence(2, 1, 3, 0.1f);
    const Image map = detail::sureMap(noisy, variance, output, divergence, Rect{0, 2, 0, 1});
    EXPECT_EQ(map(1, 0, 0), std::numeric_limits<float>::max());
    EXPECT_NEAR(map(0, 0, 0), 3.0 * (-0.01 + 2.0 * 0.01 * 0.1), 1e-7);
}

TEST(Sure, SelectionPicksTheMemberWithTheSmallestTrueErrorWhereUnambiguous) {
    // Left: smooth (a wide blur is best); right: a fine checkerboard (a tiny blur is best).
    const Image clean = cleanImage(128, 96, true);
    const FrameBuffers f = noisyFrame(clean, 0.06, 0.06, 14);
    const FilterBank bank = gaussianBank(f, {0.4, 1.0, 3.0});
    // The plain smoothed-SURE argmin (no confidence margin, no feathering) is what this test
    // checks.
    AutoOptions o;
    o.tuning["space"] = 3;  // linear
    o.tuning["window"] = 3;
    o.tuning["confidence"] = 0.0;
    o.tuning["feather"] = 0;
    const AutoResult r = autoComposite(bank, f, o);
    // With the default margin and feathering it still beats every single member (checked below
    // too).
    AutoOptions cautious = o;
    cautious.tuning.erase("confidence");  // the estimator's defaults
    cautious.tuning.erase("feather");
    const AutoResult rc = autoComposite(bank, f, cautious);

    // Where the best member's true error (smoothed like the SURE maps) is less than half the
    // runner-up's, auto must agree.
    const auto [unambiguous, agree] = testing::agreementWhereUnambiguous(bank, clean, r.choice, 3);
    ASSERT_GT(unambiguous, 128 * 96 / 3);
    EXPECT_GT(double(agree) / unambiguous, 0.95) << agree << " of " << unambiguous;
    // The composite beats every single member, and the single choice is the true best.
    double bestSingle = 1e30;
    int bestMember = -1;
    for (std::size_t m = 0; m < bank.size(); ++m)
        if (glint::mse(bank.result(m), clean).value < bestSingle)
            bestSingle = glint::mse(bank.result(m), clean).value, bestMember = int(m);
    EXPECT_LT(glint::mse(r.composite, clean).value, bestSingle);
    EXPECT_LT(glint::mse(rc.composite, clean).value, bestSingle);
    EXPECT_EQ(r.bestMember, bestMember);
    // Hard choice: layers are indicator maps that sum to 1.
    Image sum(128, 96, 1);
    for (const AutoLayer& l : r.layers)
        for (std::size_t p = 0; p < sum.data().size(); ++p) sum.data()[p] += l.weights.data()[p];
    for (float v : sum.data()) ASSERT_EQ(v, 1.0f);
    // Feathered: they still sum to 1 (up to float rounding).
    Image feathered(128, 96, 1);
    for (const AutoLayer& l : rc.layers)
        for (std::size_t p = 0; p < sum.data().size(); ++p)
            feathered.data()[p] += l.weights.data()[p];
    for (float v : feathered.data()) ASSERT_NEAR(v, 1.0f, 1e-5f);
}

TEST(Sure, SoftWeightsSumToOneAndTheCompositeIsTheirBlend) {
    const Image clean = cleanImage(64, 48, true);
    const FrameBuffers f = noisyFrame(clean, 0.04, 0.08, 15);
    const FilterBank bank = gaussianBank(f, {0.4, 1.0, 3.0});
    AutoOptions o;
    o.tuning["temperature"] = 0.5;
    const AutoResult r = autoComposite(bank, f, o);
    ASSERT_GE(r.layers.size(), 2u);
    for (int y = 0; y < 48; y += 7)
        for (int x = 0; x < 64; x += 5) {
            double w = 0.0, c = 0.0;
            for (const AutoLayer& l : r.layers) {
                w += l.weights(x, y, 0);
                c += l.weights(x, y, 0) * bank.result(std::size_t(l.member))(x, y, 0);
            }
            EXPECT_NEAR(w, 1.0, 1e-5);
            EXPECT_NEAR(c, r.composite(x, y, 0), 1e-5);
        }
}

TEST(Sure, SameResultForAnyThreadCount) {
    const FrameBuffers f = testing::syntheticFrame(64, 48, 0.08f);
    const FilterBank bank = gaussianBank(f, {0.7, 2.0}, true);
    AutoOptions o;
    o.tuning["temperature"] = 0.3;
    AutoResult one, two;
    {
        tbb::task_arena arena(1);
        arena.execute([&] { one = autoComposite(bank, f, o); });
    }
    {
        tbb::task_arena arena(2);
        arena.execute([&] { two = autoComposite(bank, f, o); });
    }
    ASSERT_EQ(one.composite.data().size(), two.composite.data().size());
    for (std::size_t i = 0; i < one.composite.data().size(); ++i)
        ASSERT_EQ(one.composite.data()[i], two.composite.data()[i]) << i;
    EXPECT_EQ(one.estimatedMse, two.estimatedMse);
    // A different seed perturbs differently (the bilateral's Monte-Carlo estimate moves).
    o.seed = 2;
    const AutoResult other = autoComposite(bank, f, o);
    EXPECT_NE(other.estimatedMse.back(), one.estimatedMse.back());
}

TEST(Sure, MissingVarianceLayerIsRefusedNamingTheLayer) {
    FrameBuffers f = testing::syntheticFrame(24, 20, 0.05f);
    f.remove(Layer::Variance);
    try {
        detail::checkSureInput(f, "noisy.exr");
        FAIL() << "no error";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::Format);
        EXPECT_EQ(e.file(), "noisy.exr");
        EXPECT_NE(std::string(e.what()).find("variance.R"), std::string::npos) << e.what();
        EXPECT_NE(e.where().find("variance"), std::string::npos) << e.what();
    }
    EXPECT_THROW(detail::estimateSure(findFilter("gaussian"), f, {}), Error);
}

TEST(Sure, AVarianceLayerTheRendererSaysUnderflowedIsRefused) {
    // glint-render marks a frame whose variance fell below float's range (written as 0): SURE,
    // which would read those pixels as noise-free, refuses it and says why.
    FrameBuffers f = testing::syntheticFrame(24, 20, 0.05f);
    ASSERT_NO_THROW(detail::checkSureInput(f, "dim.exr"));
    f.metadata().extra[kVarianceUnderflowKey] = "480";
    try {
        detail::checkSureInput(f, "dim.exr");
        FAIL() << "no error";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::Numeric);
        EXPECT_EQ(e.file(), "dim.exr");
        EXPECT_EQ(e.where(), "attribute glint:varianceUnderflow");
        EXPECT_NE(e.message().find("480 pixels"), std::string::npos) << e.what();
    }
}

TEST(Sure, NanOrInfInColourOrVarianceIsRefusedNamingThePixel) {
    struct Case {
        Layer layer;
        int c;
        float value;
        std::string where, what;
    };
    const Case cases[] = {
        {Layer::Color, 1, std::nanf(""), "pixel (5, 3), channel G", "NaN"},
        {Layer::Color, 0, INFINITY, "pixel (5, 3), channel R", "Inf"},
        {Layer::Variance, 2, std::nanf(""), "pixel (5, 3), channel variance.B", "NaN"},
        {Layer::Variance, 0, -1.0f, "pixel (5, 3), channel variance.R", "negative"},
    };
    for (const Case& c : cases) {
        FrameBuffers f = testing::syntheticFrame(24, 20, 0.05f);
        f.layer(c.layer)(5, 3, c.c) = c.value;
        try {
            detail::checkSureInput(f, "in.exr");
            FAIL() << "no error for " << c.where;
        } catch (const Error& e) {
            EXPECT_EQ(e.kind(), ErrorKind::Numeric);
            EXPECT_EQ(e.where(), c.where);
            EXPECT_NE(e.message().find(c.what), std::string::npos) << e.what();
        }
    }
}

TEST(Sure, BadOptionsAndAnotherImagesBankAreRefused) {
    const FrameBuffers f = testing::syntheticFrame(32, 24, 0.05f);
    const FilterBank bank = gaussianBank(f, {1.0});
    AutoOptions o;
    o.tuning["window"] = -1;
    EXPECT_THROW(autoComposite(bank, f, o), Error);
    o = {};
    o.tuning["temperature"] = -1.0;
    EXPECT_THROW(autoComposite(bank, f, o), Error);
    o = {};
    o.tuning["epsilon"] = 0.0;
    EXPECT_THROW(autoComposite(bank, f, o), Error);
    const FrameBuffers other = testing::syntheticFrame(32, 24, 0.05f, 99);
    EXPECT_THROW(autoComposite(bank, other, {}), Error);
}

TEST(Sure, ProgressCanStopIt) {
    const FrameBuffers f = testing::syntheticFrame(32, 24, 0.05f);
    const FilterBank bank = gaussianBank(f, {0.7, 1.0, 2.0}, true);
    AutoOptions o;
    o.progress = [](double) { return false; };
    try {
        autoComposite(bank, f, o);
        FAIL() << "not cancelled";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::Cancelled);
    }
}

TEST(Sure, SessionStartsFromTheAutoComposite) {
    const Image clean = cleanImage(48, 40, true);
    const FrameBuffers f = noisyFrame(clean, 0.04, 0.08, 16);
    const FilterBank bank = gaussianBank(f, {0.4, 1.0, 3.0}, true);
    AutoOptions o;
    o.tuning["temperature"] = 0.3;
    const AutoResult r = autoComposite(bank, f, o);
    Session session(f);
    const std::size_t edits = startFromAuto(session, bank, r);
    // The members as layers, and auto's correction of the blend's float rounding when there is
    // any: the composite is auto's bit for bit.
    ASSERT_GE(session.layerCount(), r.layers.size());
    ASSERT_LE(session.layerCount(), r.layers.size() + 1);
    EXPECT_EQ(edits, 2 * session.layerCount());
    for (std::size_t i = 0; i < r.layers.size(); ++i)
        EXPECT_EQ(session.layer(i).filter, bank.members()[std::size_t(r.layers[i].member)].filter);
    if (session.layerCount() > r.layers.size()) {
        ASSERT_TRUE(session.layer(r.layers.size()).correction);
        EXPECT_LT(
            testing::maxAbsDiff(session.layer(r.layers.size()).correction->blend, r.composite),
            1e-5);
    }
    EXPECT_EQ(testing::maxAbsDiff(session.composite(), r.composite), 0.0);
    // Every edit can be undone: back to the noisy input.
    for (std::size_t i = 0; i < edits; ++i) session.undo();
    EXPECT_EQ(session.layerCount(), 0u);
    EXPECT_EQ(testing::maxAbsDiff(session.composite(), f.color()), 0.0);
    // A bank of another image is refused and nothing changes.
    const FrameBuffers other = noisyFrame(clean, 0.04, 0.08, 17);
    Session s2(other);
    EXPECT_THROW(startFromAuto(s2, bank, r), Error);
    EXPECT_EQ(s2.layerCount(), 0u);
}

TEST(Sure, BoxSmoothIsTheMeanOverTheWindowTruncatedAtTheBorder) {
    // 300 columns: two blocks of the vertical running sums; values spanning 8 orders of
    // magnitude (a firefly among small errors) must leave no residue after they leave the window.
    const int w = 300, h = 40;
    Image image(w, h, 1);
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(0.0f, 1e-3f);
    for (float& v : image.data()) v = u(rng);
    image(150, 5, 0) = 1e5f;
    for (int radius : {0, 1, 3, 8}) {
        Image one, two;
        {
            tbb::task_arena arena(1);
            arena.execute([&] { one = detail::boxSmooth(image, radius); });
        }
        {
            tbb::task_arena arena(2);
            arena.execute([&] { two = detail::boxSmooth(image, radius); });
        }
        ASSERT_TRUE(one.sameShape(image));
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                double s = 0.0;
                int count = 0;
                for (int yy = std::max(0, y - radius); yy <= std::min(h - 1, y + radius); ++yy)
                    for (int xx = std::max(0, x - radius); xx <= std::min(w - 1, x + radius);
                         ++xx, ++count)
                        s += image(xx, yy, 0);
                const double expected = s / count;
                ASSERT_NEAR(one(x, y, 0), expected, 1e-6 * std::abs(expected) + 1e-9)
                    << "radius " << radius << " at " << x << "," << y;
                ASSERT_EQ(one(x, y, 0), two(x, y, 0));
            }
    }
}

TEST(Sure, WindowScoreIsTheBoxSmoothedDifferencePlusItsStandardError) {
    // The one-pass score of the per-pixel choice against what it replaced, boxSmooth of stored
    // d = raw − base and d² maps (value for value: the same sums in the same order), and against
    // brute-force window sums in double: within 1e-5 relative for the mean, and for the standard
    // error within what float rounding of d² and of the averages (a few 1e-8 of the mean of d²)
    // leaves after the cancellation in mean of d² − mean² and the square root. Two column blocks
    // (300 wide), a firefly among small differences, both signs.
    const int w = 300, h = 37;
    Image raw(w, h, 1), base(w, h, 1);
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(-1e-3f, 2e-3f);
    for (float& v : raw.data()) v = u(rng);
    for (float& v : base.data()) v = u(rng);
    raw(150, 5, 0) = 3e3f;
    base(20, 30, 0) = -7.5f;
    Image d(w, h, 1), d2(w, h, 1);
    for (std::size_t p = 0; p < d.data().size(); ++p) {
        const double v = double(raw.data()[p]) - double(base.data()[p]);
        d.data()[p] = float(v);
        d2.data()[p] = float(v * v);
    }
    for (int radius : {0, 1, 3, 8}) {
        const Image mean = detail::boxSmooth(d, radius), meanSq = detail::boxSmooth(d2, radius);
        const double count = double((2 * radius + 1) * (2 * radius + 1));
        for (double confidence : {0.0, 1.5}) {
            const Image score = detail::windowScore(raw, base, radius, confidence);
            ASSERT_TRUE(score.sameShape(d));
            for (int y = 0; y < h; ++y)
                for (int x = 0; x < w; ++x) {
                    const double mu = mean(x, y, 0);
                    const double var = std::max(0.0, double(meanSq(x, y, 0)) - mu * mu);
                    const float stored = confidence > 0.0
                                             ? float(mu + confidence * std::sqrt(var / count))
                                             : float(mu);
                    ASSERT_EQ(score(x, y, 0), stored) << "radius " << radius << " confidence "
                                                      << confidence << " at " << x << "," << y;
                    double s = 0.0, s2 = 0.0;
                    int n = 0;
                    for (int yy = std::max(0, y - radius); yy <= std::min(h - 1, y + radius); ++yy)
                        for (int xx = std::max(0, x - radius); xx <= std::min(w - 1, x + radius);
                             ++xx, ++n) {
                            const double v = double(raw(xx, yy, 0)) - double(base(xx, yy, 0));
                            s += v;
                            s2 += v * v;
                        }
                    const double m = s / n;
                    const double expected =
                        m + confidence * std::sqrt(std::max(0.0, s2 / n - m * m) / count);
                    const double rounding = confidence * std::sqrt(4e-7 * (s2 / n) / count);
                    ASSERT_NEAR(score(x, y, 0), expected,
                                1e-5 * std::abs(expected) + rounding + 1e-9)
                        << "radius " << radius << " confidence " << confidence << " at " << x << ","
                        << y;
                }
        }
    }
}

}  // namespace
}  // namespace glint::denoise

// Tests of the "nfor" filter (first-order regression, Bitterli et al. 2016) through the public API.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <tuple>

#include "glint/denoise/bank.h"
#include "glint/denoise/filter.h"
#include "glint/denoise/registry.h"
#include "glint/image/error.h"
#include "synthetic_frames.h"

using namespace glint;
using namespace glint::denoise;

namespace {

// A w × h frame whose clean colour is an affine function of the features (smoothly varying
// albedo, two normals meeting at an edge, a depth ramp), plus Gaussian noise of `sigma` (seed
// fixed) with a variance layer of `variance`; `truth` receives the clean colour.
FrameBuffers affineFrame(int w, int h, float sigma, float variance, Image* truth) {
    FrameBuffers f(w, h);
    std::mt19937 rng(21);
    std::normal_distribution<float> noise(0.0f, sigma);
    Image& albedo = f.ensure(Layer::Albedo);
    Image& normal = f.ensure(Layer::Normal);
    Image& depth = f.ensure(Layer::Depth);
    Image clean(w, h, 3);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            float a[3];
            for (int c = 0; c < 3; ++c)
                a[c] = 0.5f + 0.3f * std::sin(float(x) / 7.0f + float(c)) *
                                  std::cos(float(y) / 9.0f - float(c));
            const bool up = x > w / 2;
            const float d = 2.0f + 0.05f * float(y);
            for (int c = 0; c < 3; ++c) albedo(x, y, c) = a[c];
            normal(x, y, 0) = up ? 0.0f : 1.0f;
            normal(x, y, 1) = up ? 1.0f : 0.0f;
            normal(x, y, 2) = 0.0f;
            depth(x, y, 0) = d;
            for (int c = 0; c < 3; ++c) {
                clean(x, y, c) =
                    0.1f + 0.6f * a[c] + 0.2f * a[(c + 1) % 3] + (up ? 0.3f : 0.1f) + 0.02f * d;
                f.color()(x, y, c) = clean(x, y, c) + noise(rng);
            }
        }
    f.ensure(Layer::Variance).fill(variance);
    if (truth) *truth = clean;
    return f;
}

double rmsTo(const Image& a, const Image& b) {
    return denoise::testing::rmsDiff(a, b);
}

// `frame` (the clean image `clean` plus noise of `sigma`) with half buffers of 8 samples each:
// half A is the old colour, half B the clean image plus independent noise of `sigma`, the colour
// becomes their mean; features are the same in both halves.
FrameBuffers withHalves(FrameBuffers frame, const Image& clean, float sigma) {
    std::mt19937 rng(5);
    std::normal_distribution<float> noise(0.0f, sigma);
    Image b = clean;
    for (float& v : b.data()) v += noise(rng);
    Image mean = frame.color();
    for (std::size_t i = 0; i < mean.data().size(); ++i)
        mean.data()[i] = 0.5f * (frame.color().data()[i] + b.data()[i]);
    frame.set(Layer::HalfColor, b);
    frame.ensure(Layer::Variance).fill(0.5f * sigma * sigma);
    frame.ensure(Layer::HalfVariance).fill(sigma * sigma);
    frame.set(Layer::Color, mean);
    for (Layer l : {Layer::Albedo, Layer::AlbedoVariance, Layer::Normal, Layer::NormalVariance,
                    Layer::Depth, Layer::DepthVariance}) {
        if (!frame.has(l)) frame.ensure(l);
        frame.set(*halfLayer(l), frame.layer(l));
    }
    frame.ensure(Layer::SampleCount).fill(16.0f);
    frame.ensure(Layer::HalfSampleCount).fill(8.0f);
    return frame;
}

const ParamValues kSmall{{"windowRadius", 3}, {"patchRadius", 1}};

}  // namespace

// First-order regression is exact on colour that is an affine function of the features: with a
// negligible ridge the noise-free image comes back to 5e-4 (float moments; though the variance
// layer lets the weights reach across the window), and the noisy one (sigma 0.05) to an RMS error
// below a third of the noise and half a Gaussian's.
TEST(Nfor, RecoversAnAffineFunctionOfTheFeatures) {
    const Filter& nfor = findFilter("nfor");
    Image truth;
    const FrameBuffers clean = affineFrame(48, 40, 0.0f, 0.0025f, &truth);
    const ParamValues p{
        {"ridge", 1e-6}, {"strength", 1.0}, {"windowRadius", 5}, {"patchRadius", 1}};
    EXPECT_LT(denoise::testing::maxAbsDiff(applyFilter(nfor, clean, p), truth), 5e-4);

    const FrameBuffers noisy = affineFrame(48, 40, 0.05f, 0.0025f, &truth);
    const double noisyRms = rmsTo(noisy.color(), truth);
    const double nforRms = rmsTo(applyFilter(nfor, noisy, p), truth);
    EXPECT_LT(nforRms, 0.33 * noisyRms) << "noisy " << noisyRms;
    const double gaussRms =
        rmsTo(applyFilter(findFilter("gaussian"), noisy, {{"sigma", 1.0}}), truth);
    EXPECT_LT(nforRms, 0.5 * gaussRms) << "nfor " << nforRms << " gaussian " << gaussRms;
}

// On the synthetic frame with a feature edge, NFOR beats the best of a sweep of Gaussians by a
// factor of 1.5 in RMS error (fixed seed), with and without half buffers.
TEST(Nfor, BeatsTheBestGaussianOnAFeatureEdge) {
    const Filter& nfor = findFilter("nfor");
    const FrameBuffers clean = denoise::testing::syntheticFrame(64, 64, 0.0f);
    for (bool halves : {false, true}) {
        FrameBuffers noisy = denoise::testing::syntheticFrame(64, 64, 0.1f, 3);
        if (halves) noisy = withHalves(noisy, clean.color(), 0.1f);
        double bestGauss = std::numeric_limits<double>::infinity();
        for (double sigma : {0.5, 0.75, 1.0, 1.5, 2.0, 3.0, 4.0})
            bestGauss = std::min(
                bestGauss, rmsTo(applyFilter(findFilter("gaussian"), noisy, {{"sigma", sigma}}),
                                 clean.color()));
        const double err = rmsTo(applyFilter(nfor, noisy, {{"strength", 1.0}}), clean.color());
        EXPECT_LT(err * 1.5, bestGauss) << "halves " << halves;
    }
}

// A region's result equals the crop of the whole frame's (the margin is truthful), with and
// without half buffers, for a region crossing tile borders.
TEST(Nfor, RegionEqualsCropOfTheFullFrame) {
    const Filter& nfor = findFilter("nfor");
    for (bool halves : {false, true}) {
        FrameBuffers frame = denoise::testing::syntheticFrame(150, 90, 0.08f);
        if (halves)
            frame =
                withHalves(frame, denoise::testing::syntheticFrame(150, 90, 0.0f).color(), 0.08f);
        const Image full = applyFilter(nfor, frame, kSmall);
        const Rect roi{37, 101, 20, 75};
        const Image part = applyFilter(nfor, frame, kSmall, denoise::testing::inRegion(roi));
        double diff = 0.0;
        for (int y = roi.y0; y < roi.y1; ++y)
            for (int x = roi.x0; x < roi.x1; ++x)
                for (int c = 0; c < 3; ++c)
                    diff = std::max(
                        diff, double(std::fabs(full(x, y, c) - part(x - roi.x0, y - roi.y0, c))));
        EXPECT_EQ(diff, 0.0) << "halves " << halves;
    }
}

TEST(Nfor, DeterministicAcrossThreadCounts) {
    const Filter& nfor = findFilter("nfor");
    const FrameBuffers frame =
        withHalves(denoise::testing::syntheticFrame(140, 80, 0.08f),
                   denoise::testing::syntheticFrame(140, 80, 0.0f).color(), 0.08f);
    Image one, two;
    {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
        one = applyFilter(nfor, frame, kSmall);
    }
    {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
        two = applyFilter(nfor, frame, kSmall);
    }
    EXPECT_EQ(denoise::testing::maxAbsDiff(one, two), 0.0);
}

TEST(Nfor, MissingFeatureLayerIsNamed) {
    const Filter& nfor = findFilter("nfor");
    for (Layer missing : {Layer::Albedo, Layer::Normal, Layer::Depth}) {
        FrameBuffers frame = denoise::testing::syntheticFrame(20, 16);
        frame.remove(missing);
        try {
            applyFilter(nfor, frame, {});
            ADD_FAILURE() << "no error without " << layerDisplayName(missing);
        } catch (const Error& e) {
            EXPECT_EQ(e.kind(), ErrorKind::InvalidArgument);
            EXPECT_NE(std::string(e.what()).find(std::string(layerDisplayName(missing))),
                      std::string::npos)
                << e.what();
        }
    }
}

// A NaN colour pixel and a NaN feature pixel leave every output finite, and pixels beyond the
// margin equal those of the clean input (the shared non-finite policy, filter_util.h).
TEST(Nfor, NonFiniteInputStaysLocal) {
    const Filter& nfor = findFilter("nfor");
    const FrameBuffers clean = denoise::testing::syntheticFrame(60, 50, 0.05f);
    FrameBuffers bad = clean;
    bad.color()(30, 25, 1) = std::numeric_limits<float>::quiet_NaN();
    bad.layer(Layer::Albedo)(12, 10, 0) = std::numeric_limits<float>::infinity();
    const Image a = applyFilter(nfor, clean, kSmall), b = applyFilter(nfor, bad, kSmall);
    const int m = nfor.margin(resolveParams(nfor, kSmall));
    for (int y = 0; y < 50; ++y)
        for (int x = 0; x < 60; ++x)
            for (int c = 0; c < 3; ++c) {
                ASSERT_TRUE(std::isfinite(b(x, y, c))) << x << "," << y;
                const bool near1 = std::abs(x - 30) <= m && std::abs(y - 25) <= m;
                const bool near2 = std::abs(x - 12) <= m && std::abs(y - 10) <= m;
                if (!near1 && !near2) {
                    ASSERT_EQ(a(x, y, c), b(x, y, c)) << x << "," << y;
                }
            }
}

// A feature or colour no render writes (an albedo of -5e37, a normal of 1e20, a green of 1.5e38:
// found by fuzz_denoise_input) overflowed a window's float moments and wrote NaN; it now counts
// as missing, exactly as an infinite one does: finite output, the same bits as with a NaN there.
TEST(Nfor, AbsurdFeaturesAndColoursAreMissingLikeNonFiniteOnes) {
    const Filter& nfor = findFilter("nfor");
    const FrameBuffers clean = denoise::testing::syntheticFrame(40, 30, 0.05f);
    FrameBuffers absurd = clean, missing = clean;
    absurd.layer(Layer::Albedo)(20, 15, 1) = -5e37f;
    absurd.layer(Layer::Normal)(8, 6, 2) = 1e20f;
    absurd.color()(30, 20, 1) = 1.5e38f;
    absurd.layer(Layer::Depth)(12, 25, 0) = 1e29f;  // nor does it change the others' depth scale
    for (auto [x, y, l] : {std::tuple{20, 15, Layer::Albedo}, std::tuple{8, 6, Layer::Normal},
                           std::tuple{30, 20, Layer::Color}, std::tuple{12, 25, Layer::Depth}})
        missing.layer(l)(x, y, 0) = std::numeric_limits<float>::quiet_NaN();
    const Image a = applyFilter(nfor, absurd, kSmall), b = applyFilter(nfor, missing, kSmall);
    for (int y = 0; y < 30; ++y)
        for (int x = 0; x < 40; ++x)
            for (int c = 0; c < 3; ++c) {
                ASSERT_TRUE(std::isfinite(a(x, y, c))) << x << "," << y;
                ASSERT_EQ(a(x, y, c), b(x, y, c)) << x << "," << y;
            }
}

// The emitter guard: on a flat dark frame (0.1, noise sigma 0.03 with its variance, seed fixed)
// one pixel holds a tiny bright emitter as 2 samples would see it (mean 50, variance of the mean
// 2500, so the variance-normalised distance alone accepts it, D ~ 0). Pixels 2 to 12 px away stay
// within 0.05 of 0.1; without the guard the emitter's window spreads about 50 / 81 = 0.6 over
// them.
TEST(Nfor, BrightHighVarianceSpeckDoesNotLeak) {
    const int n = 41, c0 = 20;
    FrameBuffers f(n, n);
    std::mt19937 rng(8);
    std::normal_distribution<float> noise(0.0f, 0.03f);
    f.ensure(Layer::Albedo).fill(0.5f);
    Image& normal = f.ensure(Layer::Normal);
    f.ensure(Layer::Depth).fill(1.0f);
    Image& var = f.ensure(Layer::Variance);
    var.fill(0.03f * 0.03f);
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            normal(x, y, 2) = 1.0f;
            for (int c = 0; c < 3; ++c) f.color()(x, y, c) = 0.1f + noise(rng);
        }
    for (int c = 0; c < 3; ++c) {
        f.color()(c0, c0, c) = 50.0f;
        var(c0, c0, c) = 2500.0f;
    }
    const Image out = applyFilter(findFilter("nfor"), f, {});
    double worst = 0.0;
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            const int d = std::max(std::abs(x - c0), std::abs(y - c0));
            if (d < 2 || d > 12) continue;
            for (int c = 0; c < 3; ++c)
                worst = std::max(worst, std::fabs(double(out(x, y, c)) - 0.1));
        }
    EXPECT_LT(worst, 0.05);
}

// nfor is an opt-in bank filter: the default bank leaves it out, a bank that names it holds it.
TEST(Nfor, JoinsABankOnlyWhenNamed) {
    for (const Filter* f : defaultBankFilters()) EXPECT_NE(f->name(), "nfor");
    EXPECT_LT(defaultBankFilters().size(), allFilters().size());
    const FrameBuffers frame = denoise::testing::syntheticFrame(32, 24);
    BankOptions options;
    options.size = 2;
    options.filters = {"nfor"};
    const FilterBank bank = buildBank(frame, options);
    ASSERT_EQ(bank.size(), 3u);
    for (const BankMember& m : bank.members()) EXPECT_EQ(m.filter, "nfor");
}

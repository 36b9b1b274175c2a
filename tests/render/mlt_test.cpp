// Metropolis light transport (integrator mlt): the primary-sample-space sampler's mutations
// and stationary distribution, convergence to the path tracer on cornell, statistics, thread
// determinism, and MLT beating the path tracer on Veach's door scene at equal samples.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "glint/image/error.h"
#include "glint/image/io.h"
#include "glint/image/metrics.h"
#include "glint/render/renderer.h"
#include "glint/render/scene.h"
#include "sampling/mlt_sampler.h"
#include "test_util.h"

namespace glint::render {
namespace {

namespace fs = std::filesystem;

/// The shipped scenes/cornell/scene.json at size × size.
Scene cornell(int size) {
    const fs::path shipped = fs::path(GLINT_SOURCE_DIR) / "scenes/cornell/scene.json";
    std::ifstream in(shipped);
    nlohmann::json j = nlohmann::json::parse(in);
    j["film"] = {{"width", size}, {"height", size}};
    return parseScene(j.dump(), shipped);
}

double meanLuminance(const Image& img) {
    double sum = 0.0;
    for (int y = 0; y < img.height(); ++y)
        for (int x = 0; x < img.width(); ++x)
            sum += 0.2126 * img(x, y, 0) + 0.7152 * img(x, y, 1) + 0.0722 * img(x, y, 2);
    return sum / double(img.pixelCount());
}

MutationSizes defaultSizes() {
    MutationSizes s;
    s.small = {1.0f / 1024.0f, 1.0f / 64.0f};
    s.lensX = s.lensY = {1.0f / 256.0f, 1.0f / 16.0f};
    s.light = {1.0f / 256.0f, 1.0f / 8.0f};
    return s;
}

// ---------------------------------------------------------------------------------------------
// The sampler on its own.

TEST(PrimarySample, MutationsTouchOnlyTheirCoordinates) {
    MltSampler s(42, defaultSizes());
    auto read = [&](std::vector<float>& camera, std::vector<float>& path,
                    std::vector<float>& light) {
        camera.clear(), path.clear(), light.clear();
        for (int d = 0; d < kCameraDims; ++d) camera.push_back(s.camera(d));
        for (int i = 0; i < 6; ++i) path.push_back(s.uniform()), light.push_back(s.uniformLight());
    };
    std::vector<float> c0, p0, l0, c1, p1, l1;
    s.startIteration(MutationKind::Large);
    read(c0, p0, l0);
    s.accept();

    // Lens perturbation: film x/y and lens u/v move, time and both streams stay.
    s.startIteration(MutationKind::Lens);
    read(c1, p1, l1);
    for (int d = kFilmX; d <= kLensV; ++d) EXPECT_NE(c1[std::size_t(d)], c0[std::size_t(d)]) << d;
    EXPECT_EQ(c1[kTime], c0[kTime]);
    EXPECT_EQ(p1, p0);
    EXPECT_EQ(l1, l0);
    // Rejection restores the accepted state exactly.
    s.reject();
    s.startIteration(MutationKind::Light);
    read(c1, p1, l1);
    EXPECT_EQ(c1, c0);
    EXPECT_EQ(p1, p0);
    for (std::size_t i = 0; i < l0.size(); ++i) EXPECT_NE(l1[i], l0[i]) << i;
    s.reject();

    // Small step: every coordinate moves, each by at most s2 (around the circle).
    s.startIteration(MutationKind::Small);
    read(c1, p1, l1);
    auto near = [](float a, float b) {
        const float d = std::abs(a - b);
        return std::min(d, 1.0f - d) <= 1.0f / 64.0f + 1e-6f;
    };
    for (std::size_t i = 0; i < c0.size(); ++i) EXPECT_TRUE(near(c1[i], c0[i]) && c1[i] != c0[i]);
    for (std::size_t i = 0; i < p0.size(); ++i) EXPECT_TRUE(near(p1[i], p0[i]) && p1[i] != p0[i]);
    s.accept();

    // Large step: fresh numbers everywhere.
    s.startIteration(MutationKind::Large);
    read(c0, p0, l0);
    EXPECT_NE(p0, p1);
    EXPECT_NE(c0, c1);
}

TEST(PrimarySample, SameKeyReproducesTheState) {
    // A chain restarts from a bootstrap sample by replaying its stream: same key, same numbers.
    MltSampler a(7, defaultSizes()), b(7, defaultSizes());
    a.startIteration(MutationKind::Large);
    b.startIteration(MutationKind::Large);
    for (int i = 0; i < 20; ++i) EXPECT_EQ(a.uniform(), b.uniform());
    EXPECT_EQ(a.camera(kFilmX), b.camera(kFilmX));
}

// The chain's states are distributed in proportion to a known target, including a coordinate
// that only some states read (lazily extended dimensions). Target on (x0, x1, l, p), with x0,
// x1 camera coordinates, l a light-stream and p a path-stream number read only when x0 < 0.5:
//   f = (0.3 <= x0 < 0.31 ? 40 : 1) · (x1 < 0.5 ? 1 : 2) · (1 + 2 l) · (x0 < 0.5 ? 0.5 + p : 1).
// The narrow bright band makes the chain stick, where a step size that grew with rejections
// (counting rejected iterations as pending steps) would under-sample it. Marginals: x0 ∝ (40
// on [0.3, 0.31), 1 elsewhere); l ∝ 1 + 2l; p | x0<0.5 ∝ 0.5 + p. The final
// states of 6000 independent chains (300 mutations each, started uniformly) are independent
// samples; Pearson chi-square per marginal at family-wise α = 0.01 (Šidák over 3 tests).
TEST(PrimarySample, ChainSamplesTheTarget) {
    const int chains = 6000, steps = 300, bins = 10;
    std::vector<double> hx(bins, 0.0), hl(bins, 0.0), hp(bins, 0.0);
    const float cdf[4] = {0.25f, 0.8f, 0.9f, 2.0f};  // large, small, lens, light
    for (int c = 0; c < chains; ++c) {
        MltSampler s(1000 + std::uint64_t(c), defaultSizes());
        float fx = 0.0f, x0 = 0.0f, l = 0.0f, p = -1.0f;
        auto eval = [&](float& ox0, float& ol, float& op) {
            const float a = s.camera(kFilmX), b = s.camera(kFilmY), u = s.uniformLight();
            ox0 = a, ol = u, op = -1.0f;
            float f = (a >= 0.3f && a < 0.31f ? 40.0f : 1.0f) * (b < 0.5f ? 1.0f : 2.0f) *
                      (1.0f + 2.0f * u);
            if (a < 0.5f) {
                op = s.uniform();
                f *= 0.5f + op;
            }
            return f;
        };
        s.startIteration(MutationKind::Large);
        fx = eval(x0, l, p);
        s.accept();
        for (int i = 0; i < steps; ++i) {
            const float uk = s.rng().uniform();
            int k = 0;
            while (uk >= cdf[k]) ++k;
            s.startIteration(MutationKind(k));
            float y0, yl, yp;
            const float fy = eval(y0, yl, yp);
            if (s.rng().uniform() < std::min(1.0f, fy / fx)) {
                s.accept();
                fx = fy, x0 = y0, l = yl, p = yp;
            } else {
                s.reject();
            }
        }
        hx[std::size_t(std::min(int(x0 * bins), bins - 1))] += 1.0;
        hl[std::size_t(std::min(int(l * bins), bins - 1))] += 1.0;
        if (p >= 0.0f) hp[std::size_t(std::min(int(p * bins), bins - 1))] += 1.0;
    }
    // Expected counts from the marginals (bin integrals).
    std::vector<double> ex(bins), el(bins), ep(bins);
    const double zx = 40.0 * 0.01 + 0.99;
    double pCount = 0.0;
    for (double v : hp) pCount += v;
    for (int i = 0; i < bins; ++i) {
        const double a = double(i) / bins, b = double(i + 1) / bins;
        ex[std::size_t(i)] = chains * (i == 3 ? 0.4 + 0.09 : 0.1) / zx;
        el[std::size_t(i)] = chains * ((b - a) + (b * b - a * a)) / 2.0;
        ep[std::size_t(i)] = pCount * (0.5 * (b - a) + 0.5 * (b * b - a * a));
    }
    const double alpha = test::sidak(0.01, 3);
    const test::Chi2 rx = test::chi2Test(hx, ex), rl = test::chi2Test(hl, el),
                     rp = test::chi2Test(hp, ep);
    EXPECT_GT(rx.pValue, alpha) << "x0 chi2 " << rx.statistic;
    EXPECT_GT(rl.pValue, alpha) << "light chi2 " << rl.statistic;
    EXPECT_GT(rp.pValue, alpha) << "path chi2 " << rp.statistic;
}

// ---------------------------------------------------------------------------------------------
// The integrator.

Settings mltSettings(const Renderer& r, int spp) {
    Settings s = r.scene().settings();
    s.integrator = Integrator::Mlt;
    s.spp = spp;
    s.threads = 2;
    s.mlt.chains = 64;
    s.mlt.groups = 16;
    s.mlt.bootstrap = 1 << 16;
    s.mlt.featureSpp = 1;
    return s;
}

// Cornell 24×24: MLT at 512 mutations per pixel (295k mutations, 64 chains, 2^20 bootstrap
// paths) against the path tracer at 4096 spp. Tolerances, from the estimators' own statistics:
// the mean of (MLT − PT)² / (var_MLT + var_PT) over pixels and channels is ≈ 1 for a consistent
// estimator with honest variances (batch means over 16 groups have 15 degrees of freedom, so
// ≈ 15/13; the shared estimate of b adds a little); measured 1.28 at seed 1, we require it in
// [0.4, 2.5]. relMSE measured 0.0062 at seed 1 (0.026 with the history-dependent step bug of
// docs/metropolis.md); bound 0.015. Mean luminance: it is set by b, whose relative standard
// error is 0.31 % here (reported by the render), and the PT reference's is ≈ 0.1 %, so 1 % is
// over 3σ (measured +0.02 %).
TEST(Mlt, ConvergesToThePathTracerOnCornell) {
    Renderer renderer(cornell(24));
    Settings pt = renderer.scene().settings();
    pt.spp = 4096;
    pt.threads = 2;
    const FrameBuffers ref = renderer.render(pt).frame;
    Settings s = mltSettings(renderer, 512);
    s.mlt.bootstrap = 1 << 20;  // b sets the image mean: its relative standard error ≈ 0.3 %
    const FrameBuffers mlt = renderer.render(s).frame;
    std::cout << "b relative standard error " << mlt.metadata().extra.at("mltBRelStdErr") << "\n";
    EXPECT_EQ(mlt.metadata().integrator, "mlt");
    EXPECT_EQ(mlt.metadata().spp, 512);

    const double rel = relMse(mlt.color(), ref.color()).value;
    std::cout << "cornell 24x24: MLT relMSE " << rel << "\n";
    EXPECT_LT(rel, 0.015);
    const double lm = meanLuminance(mlt.color()), lr = meanLuminance(ref.color());
    EXPECT_NEAR(lm / lr, 1.0, 0.01) << lm << " vs " << lr;

    double z2 = 0.0;
    int n = 0;
    const Image &m = mlt.color(), &r = ref.color();
    const Image &vm = mlt.layer(Layer::Variance), &vr = ref.layer(Layer::Variance);
    for (int y = 0; y < m.height(); ++y)
        for (int x = 0; x < m.width(); ++x)
            for (int c = 0; c < 3; ++c) {
                const double v = double(vm(x, y, c)) + vr(x, y, c);
                if (v <= 0.0) continue;
                const double d = double(m(x, y, c)) - r(x, y, c);
                z2 += d * d / v;
                ++n;
            }
    ASSERT_GT(n, m.width() * m.height());  // most pixels have a variance estimate
    std::cout << "mean z^2 " << z2 / n << ", luminance ratio " << lm / lr << "\n";
    EXPECT_LT(z2 / n, 2.5);
    EXPECT_GT(z2 / n, 0.4);
}

// A long-ish run: 2048 mutations per pixel on 16×16 (524k mutations): every pixel finite, no
// path discarded as NaN/Inf, statistics recorded.
TEST(Mlt, NoNanAfterALongRunAndStatisticsRecorded) {
    Renderer renderer(cornell(16));
    Settings s = mltSettings(renderer, 2048);
    const RenderResult result = renderer.render(s);
    const FrameBuffers& f = result.frame;
    EXPECT_EQ(f.color().countNonFinite(), 0u);
    EXPECT_EQ(f.layer(Layer::Variance).countNonFinite(), 0u);
    EXPECT_EQ(f.metadata().nonFiniteSamples, 0);
    EXPECT_EQ(result.stats.nonFiniteSamples, 0);
    // The statistics travel typed, and the file records the same numbers.
    ASSERT_TRUE(result.stats.mlt.has_value());
    const MltStats& mlt = *result.stats.mlt;
    EXPECT_EQ(mlt.mutations, 2048ull * 256);
    EXPECT_EQ(mlt.chains, 64);
    EXPECT_EQ(mlt.groups, 16);
    EXPECT_GT(mlt.b, 0.0);
    EXPECT_EQ(std::to_string(mlt.mutations), f.metadata().extra.at("mltMutations"));
    for (int k = 0; k < 4; ++k) {
        EXPECT_GT(mlt.acceptance(k), 0.0) << mltMutationName(k);
        EXPECT_LE(mlt.acceptance(k), 1.0) << mltMutationName(k);
    }
    const auto& extra = f.metadata().extra;
    ASSERT_TRUE(extra.count("mltVariance"));
    EXPECT_EQ(extra.at("mltVariance"), "batch-means over 16 groups of 4 chains");
    EXPECT_GT(std::stod(extra.at("mltB")), 0.0);
    EXPECT_EQ(std::stoull(extra.at("mltMutations")), 2048ull * 256);
    for (const char* k :
         {"mltAcceptanceLarge", "mltAcceptanceSmall", "mltAcceptanceLens", "mltAcceptanceLight"}) {
        ASSERT_TRUE(extra.count(k)) << k;
        const double a = std::stod(extra.at(k));
        EXPECT_GT(a, 0.0) << k;
        EXPECT_LE(a, 1.0) << k;
    }
    EXPECT_GT(std::stod(extra.at("mltMutationsPerSecond")), 0.0);
    // The image mean's error holds b's and the chains' (in quadrature).
    const double bRel = std::stod(extra.at("mltBRelStdErr")),
                 chainsRel = std::stod(extra.at("mltChainsRelStdErr"));
    EXPECT_GT(chainsRel, 0.0);
    EXPECT_NEAR(std::stod(extra.at("mltMeanRelStdErr")), std::hypot(bRel, chainsRel),
                1e-6 * std::hypot(bRel, chainsRel));
    // The same figures in the render's statistics (glint-render's summary and --json).
    EXPECT_NEAR(mlt.chainsRelStdErr, chainsRel, 1e-6 * chainsRel);
    EXPECT_NEAR(mlt.meanRelStdErr, std::hypot(bRel, chainsRel), 1e-6 * mlt.meanRelStdErr);
    // Features come from the path-traced pass.
    EXPECT_TRUE(f.has(Layer::Albedo));
    EXPECT_TRUE(f.has(Layer::Normal));
    EXPECT_TRUE(f.has(Layer::Depth));
}

// The reported errors against their spread over 40 seeds (101-140, used for nothing else):
// cornell 24×24, 32 mutations per pixel, 2^16 bootstrap paths. The spread of b matches b's
// relative standard error, and the spread of the image's mean luminance matches
// mltMeanRelStdErr (b's and the chains' errors in quadrature), each within a factor 1.5 (the
// standard deviation of 40 draws is itself uncertain by ≈ 11 %). b's error alone is not that of
// the mean: the chains' part is as large here, and 3-4 × larger behind a pane
// (docs/metropolis.md).
TEST(Mlt, ReportedErrorsMatchTheSpreadOverSeeds) {
    Renderer renderer(cornell(24));
    std::vector<double> means, bs;
    double bRel2 = 0.0, meanRel2 = 0.0;
    const int seeds = 40;
    for (int seed = 101; seed < 101 + seeds; ++seed) {
        Settings s = mltSettings(renderer, 32);
        s.seed = std::uint64_t(seed);
        const FrameBuffers f = renderer.render(s).frame;
        const auto& extra = f.metadata().extra;
        means.push_back(meanLuminance(f.color()));
        bs.push_back(std::stod(extra.at("mltB")));
        bRel2 += std::pow(std::stod(extra.at("mltBRelStdErr")), 2) / seeds;
        meanRel2 += std::pow(std::stod(extra.at("mltMeanRelStdErr")), 2) / seeds;
    }
    auto relSpread = [](const std::vector<double>& v) {
        double m = 0.0, s2 = 0.0;
        for (double x : v) m += x / double(v.size());
        for (double x : v) s2 += (x - m) * (x - m) / double(v.size() - 1);
        return std::sqrt(s2) / m;
    };
    const double bRatio = relSpread(bs) / std::sqrt(bRel2);
    const double meanRatio = relSpread(means) / std::sqrt(meanRel2);
    std::cout << "spread / reported: b " << bRatio << ", image mean " << meanRatio
              << ", image mean against b's error alone " << relSpread(means) / std::sqrt(bRel2)
              << "\n";
    EXPECT_GT(bRatio, 1.0 / 1.5);
    EXPECT_LT(bRatio, 1.5);
    EXPECT_GT(meanRatio, 1.0 / 1.5);
    EXPECT_LT(meanRatio, 1.5);
}

TEST(Mlt, BitIdenticalForAnyThreadCount) {
    Renderer renderer(cornell(16));
    Settings s = mltSettings(renderer, 32);
    s.threads = 1;
    const FrameBuffers one = renderer.render(s).frame;
    s.threads = 2;
    const FrameBuffers two = renderer.render(s).frame;
    test::expectSameFrames(one, two);
    for (const char* k : {"mltB", "mltAcceptanceSmall", "mltAcceptanceLarge", "mltMutations"})
        EXPECT_EQ(one.metadata().extra.at(k), two.metadata().extra.at(k)) << k;
    s.seed = 5;
    EXPECT_FALSE(test::sameLayer(one, renderer.render(s).frame, Layer::Color));
}

TEST(Mlt, CancelReturnsTheCompletedPasses) {
    Renderer renderer(cornell(16));
    Settings s = mltSettings(renderer, 8);  // passes of 1, 1, 2, 4 mutations per pixel
    int passes = 0;
    Callbacks cb;
    cb.passDone = [&](int, const FrameBuffers&) { ++passes; };
    cb.cancel = [&] { return passes >= 2; };
    const RenderResult result = renderer.render(s, cb);
    const FrameBuffers& f = result.frame;
    EXPECT_EQ(f.metadata().spp, 2);
    EXPECT_EQ(f.metadata().extra.at("cancelled"), "true");
    EXPECT_TRUE(result.stats.cancelled);
    // The frame equals an uncancelled 2-mutations-per-pixel render.
    s.spp = 2;
    EXPECT_TRUE(test::sameLayer(f, renderer.render(s).frame, Layer::Color));
}

TEST(Mlt, RejectsBadParameters) {
    Renderer renderer(cornell(8));
    auto expectError = [&](auto edit, const std::string& fragment) {
        Settings s = mltSettings(renderer, 1);
        edit(s.mlt);
        try {
            renderer.render(s);
            ADD_FAILURE() << "expected an error containing '" << fragment << "'";
        } catch (const Error& e) {
            EXPECT_EQ(e.kind(), ErrorKind::InvalidArgument);
            EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
        }
    };
    expectError([](MltSettings& m) { m.largeStep = -0.1; }, "probabilities");
    expectError([](MltSettings& m) { m.largeStep = m.smallStep = m.lens = m.light = 0.0; },
                "at least one");
    expectError([](MltSettings& m) { m.s1 = 0.1, m.s2 = 0.01; }, "s1 <= s2");
    expectError([](MltSettings& m) { m.groups = 1; }, "groups");
    expectError([](MltSettings& m) { m.chains = 20; }, "multiple of groups");
    expectError([](MltSettings& m) { m.bootstrap = 0; }, "bootstrap");
    expectError([](MltSettings& m) { m.featureSpp = 0; }, "featureSpp");
}

// Veach's door scene (scenes/door): light reaches the camera's room only through a narrow slit,
// the case where Metropolis wins. Equal numbers of traced paths: the path tracer at 20 spp
// against MLT at 16 mutations per pixel + a 3-spp bootstrap + a 1-spp feature pass, both
// compared with the committed 16384-spp reference (seed 1; these runs use seed 2). Measured
// relMSE at seed 2: PT 24.4 (its fireflies), MLT 0.79; seeds 1, 3, 4: PT 5.55 / 2.32 / 17.5,
// MLT 0.59 / 1.03 / 1.00. We require MLT below 0.6 × PT.
TEST(Mlt, BeatsThePathTracerOnDoorAtEqualSamples) {
    const fs::path dir = fs::path(GLINT_SOURCE_DIR) / "scenes/door";
    ASSERT_TRUE(fs::exists(dir / "reference.exr")) << "missing scenes/door/reference.exr";
    const FrameBuffers ref = readExr(dir / "reference.exr");
    Renderer renderer(loadScene(dir / "scene.json"));
    const std::int64_t pixels = std::int64_t(renderer.scene().width()) * renderer.scene().height();
    Settings pt = renderer.scene().settings();
    pt.spp = 20;
    pt.threads = 2;
    pt.seed = 2;  // the reference used seed 1: share no samples with it
    const double ptRel = relMse(renderer.render(pt).frame.color(), ref.color()).value;
    Settings s = pt;
    s.integrator = Integrator::Mlt;
    s.spp = 16;
    s.mlt.bootstrap = 3 * pixels;
    s.mlt.featureSpp = 1;
    const double mltRel = relMse(renderer.render(s).frame.color(), ref.color()).value;
    std::cout << "door: PT relMSE " << ptRel << ", MLT relMSE " << mltRel << "\n";
    EXPECT_LT(mltRel, 0.6 * ptRel) << "MLT " << mltRel << " vs PT " << ptRel;
}

}  // namespace
}  // namespace glint::render

namespace glint::render {
namespace {

// One render loop drives both integrators: the MLT feature pass reports progress and can be
// cancelled like the chains (it could do neither before).
TEST(MltLoop, FeaturePassReportsProgressAndCanBeCancelled) {
    Renderer renderer(cornell(16));
    Settings s = mltSettings(renderer, 8);
    s.mlt.featureSpp = 4;
    s.tileSize = 4;  // 16 tiles per pass: the cancel poll comes between tiles
    std::vector<double> fractions;
    int polls = 0;
    Callbacks cb;
    cb.progress = [&](int, double f) { fractions.push_back(f); };
    cb.cancel = [&] { return ++polls > 3; };  // at the 4th tile of the first feature pass
    const RenderResult stopped = renderer.render(s, cb);
    EXPECT_TRUE(stopped.stats.cancelled);
    EXPECT_EQ(stopped.frame.metadata().spp, 0);
    EXPECT_FALSE(stopped.stats.mlt.has_value());
    EXPECT_EQ(stopped.frame.color().countNonFinite(), 0u);
    ASSERT_FALSE(fractions.empty());
    // Feature-pass progress stays below the feature pass's share of the whole render.
    for (double f : fractions) EXPECT_LE(f, 4.0 / 12.0 + 1e-12);

    // Uncancelled: progress rises through both stages to 1.
    fractions.clear();
    cb.cancel = nullptr;
    const RenderResult full = renderer.render(s, cb);
    EXPECT_FALSE(full.stats.cancelled);
    ASSERT_FALSE(fractions.empty());
    for (std::size_t i = 1; i < fractions.size(); ++i) EXPECT_GE(fractions[i], fractions[i - 1]);
    EXPECT_NEAR(fractions.back(), 1.0, 1e-9);
    EXPECT_TRUE(full.stats.mlt.has_value());
}

// The bootstrap is the loop's first pass (a preparatory one): it reports progress as its blocks
// of 1024 paths finish and stops between blocks when cancelled (before, it did neither).
// Cornell 16×16 with 2^18 bootstrap paths (256 blocks, 1024 paths a pixel), 1 feature spp and
// 2 mutations a pixel: the features take [0, 1/3] of the progress, the bootstrap the next
// 1024/1026 of the rest.
TEST(MltLoop, BootstrapReportsProgress) {
    Renderer renderer(cornell(16));
    Settings s = mltSettings(renderer, 2);
    s.mlt.bootstrap = 1 << 18;
    const double featureEnd = 1.0 / 3.0;
    const double bootEnd = featureEnd + (1.0 - featureEnd) * 1024.0 / 1026.0;
    std::vector<double> fractions;
    int passes = 0, duringBootstrap = 0;
    Callbacks cb;
    cb.progress = [&](int, double f) {
        fractions.push_back(f);
        if (passes == 0 && f > featureEnd + 1e-12 && f <= bootEnd + 1e-12) ++duringBootstrap;
    };
    cb.passDone = [&](int, const FrameBuffers&) { ++passes; };
    const RenderResult result = renderer.render(s, cb);
    EXPECT_FALSE(result.stats.cancelled);
    ASSERT_TRUE(result.stats.mlt.has_value());
    EXPECT_EQ(result.stats.mlt->bootstrap, std::uint64_t(1) << 18);
    EXPECT_EQ(passes, 2);
    // One report per bootstrap block before any chain ran (the chains report above bootEnd)...
    EXPECT_GE(duringBootstrap, 256);
    // ...the last block's at the bootstrap's end of the progress, which never goes back.
    EXPECT_NE(std::find_if(fractions.begin(), fractions.end(),
                           [&](double f) { return std::abs(f - bootEnd) < 1e-9; }),
              fractions.end());
    for (std::size_t i = 1; i < fractions.size(); ++i) EXPECT_GE(fractions[i], fractions[i - 1]);
    EXPECT_NEAR(fractions.back(), 1.0, 1e-9);
}

TEST(MltLoop, CancelDuringTheBootstrapStopsIt) {
    Renderer renderer(cornell(16));
    Settings s = mltSettings(renderer, 2);
    s.mlt.bootstrap = 1 << 18;
    const double featureEnd = 1.0 / 3.0;
    bool inBootstrap = false;
    Callbacks cb;
    // Cancel at the first poll after a bootstrap block reported.
    cb.progress = [&](int, double f) { inBootstrap = inBootstrap || f > featureEnd + 1e-12; };
    cb.cancel = [&] { return inBootstrap; };
    const RenderResult result = renderer.render(s, cb);
    EXPECT_TRUE(result.stats.cancelled);
    EXPECT_EQ(result.stats.passes, 0);
    EXPECT_EQ(result.frame.metadata().spp, 0);
    EXPECT_EQ(result.frame.metadata().extra.at("cancelled"), "true");
    ASSERT_TRUE(result.stats.mlt.has_value());
    // Stopped within the blocks in flight (two threads): a few of the 256, not all of them.
    EXPECT_GE(result.stats.mlt->bootstrap, 1024u);
    EXPECT_LE(result.stats.mlt->bootstrap, 8u * 1024u);
    EXPECT_EQ(result.stats.mlt->mutations, 0u);
    // No chain ran: the colour is black, the features are the feature pass's.
    EXPECT_EQ(meanLuminance(result.frame.color()), 0.0);
    EXPECT_EQ(result.frame.color().countNonFinite(), 0u);
    EXPECT_TRUE(result.frame.has(Layer::Albedo));
}

}  // namespace
}  // namespace glint::render

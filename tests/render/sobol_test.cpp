// The Owen-scrambled Sobol sampler (sampling/sobol.h): stratification of every prefix, uniform
// scrambled values, faster than Monte Carlo convergence on a smooth integrand, and an unbiased
// Cornell box.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <vector>

#include "glint/image/io.h"
#include "glint/render/renderer.h"
#include "glint/render/scene.h"
#include "sampling/rng.h"
#include "sampling/sobol.h"
#include "test_util.h"

namespace glint::render {
namespace {

TEST(Sobol, TheUnscrambledPairIsAZeroTwoSequence) {
    // Every elementary interval of area 2^-m (2^a × 2^(m-a) cells) holds exactly one of the
    // first 2^m points, for every m up to 12 and every aligned block of 2^m points.
    for (int m = 0; m <= 12; ++m) {
        const std::uint32_t n = 1u << m;
        for (std::uint32_t block : {0u, 1u, 7u}) {
            for (int a = 0; a <= m; ++a) {
                std::vector<int> cells(n, 0);
                for (std::uint32_t i = block * n; i < (block + 1) * n; ++i) {
                    const std::uint32_t cx = a == 0 ? 0 : sobol0(i) >> (32 - a);
                    const std::uint32_t cy = m - a == 0 ? 0 : sobol1(i) >> (32 - (m - a));
                    ++cells[(cy << a) | cx];
                }
                for (int c : cells) ASSERT_EQ(c, 1) << "m " << m << " a " << a;
            }
        }
    }
}

TEST(Sobol, EveryScrambledPrefixOfAPowerOfTwoIsANet) {
    // After the index shuffle and the per-coordinate Owen scrambles, the first 2^m samples of a
    // pixel's pair still put one point in every elementary interval (float coordinates: the top
    // 24 bits, so up to 2^12 points per axis split).
    for (std::uint64_t seed : {1ull, 0x1234ull, 0xdeadbeefcafeull}) {
        for (int m = 1; m <= 10; ++m) {
            const std::uint32_t n = 1u << m;
            for (int a = 0; a <= m; ++a) {
                std::vector<int> cells(n, 0);
                for (std::uint32_t i = 0; i < n; ++i) {
                    const Vec2 p = sobol2D(i, seed);
                    const auto cx = std::uint32_t(p.x * float(1u << a));
                    const auto cy = std::uint32_t(p.y * float(1u << (m - a)));
                    ++cells[(cy << a) | cx];
                }
                for (int c : cells) ASSERT_EQ(c, 1) << "seed " << seed << " m " << m << " a " << a;
            }
            // The 1D form stratifies into 2^m equal intervals.
            std::vector<int> strata(n, 0);
            for (std::uint32_t i = 0; i < n; ++i)
                ++strata[std::uint32_t(sobol1D(i, seed) * float(n))];
            for (int c : strata) ASSERT_EQ(c, 1) << "1D, m " << m;
        }
    }
}

TEST(Sobol, ScrambledValuesAreUniformAcrossPixels) {
    // Sample 5 of 65536 pixels in one dimension: independent uniform values across pixels.
    // χ² over 64 bins has 63 degrees of freedom; Q < 1e-4 happens by chance once in 10^4.
    for (int dim = 0; dim < 4; ++dim) {
        std::vector<double> bins(64, 0.0);
        const int n = 65536;
        for (int pixel = 0; pixel < n; ++pixel) {
            const SobolSampler s(7, std::uint64_t(pixel), 5);
            const float v = dim < 2 ? s.camera2D(dim).y : s.bounce1D(dim, BounceDim::Roulette);
            ASSERT_GE(v, 0.0f);
            ASSERT_LT(v, 1.0f);
            bins[std::size_t(v * 64.0f)] += 1.0;
        }
        double chi2 = 0.0;
        const double expected = n / 64.0;
        for (double b : bins) chi2 += (b - expected) * (b - expected) / expected;
        EXPECT_GT(test::gammaQ(63 / 2.0, chi2 / 2.0), 1e-4) << "dim " << dim << " χ² " << chi2;
    }
}

/// Mean squared error over 128 pixels of an N-sample estimate of ∫∫ f over [0,1)², and the
/// least-squares slope of log(MSE) against log(N) over N = 16 … 1024.
template <class Estimate>
double mseSlope(Estimate estimate) {
    std::vector<double> lx, ly;
    for (int n = 16; n <= 1024; n *= 2) {
        double mse = 0.0;
        for (int pixel = 0; pixel < 128; ++pixel) {
            const double e = estimate(pixel, n);
            mse += e * e / 128.0;
        }
        lx.push_back(std::log(double(n)));
        ly.push_back(std::log(mse));
    }
    const double k = double(lx.size());
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    for (std::size_t i = 0; i < lx.size(); ++i)
        sx += lx[i], sy += ly[i], sxx += lx[i] * lx[i], sxy += lx[i] * ly[i];
    return (k * sxy - sx * sy) / (k * sxx - sx * sx);
}

TEST(Sobol, ASmoothIntegrandConvergesFasterThanMonteCarlo) {
    // f(x, y) = exp(-x² - y²) on [0,1)²: exact value (√π/2 · erf 1)².
    const double exact = std::pow(std::sqrt(M_PI) / 2.0 * std::erf(1.0), 2.0);
    auto f = [](double x, double y) { return std::exp(-x * x - y * y); };
    const double sobol = mseSlope([&](int pixel, int n) {
        double sum = 0.0;
        for (int i = 0; i < n; ++i) {
            const Vec2 p = SobolSampler(3, std::uint64_t(pixel), std::uint32_t(i))
                               .bounce2D(0, BounceDim::BsdfDirection);
            sum += f(p.x, p.y);
        }
        return sum / n - exact;
    });
    const double independent = mseSlope([&](int pixel, int n) {
        Rng rng(3, std::uint64_t(pixel), 0);
        double sum = 0.0;
        for (int i = 0; i < n; ++i) sum += f(rng.uniform(), rng.uniform());
        return sum / n - exact;
    });
    // Monte Carlo's MSE falls as N^-1; Owen-scrambled nets on a smooth integrand as N^-3
    // (Owen 1997). Over 128 pixels the fitted slopes are stable to about ±0.1.
    EXPECT_NEAR(independent, -1.0, 0.15);
    EXPECT_LT(sobol, -1.25);
}

TEST(Sobol, TheCornellBoxIsUnbiased) {
    // The image mean of a 16-spp Sobol render against the committed 4096-spp reference: within
    // 4 standard errors (the per-pixel variances of both images; the sample variance of a
    // scrambled net overstates its error, so this bound is conservative).
    const std::filesystem::path dir = GLINT_SOURCE_DIR;
    Renderer renderer(loadScene(dir / "scenes/cornell/scene.json"));
    Settings s = renderer.scene().settings();
    s.spp = 16;
    s.sampler = SamplerKind::Sobol;
    const FrameBuffers frame = renderer.render(s).frame;
    const FrameBuffers reference = readExr(dir / "scenes/cornell/reference.exr");
    ASSERT_EQ(reference.width(), frame.width());
    for (int c = 0; c < 3; ++c) {
        double mean = 0.0, refMean = 0.0, var = 0.0;
        const double n = double(frame.color().pixelCount());
        for (int y = 0; y < frame.height(); ++y)
            for (int x = 0; x < frame.width(); ++x) {
                mean += frame.color()(x, y, c) / n;
                refMean += reference.color()(x, y, c) / n;
                var += (frame.layer(Layer::Variance)(x, y, c) +
                        reference.layer(Layer::Variance)(x, y, c)) /
                       (n * n);
            }
        EXPECT_NEAR(mean, refMean, 4.0 * std::sqrt(var)) << "channel " << c;
    }
}

}  // namespace
}  // namespace glint::render

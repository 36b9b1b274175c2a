// The Owen-scrambled Sobol sampler (sampling/sobol.h): stratification of every prefix, uniform
// scrambled values, faster than Monte Carlo convergence on a smooth integrand, and an unbiased
// Cornell box.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "glint/image/error.h"
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

/// Whether the n points put exactly one in every elementary interval of area 1/n (n = 2^m).
bool isNet(const std::vector<Vec2>& points) {
    const auto n = std::uint32_t(points.size());
    const int m = ceilLog2(n);
    for (int a = 0; a <= m; ++a) {
        std::vector<int> cells(n, 0);
        for (const Vec2& p : points)
            ++cells[(std::uint32_t(p.y * float(1u << (m - a))) << a) |
                    std::uint32_t(p.x * float(1u << a))];
        for (int c : cells)
            if (c != 1) return false;
    }
    return true;
}

TEST(ZSobol, EveryPixelsBlockIsANetInEveryPair) {
    // A pixel's 2^m samples are an aligned block of the film-wide index after the nested digit
    // permutation, so every pair of every pixel is a (0, m, 2)-net, for even and odd m, at any
    // film position (corners and the last row of a non-square film included); and so are the
    // aligned prefixes (the nested permutation keeps the top digits of a prefix).
    for (int log2Spp : {4, 5, 6}) {
        const std::uint32_t spp = 1u << log2Spp;
        // The digits are base 4 from the top, so aligned prefixes hold 4^j samples with an
        // even log2Spp and 2 · 4^j with an odd one (the lowest digit is then base 2).
        const std::uint32_t prefixSize = log2Spp % 2 == 0 ? 16u : 8u;
        for (const auto& [x, y] : {std::pair{0, 0}, std::pair{37, 5}, std::pair{255, 191}}) {
            for (int dim : {0, 1, 3 + 1, 3 + 5 * 4 + 3}) {
                std::vector<Vec2> block, prefix;
                for (std::uint32_t s = 0; s < spp; ++s) {
                    const Vec2 p = ZSobolSampler(11, x, y, s, 8, log2Spp).camera2D(dim);
                    block.push_back(p);
                    if (s < prefixSize) prefix.push_back(p);
                }
                EXPECT_TRUE(isNet(block))
                    << "spp " << spp << " pixel " << x << "," << y << " dim " << dim;
                EXPECT_TRUE(isNet(prefix))
                    << "prefix " << prefixSize << ", pixel " << x << "," << y;
            }
            // A 1D dimension: 2^m equal strata, one sample each.
            std::vector<int> strata(spp, 0);
            for (std::uint32_t s = 0; s < spp; ++s)
                ++strata[std::uint32_t(
                    ZSobolSampler(11, x, y, s, 8, log2Spp).bounce1D(2, BounceDim::Roulette) *
                    float(spp))];
            for (int c : strata) EXPECT_EQ(c, 1);
        }
    }
}

TEST(ZSobol, IndicesArePixelBlocksAndDimensionsAreDecorrelated) {
    // The permuted index of pixel (x, y) stays inside some aligned block of 2^log2Spp indices
    // (one per pixel: 64 pixels of an 8 × 8 film take 64 distinct blocks), and two dimensions
    // order a pixel's samples differently (else their points would lie on a curve).
    const int log2Spp = 4;
    for (int dim : {0, 7}) {
        std::vector<int> owner(64, -1);
        for (int y = 0; y < 8; ++y)
            for (int x = 0; x < 8; ++x) {
                const std::uint32_t block =
                    ZSobolSampler(3, x, y, 0, 3, log2Spp).indexOf(dim) >> log2Spp;
                ASSERT_LT(block, 64u);
                EXPECT_EQ(owner[block], -1) << "block " << block << " taken twice";
                owner[block] = y * 8 + x;
                for (std::uint32_t s = 1; s < 16; ++s)
                    EXPECT_EQ(ZSobolSampler(3, x, y, s, 3, log2Spp).indexOf(dim) >> log2Spp, block);
            }
    }
    int sameOrder = 0;
    for (std::uint32_t s = 0; s < 16; ++s)
        sameOrder += ZSobolSampler(3, 2, 5, s, 3, log2Spp).indexOf(4) ==
                     ZSobolSampler(3, 2, 5, s, 3, log2Spp).indexOf(9);
    EXPECT_LT(sameOrder, 16);
    // Values across pixels are uniform: χ² over 64 bins of one sample of each of 65536 pixels
    // (63 degrees of freedom; Q < 1e-4 by chance once in 10^4).
    std::vector<double> bins(64, 0.0);
    for (int y = 0; y < 256; ++y)
        for (int x = 0; x < 256; ++x)
            bins[std::size_t(ZSobolSampler(7, x, y, 5, 8, 6).bounce2D(1, BounceDim::LightPoint).y *
                             64.0f)] += 1.0;
    double chi2 = 0.0;
    for (double b : bins) chi2 += (b - 1024.0) * (b - 1024.0) / 1024.0;
    EXPECT_GT(test::gammaQ(63 / 2.0, chi2 / 2.0), 1e-4) << "χ² " << chi2;
}

TEST(ZSobol, RefusesATimeLimitAndTooManyBits) {
    Renderer renderer(
        loadScene(std::filesystem::path(GLINT_SOURCE_DIR) / "scenes/cornell/scene.json"));
    Settings s = renderer.scene().settings();
    s.sampler = SamplerKind::ZSobol;
    s.spp = 0;
    s.timeLimit = 1.0;
    EXPECT_THROW(renderer.render(s), Error);
    s.timeLimit = 0.0;
    s.spp = 1 << 17;  // 2 · 8 + 17 = 33 bits for the 256² film
    try {
        renderer.render(s);
        ADD_FAILURE() << "no error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("zsobol"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("33 bits"), std::string::npos) << e.what();
    }
}

TEST(Sobol, TheCornellBoxIsUnbiased) {
    // The image mean of a 16-spp Sobol (and ZSobol) render against the committed 65,536-spp
    // reference: within 4 standard errors (the per-pixel variances of both images; the sample
    // variance of a scrambled net overstates its error, so this bound is conservative).
    const std::filesystem::path dir = GLINT_SOURCE_DIR;
    Renderer renderer(loadScene(dir / "scenes/cornell/scene.json"));
    for (SamplerKind sampler : {SamplerKind::Sobol, SamplerKind::ZSobol}) {
        SCOPED_TRACE(samplerName(sampler));
        Settings s = renderer.scene().settings();
        s.spp = 16;
        s.sampler = sampler;
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
}

}  // namespace
}  // namespace glint::render

// Piecewise-constant distributions: normalisation, sample/pdf agreement and inversion.
#include <gtest/gtest.h>

#include <vector>

#include "sampling/distribution.h"
#include "sampling/rng.h"

namespace glint::render {
namespace {

TEST(Distribution1D, PdfIntegratesToOne) {
    const std::vector<float> f = {0.0f, 1.0f, 3.0f, 0.5f, 0.0f, 2.0f};
    const Distribution1D d(f);
    // Midpoint rule is exact for a piecewise-constant density.
    double integral = 0.0;
    const int n = 6000;
    for (int i = 0; i < n; ++i) integral += d.pdf((i + 0.5f) / n) / n;
    EXPECT_NEAR(integral, 1.0, 1e-6);
    double discrete = 0.0;
    for (int i = 0; i < d.size(); ++i) discrete += d.discretePdf(i);
    EXPECT_NEAR(discrete, 1.0, 1e-6);
    EXPECT_NEAR(d.integral(), 6.5 / 6.0, 1e-6);
}

TEST(Distribution1D, SampleMatchesPdfAndInverts) {
    const std::vector<float> f = {0.2f, 0.0f, 5.0f, 1.0f};
    const Distribution1D d(f);
    Rng rng(7, 0, 0);
    for (int i = 0; i < 1000; ++i) {
        const float u = rng.uniform();
        float pdf = 0.0f;
        int bin = -1;
        const float x = d.sampleContinuous(u, &pdf, &bin);
        ASSERT_GE(x, 0.0f);
        ASSERT_LT(x, 1.0f);
        EXPECT_NE(bin, 1) << "zero-valued bins are never sampled";
        EXPECT_FLOAT_EQ(pdf, d.pdf(x));
        EXPECT_NEAR(d.invert(x), u, 1e-5);
    }
}

TEST(Distribution1D, AllZeroFallsBackToUniform) {
    const std::vector<float> f(4, 0.0f);
    const Distribution1D d(f);
    float pdf = 0.0f;
    d.sampleContinuous(0.3f, &pdf);
    EXPECT_FLOAT_EQ(pdf, 1.0f);
}

TEST(Distribution2D, PdfIntegratesToOneAndInverts) {
    const int nu = 8, nv = 5;
    std::vector<float> f(nu * nv);
    for (int v = 0; v < nv; ++v)
        for (int u = 0; u < nu; ++u)
            f[v * nu + u] = float((u * 7 + v * 3) % 5) + (v == 2 ? 0 : 0.25f);
    const Distribution2D d(f, nu, nv);
    double integral = 0.0;
    const int n = 200;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i)
            integral += d.pdf({(i + 0.5f) / n, (j + 0.5f) / n}) / (double(n) * n);
    EXPECT_NEAR(integral, 1.0, 1e-5);
    Rng rng(11, 0, 0);
    for (int i = 0; i < 1000; ++i) {
        const Vec2 u{rng.uniform(), rng.uniform()};
        float pdf = 0.0f;
        const Vec2 x = d.sample(u, &pdf);
        EXPECT_NEAR(pdf, d.pdf(x), 1e-4f * pdf);
        const Vec2 back = d.invert(x);
        EXPECT_NEAR(back.x, u.x, 1e-4);
        EXPECT_NEAR(back.y, u.y, 1e-4);
    }
}

TEST(Rng, StreamsDependOnEveryKeyPart) {
    Rng a(1, 2, 3), b(1, 2, 4), c(1, 3, 3), d(2, 2, 3), a2(1, 2, 3);
    const std::uint64_t va = a.nextU64();
    EXPECT_EQ(va, a2.nextU64());
    EXPECT_NE(va, b.nextU64());
    EXPECT_NE(va, c.nextU64());
    EXPECT_NE(va, d.nextU64());
}

TEST(Rng, PermuteIndexIsAPermutation) {
    for (std::uint32_t n : {1u, 2u, 5u, 16u, 17u, 100u}) {
        std::vector<int> seen(n, 0);
        for (std::uint32_t i = 0; i < n; ++i) ++seen[permuteIndex(i, n, 0x1234567u + n)];
        for (std::uint32_t i = 0; i < n; ++i) EXPECT_EQ(seen[i], 1) << "n=" << n;
    }
}

}  // namespace
}  // namespace glint::render

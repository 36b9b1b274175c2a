// bilateral (exact): limits, edge preservation and numerical extremes (public API only).
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <limits>
#include <string>

#include "glint/denoise/filter.h"
#include "glint/denoise/registry.h"
#include "synthetic_frames.h"

namespace glint::denoise {
namespace {

// Brute-force double-precision bilateral (Tomasi & Manduchi 1998) over the square window, with
// the documented non-finite policy: missing neighbours get weight 0, a missing centre drops the
// range term. The reference for the symmetric-pair implementation.
Image referenceBilateral(const Image& c, int radius, double sigmaS, double sigmaR) {
    Image out(c.width(), c.height(), 3);
    auto finite = [&](int x, int y) {
        return std::isfinite(c(x, y, 0)) && std::isfinite(c(x, y, 1)) && std::isfinite(c(x, y, 2));
    };
    for (int y = 0; y < c.height(); ++y)
        for (int x = 0; x < c.width(); ++x) {
            double num[3] = {0, 0, 0}, den = 0;
            for (int qy = std::max(0, y - radius); qy <= std::min(c.height() - 1, y + radius); ++qy)
                for (int qx = std::max(0, x - radius); qx <= std::min(c.width() - 1, x + radius);
                     ++qx) {
                    if (!finite(qx, qy)) continue;
                    double d2 = 0;
                    for (int k = 0; k < 3 && finite(x, y); ++k) {
                        const double d = double(c(qx, qy, k)) - double(c(x, y, k));
                        d2 += d * d;
                    }
                    const double s2 = double((qx - x) * (qx - x) + (qy - y) * (qy - y));
                    const double w =
                        std::exp(-s2 / (2 * sigmaS * sigmaS) - d2 / (2 * sigmaR * sigmaR));
                    for (int k = 0; k < 3; ++k) num[k] += w * c(qx, qy, k);
                    den += w;
                }
            for (int k = 0; k < 3; ++k) out(x, y, k) = den > 0 ? float(num[k] / den) : 0.0f;
        }
    return out;
}

TEST(Bilateral, SymmetricPairsMatchBruteForceAcrossBands) {
    // 150 rows with radius 6 span three 64-row bands of the symmetric-pair kernel (pairs inside a
    // band, pairs across a band border, the centre row); a NaN makes the middle band take the
    // one-sided path. The tolerance covers the 3.6e-6 relative error of the weights' exp2 and
    // float summation over 169 window pixels (values 0 ... 1).
    FrameBuffers frame = testing::syntheticFrame(37, 150, 0.1f);
    frame.color()(20, 90, 1) = std::numeric_limits<float>::quiet_NaN();
    const ParamValues p{{"sigmaS", 3.0}, {"sigmaR", 0.15}, {"radius", 6}};
    const Image ref = referenceBilateral(frame.color(), 6, 3.0, 0.15);
    const Image out = applyFilter(findFilter("bilateral"), frame, p);
    EXPECT_LT(testing::maxAbsDiff(out, ref), 1e-5);
    EXPECT_EQ(out.countNonFinite(), 0u);
    // A region of interest that crosses the band borders equals the same region of the full
    // output (different p columns change only the float summation order).
    const Rect roi{3, 30, 50, 140};
    EXPECT_LT(
        testing::maxAbsDiff(applyFilter(findFilter("bilateral"), frame, p, testing::inRegion(roi)),
                            out.crop(roi)),
        1e-6);
}

TEST(Bilateral, BitIdenticalForAnyThreadCount) {
    // Bands are fixed in image coordinates and each is summed by one task, so the thread count
    // cannot change the summation order.
    const FrameBuffers frame = testing::syntheticFrame(70, 260, 0.1f);
    for (const char* name : {"bilateral", "bilateral-mc"}) {
        const ParamValues p{{"sigmaS", 2.0}, {"sigmaR", 0.2}, {"radius", 5}};
        Image one, many;
        {
            tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
            one = applyFilter(findFilter(name), frame, p);
        }
        {
            tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 3);
            many = applyFilter(findFilter(name), frame, p);
        }
        EXPECT_EQ(testing::maxAbsDiff(one, many), 0.0) << name;
    }
}

TEST(Bilateral, HugeRangeSigmaEqualsGaussian) {
    const FrameBuffers frame = testing::syntheticFrame(31, 27, 0.2f);
    for (double sigma : {0.7, 2.0, 3.5}) {
        const Image b =
            applyFilter(findFilter("bilateral"), frame, {{"sigmaS", sigma}, {"sigmaR", 1e6}});
        const Image g = applyFilter(findFilter("gaussian"), frame, {{"sigma", sigma}});
        // Range weights are exp(-d²/2e12) = 1 to float precision; summation orders differ.
        EXPECT_LT(testing::maxAbsDiff(b, g), 1e-5) << "sigma " << sigma;
    }
}

TEST(Bilateral, TinySigmasAreTheIdentity) {
    const FrameBuffers frame = testing::syntheticFrame(15, 12, 0.2f);
    const Image s =
        applyFilter(findFilter("bilateral"), frame, {{"sigmaS", 1e-6}, {"sigmaR", 1.0}});
    EXPECT_EQ(testing::maxAbsDiff(s, frame.color()), 0.0);
    // Every neighbour differs by far more than sigmaR = 1e-6: only the centre keeps weight.
    const Image r =
        applyFilter(findFilter("bilateral"), frame, {{"sigmaS", 2.0}, {"sigmaR", 1e-6}});
    EXPECT_LT(testing::maxAbsDiff(r, frame.color()), 1e-7);
}

TEST(Bilateral, KeepsAnEdgeThatGaussianBlurs) {
    FrameBuffers frame = testing::constantFrame(32, 16, 0.1f, 0.1f, 0.1f);
    for (int y = 0; y < 16; ++y)
        for (int x = 16; x < 32; ++x)
            for (int c = 0; c < 3; ++c) frame.color()(x, y, c) = 0.9f;
    const Image b = applyFilter(findFilter("bilateral"), frame, {{"sigmaS", 3.0}, {"sigmaR", 0.1}});
    const Image g = applyFilter(findFilter("gaussian"), frame, {{"sigma", 3.0}});
    EXPECT_NEAR(b(15, 8, 0), 0.1f, 1e-4);
    EXPECT_NEAR(b(16, 8, 0), 0.9f, 1e-4);
    EXPECT_GT(g(15, 8, 0), 0.3f);  // the Gaussian mixes the two sides
}

TEST(Bilateral, RadiusParameterSetsTheWindow) {
    const Filter& f = findFilter("bilateral");
    EXPECT_EQ(f.margin(resolveParams(f, {{"radius", 15}})), 15);    // OpenCV d = 31
    EXPECT_EQ(f.margin(resolveParams(f, {{"sigmaS", 5.0}})), 15);   // ceil(3 sigmaS)
    EXPECT_EQ(f.margin(resolveParams(f, {{"sigmaS", 1e6}})), 100);  // capped
    // A refused value is written as given (not std::to_string's "0.000000" for 1e-12).
    auto refusal = [&](const ParamValues& given) {
        try {
            resolveParams(f, given);
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    EXPECT_NE(refusal({{"sigmaS", 1e-12}}).find("'sigmaS' = 1e-12 is outside"), std::string::npos)
        << refusal({{"sigmaS", 1e-12}});
    EXPECT_NE(refusal({{"radius", 2.5}}).find("'radius' = 2.5 must be an integer"),
              std::string::npos)
        << refusal({{"radius", 2.5}});
    // A larger window with the same sigmas changes the result only through the tail weights.
    const FrameBuffers frame = testing::syntheticFrame(24, 24, 0.1f);
    const Image r2 = applyFilter(f, frame, {{"sigmaS", 3.0}, {"radius", 2}});
    const Image r9 = applyFilter(f, frame, {{"sigmaS", 3.0}, {"radius", 9}});
    EXPECT_GT(testing::maxAbsDiff(r2, r9), 1e-4);
}

TEST(Bilateral, ExtremeSigmasAndRadianceStayFinite) {
    for (double sS : {1e-6, 1.5, 1e6})
        for (double sR : {1e-6, 0.1, 1e6})
            for (float scale : {1e-30f, 1.0f, 1e30f}) {
                FrameBuffers frame = testing::syntheticFrame(13, 11, 0.2f);
                for (float& v : frame.color().data()) v *= scale;
                const Image out = applyFilter(findFilter("bilateral"), frame,
                                              {{"sigmaS", sS}, {"sigmaR", sR}, {"radius", 4}});
                EXPECT_EQ(out.countNonFinite(), 0u) << sS << " " << sR << " " << scale;
                // A normalised filter never leaves the range of its input.
                float lo = frame.color()(0, 0, 0), hi = lo;
                for (float v : frame.color().data()) lo = std::min(lo, v), hi = std::max(hi, v);
                for (float v : out.data()) {
                    EXPECT_GE(v, lo - 1e-6f * std::fabs(lo));
                    EXPECT_LE(v, hi + 1e-6f * std::fabs(hi));
                }
            }
}

}  // namespace
}  // namespace glint::denoise

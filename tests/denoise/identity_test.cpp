// The identity filter (denoise/src/filters/identity.cpp): the render as it is, auto's candidate
// where no filter improves it. Its finite pixels come out bit for bit, it is its default member
// only in a bank, and beside one cross-bilateral member auto keeps a converged frame about as good
// as the render itself where cross-bilateral alone blurs it, without losing the filter's gain on
// a noisy frame.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "glint/denoise/auto.h"
#include "glint/denoise/bank.h"
#include "glint/denoise/registry.h"
#include "halves_frames.h"
#include "synthetic_frames.h"

namespace glint::denoise {
namespace {

using halves_test::cleanImage;
using halves_test::halvesFrame;
using halves_test::Noise;

TEST(Identity, FinitePixelsComeOutBitForBitAndAMissingOneFromItsNeighbours) {
    const Filter& identity = findFilter("identity");
    EXPECT_FALSE(identity.traits().smooths);
    EXPECT_TRUE(identity.params().empty());
    FrameBuffers frame = testing::syntheticFrame(9, 7, 0.1f);
    const Image clean = applyFilter(identity, frame, {});
    EXPECT_TRUE(testing::sameBits(clean, frame.color()));
    // A NaN at (4, 3): the mean of its eight neighbours; every other pixel as it was.
    const Image before = frame.color();
    frame.color()(4, 3, 1) = std::numeric_limits<float>::quiet_NaN();
    const Image out = applyFilter(identity, frame, {});
    for (int c = 0; c < 3; ++c) {
        double sum = 0.0;
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx)
                if (dx != 0 || dy != 0) sum += before(4 + dx, 3 + dy, c);
        EXPECT_FLOAT_EQ(out(4, 3, c), float(sum / 8.0)) << c;
    }
    for (int y = 0; y < 7; ++y)
        for (int x = 0; x < 9; ++x) {
            if (x == 4 && y == 3) continue;
            for (int c = 0; c < 3; ++c) ASSERT_EQ(out(x, y, c), before(x, y, c));
        }
}

TEST(Identity, InABankItIsItsDefaultMemberOnly) {
    BankOptions o;
    o.size = 4;
    o.filters = {"cross-bilateral"};
    const FrameBuffers frame = testing::syntheticFrame(16, 12, 0.05f);
    const FilterBank without = buildBank(frame, o);
    o.filters.push_back("identity");
    const FilterBank with = buildBank(frame, o);
    ASSERT_EQ(with.size(), without.size() + 1);
    // The filters' defaults come first, the identity's second; the Latin-hypercube members
    // after them are the same: the identity takes no stratum.
    EXPECT_EQ(with.members()[1].filter, "identity");
    EXPECT_TRUE(with.members()[1].isDefault);
    for (std::size_t i = 0; i < without.size(); ++i) {
        const BankMember& same = with.members()[i == 0 ? 0 : i + 1];
        EXPECT_EQ(same.filter, without.members()[i].filter) << i;
        EXPECT_EQ(same.params, without.members()[i].params) << i;
    }
}

// halvesFrame's clean image and noise, with flat features: cross-bilateral's guides see nothing
// of the disc's edge or the checkerboard, so it blurs them.
FrameBuffers flatFeatures(FrameBuffers f) {
    for (Layer albedo : {Layer::Albedo, Layer::HalfAlbedo}) f.ensure(albedo).fill(0.5f);
    for (Layer normal : {Layer::Normal, Layer::HalfNormal}) {
        Image& n = f.ensure(normal);
        for (int y = 0; y < f.height(); ++y)
            for (int x = 0; x < f.width(); ++x) n(x, y, 2) = 1.0f;
    }
    for (Layer depth : {Layer::Depth, Layer::HalfDepth}) f.ensure(depth).fill(2.0f);
    for (Layer variance :
         {Layer::AlbedoVariance, Layer::NormalVariance, Layer::DepthVariance,
          Layer::HalfAlbedoVariance, Layer::HalfNormalVariance, Layer::HalfDepthVariance})
        f.ensure(variance);
    return f;
}

double meanSquared(const Image& a, const Image& b) {
    double sum = 0.0;
    for (std::size_t i = 0; i < a.data().size(); ++i) {
        const double d = double(a.data()[i]) - double(b.data()[i]);
        sum += d * d;
    }
    return sum / double(a.data().size());
}

// Auto fast on one cross-bilateral member (its defaults and one Latin-hypercube member), with or
// without the identity: glint-final's cheapest plan.
double cheapestError(const FrameBuffers& frame, const Image& clean, bool withIdentity) {
    BankOptions bank;
    bank.size = 1;
    bank.filters = {"cross-bilateral"};
    if (withIdentity) bank.filters.push_back("identity");
    AutoOptions o;
    o.tuning = autoQualityTuning(AutoQuality::Fast);
    const AutoResult r = autoComposite(buildBank(frame, bank), frame, o);
    return meanSquared(r.composite, clean);
}

TEST(Identity, BesideOneFilterAutoKeepsAConvergedFrameAndStillDenoisesANoisyOne) {
    const Image clean = cleanImage(64, 48);
    // Converged: noise 0.002 a half (the colour's mean squared error 2.0e-6). Cross-bilateral
    // alone blurs the disc's edge and the checkerboard: 6.8e-3, 3,300 times that; with the
    // identity auto keeps the render there: 1.8e-6 (seeds 3 and 4 alike). Bounds: 1.5 × the
    // render's, and 100 × below the filter alone.
    for (std::uint32_t seed : {3u, 4u}) {
        const FrameBuffers frame = flatFeatures(halvesFrame(clean, 0.002, Noise::Gaussian, seed));
        const double render = meanSquared(frame.color(), clean);
        const double alone = cheapestError(frame, clean, false);
        const double with = cheapestError(frame, clean, true);
        EXPECT_LT(with, 1.5 * render) << "seed " << seed;
        EXPECT_LT(100.0 * with, alone) << "seed " << seed;
    }
    // Noisy: noise 0.2 a half (the render 2.0e-2). The filter's gain stays: 9.2e-3 and 9.6e-3
    // alone, 9.2e-3 and 9.6e-3 with the identity (0.3 and 0.6 % lower). Bounds: at most 5 %
    // above the filter alone, and below 0.7 × the render.
    for (std::uint32_t seed : {3u, 4u}) {
        const FrameBuffers frame = flatFeatures(halvesFrame(clean, 0.2, Noise::Gaussian, seed));
        const double alone = cheapestError(frame, clean, false);
        const double with = cheapestError(frame, clean, true);
        EXPECT_LT(with, 1.05 * alone) << "seed " << seed;
        EXPECT_LT(with, 0.7 * meanSquared(frame.color(), clean)) << "seed " << seed;
    }
}

}  // namespace
}  // namespace glint::denoise

// The simulated user, the oracle and the expected-error oracle (glint/lab/).
#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <cmath>
#include <set>

#include "glint/denoise/bank.h"
#include "glint/denoise/navigation.h"
#include "glint/image/error.h"
#include "glint/lab/expected_oracle.h"
#include "glint/lab/oracle.h"
#include "glint/lab/simulated_user.h"
#include "navigation_images.h"
#include "synthetic_frames.h"

namespace glint::lab {
namespace {

using denoise::BankOptions;
using denoise::buildBank;
using denoise::FilterBank;
using denoise::NavigationTree;
using denoise::TreeOptions;
using glint::testing::pointers;
using glint::testing::syntheticResults;
namespace testing = glint::denoise::testing;

TEST(SimulatedUser, ReachesTheMemberClosestToTheReference) {
    const std::vector<Image> images = syntheticResults(40);
    const NavigationTree tree(pointers(images), TreeOptions{});
    for (int target : {0, 13, 27, 39}) {
        const std::vector<SimulatedChoice> steps =
            simulateUser(tree, pointers(images), images[std::size_t(target)]);
        ASSERT_FALSE(steps.empty());
        EXPECT_EQ(steps.back().member, target);
        EXPECT_NEAR(steps.back().ssim, 1.0, 1e-9);
        // One choice per level down to a leaf, then the pick.
        EXPECT_LE(steps.size(), 1u + std::size_t(std::ceil(std::log2(40.0))));
    }
}

TEST(Oracle, OrderedMeasuresOnARealBank) {
    const FrameBuffers noisy = testing::syntheticFrame(48, 40, 0.1f);
    const FrameBuffers clean = testing::syntheticFrame(48, 40, 0.0f);
    BankOptions o;
    o.size = 12;
    const FilterBank bank = buildBank(noisy, o);
    const OracleResult r = oracle(bank, noisy.color(), clean.color());
    EXPECT_GT(r.bestSingle, r.noisy);
    EXPECT_GE(r.best3, r.bestSingle - 0.02);
    EXPECT_GE(r.perPixel, r.best3 - 0.02);
    EXPECT_GE(r.bestMember, 0);
    EXPECT_EQ(r.choice.width(), 48);
    for (float v : r.choice.data()) {
        EXPECT_GE(v, 0.0f);
        EXPECT_LT(v, float(bank.size()));
    }
    std::set<int> three(r.best3Members.begin(), r.best3Members.end());
    EXPECT_EQ(three.size(), 3u);
    EXPECT_THROW(oracle(bank, noisy.color(), Image(10, 10, 3)), Error);
}

TEST(Oracle, TheExpectedErrorOfOneRenderIsThePerPixelOracle) {
    // With the bank's own input as the only other render, each member's averaged error is the
    // error it made, so the choice at radius 0 is the per-pixel oracle's, pixel for pixel; it is
    // the same for any thread count, and bad input is refused.
    const FrameBuffers noisy = testing::syntheticFrame(48, 40, 0.1f);
    const FrameBuffers clean = testing::syntheticFrame(48, 40, 0.0f);
    BankOptions o;
    o.size = 8;
    const FilterBank bank = buildBank(noisy, o);
    const OracleResult r = oracle(bank, noisy.color(), clean.color());
    ExpectedOracleResult one, two;
    {
        tbb::task_arena arena(1);
        arena.execute([&] { one = expectedErrorOracle(bank, {noisy}, clean.color()); });
    }
    {
        tbb::task_arena arena(2);
        arena.execute([&] { two = expectedErrorOracle(bank, {noisy}, clean.color()); });
    }
    ASSERT_EQ(one.ssim.size(), 4u);
    EXPECT_EQ(one.renders, 2);
    EXPECT_EQ(one.ssim[0], r.perPixel);
    for (std::size_t p = 0; p < r.choice.data().size(); ++p)
        ASSERT_EQ(one.choice.data()[p], r.choice.data()[p]) << p;
    EXPECT_EQ(one.ssim, two.ssim);
    // Another render: a different choice, still a per-pixel choice among the members.
    const ExpectedOracleResult other =
        expectedErrorOracle(bank, {testing::syntheticFrame(48, 40, 0.1f, 11)}, clean.color());
    EXPECT_NE(other.ssim[0], one.ssim[0]);
    EXPECT_GT(other.ssim[0], r.noisy);
    EXPECT_THROW(expectedErrorOracle(bank, {}, clean.color()), Error);
    try {
        expectedErrorOracle(bank, {noisy, testing::syntheticFrame(40, 40, 0.1f)}, clean.color());
        FAIL() << "no error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("other render 2 is 40x40"), std::string::npos)
            << e.what();
    }
    ExpectedOracleOptions bad;
    bad.radii = {65};
    EXPECT_THROW(expectedErrorOracle(bank, {noisy}, clean.color(), bad), Error);
}

}  // namespace
}  // namespace glint::lab

// The navigation tree (soft hierarchical clustering), the navigator, the simulated user and
// the oracle.
#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "glint/denoise/bank.h"
#include "glint/denoise/navigation.h"
#include "glint/denoise/oracle.h"
#include "glint/denoise/research/expected_oracle.h"
#include "glint/image/error.h"
#include "glint/image/random.h"
#include "synthetic_frames.h"

namespace glint::denoise {
namespace {

// n images of 24×20 whose colour is a distinct level plus a pattern, so that their distances
// are spread out and unambiguous.
std::vector<Image> syntheticResults(int n, std::uint64_t seed = 3) {
    std::vector<Image> images;
    SplitMix64 rng(seed);
    for (int i = 0; i < n; ++i) {
        Image im(24, 20, 3);
        const float level = 0.05f + 0.9f * float(i) / float(std::max(n - 1, 1));
        const float tilt = float(rng.uniformDouble()) * 0.1f;
        for (int y = 0; y < 20; ++y)
            for (int x = 0; x < 24; ++x)
                for (int c = 0; c < 3; ++c)
                    im(x, y, c) =
                        level * (1.0f + tilt * float(x - 12) / 12.0f) * (c == 0 ? 1.0f : 0.8f);
        images.push_back(std::move(im));
    }
    return images;
}

std::vector<const Image*> pointers(const std::vector<Image>& images) {
    std::vector<const Image*> out;
    for (const Image& im : images) out.push_back(&im);
    return out;
}

// Every node's invariants, recursively; returns the members reachable below `node`.
std::set<int> checkNode(const NavigationTree& tree, int node) {
    const NavigationTree::Node& n = tree.node(node);
    const int k = tree.options().k;
    std::set<int> reach;
    if (n.children.empty()) {
        EXPECT_LE(int(n.members.size()), k);
        return {n.members.begin(), n.members.end()};
    }
    EXPECT_GT(int(n.members.size()), k);
    EXPECT_EQ(int(n.children.size()), k);
    const int parent = int(n.members.size());
    const int expected =
        std::min(int(std::ceil(tree.options().p * double(parent) - 1e-9)), parent - 1);
    std::multiset<int> slots;
    for (int c : n.children) {
        const NavigationTree::Node& child = tree.node(c);
        EXPECT_EQ(int(child.members.size()), expected) << "parent " << parent;
        EXPECT_EQ(child.parent, node);
        EXPECT_EQ(child.depth, n.depth + 1);
        // Children hold members of their parent, and their representative is one of them.
        for (int m : child.members)
            EXPECT_NE(std::find(n.members.begin(), n.members.end(), m), n.members.end());
        EXPECT_NE(std::find(child.members.begin(), child.members.end(), child.representative),
                  child.members.end());
        slots.insert(child.members.begin(), child.members.end());
        const std::set<int> below = checkNode(tree, c);
        reach.insert(below.begin(), below.end());
    }
    // Soft clustering: children overlap (k·⌈p·n⌉ > n here), and nothing is lost.
    EXPECT_GT(slots.size(), std::set<int>(slots.begin(), slots.end()).size());
    EXPECT_EQ(reach, std::set<int>(n.members.begin(), n.members.end()));
    return reach;
}

TEST(NavigationTree, InvariantsHoldAndEveryMemberIsReachable) {
    for (int n : {5, 16, 64, 70}) {
        const std::vector<Image> images = syntheticResults(n);
        const NavigationTree tree(pointers(images), TreeOptions{});
        EXPECT_EQ(tree.memberCount(), std::size_t(n));
        EXPECT_EQ(int(tree.node(tree.root()).members.size()), n);
        const std::set<int> all = checkNode(tree, tree.root());
        EXPECT_EQ(int(all.size()), n);
    }
    // Other k and p.
    TreeOptions o;
    o.k = 3;
    o.p = 0.4;
    const std::vector<Image> images = syntheticResults(40);
    const NavigationTree tree(pointers(images), o);
    EXPECT_EQ(int(checkNode(tree, tree.root()).size()), 40);
}

TEST(NavigationTree, DistanceIsSymmetricAndZeroOnTheDiagonal) {
    const std::vector<Image> images = syntheticResults(10);
    for (ImageDistance d : {ImageDistance::Mse, ImageDistance::Ssim}) {
        TreeOptions o;
        o.distance = d;
        const NavigationTree tree(pointers(images), o);
        for (int a = 0; a < 10; ++a) {
            EXPECT_EQ(tree.distance(a, a), 0.0);
            for (int b = 0; b < 10; ++b) EXPECT_EQ(tree.distance(a, b), tree.distance(b, a));
        }
        // Levels far apart are farther than neighbours.
        EXPECT_GT(tree.distance(0, 9), tree.distance(0, 1));
    }
}

TEST(NavigationTree, BadOptionsAndImagesAreRefused) {
    const std::vector<Image> images = syntheticResults(8);
    TreeOptions o;
    o.k = 1;
    EXPECT_THROW(NavigationTree(pointers(images), o), Error);
    o = {};
    o.p = 1.0;
    EXPECT_THROW(NavigationTree(pointers(images), o), Error);
    o.p = 0.0;
    EXPECT_THROW(NavigationTree(pointers(images), o), Error);
    o.p = 0.2;  // k·p < 1
    EXPECT_THROW(NavigationTree(pointers(images), o), Error);
    EXPECT_THROW(NavigationTree({}, TreeOptions{}), Error);
    std::vector<Image> mixed = syntheticResults(3);
    mixed.push_back(Image(10, 10, 3));
    EXPECT_THROW(NavigationTree(pointers(mixed), TreeOptions{}), Error);
}

TEST(Navigator, ChooseBackRestartAndTheyLookTheSame) {
    const std::vector<Image> images = syntheticResults(32);
    const NavigationTree tree(pointers(images), TreeOptions{});
    Navigator nav(tree, 9);
    EXPECT_EQ(nav.current(), tree.root());
    ASSERT_EQ(nav.options().size(), 4u);
    const int first = nav.options()[2].node;
    nav.choose(2);
    EXPECT_EQ(nav.current(), first);
    EXPECT_EQ(nav.choices(), 1);
    nav.back();
    EXPECT_EQ(nav.current(), tree.root());
    nav.back();  // nothing above the root
    EXPECT_EQ(nav.current(), tree.root());
    // Descend to a leaf and pick.
    while (!tree.isLeaf(nav.current())) nav.choose(0);
    const std::vector<Navigator::Option> leaf = nav.options();
    ASSERT_FALSE(leaf.empty());
    EXPECT_EQ(leaf[0].node, -1);
    nav.choose(0);
    ASSERT_TRUE(nav.chosen().has_value());
    EXPECT_EQ(*nav.chosen(), leaf[0].member);
    EXPECT_THROW(nav.choose(0), Error);
    nav.back();  // un-picks
    EXPECT_FALSE(nav.chosen().has_value());
    nav.restart();
    EXPECT_EQ(nav.current(), tree.root());
    // "They look the same": a member of the current subtree, the same for the same seed.
    nav.choose(1);
    const std::vector<int>& subtree = tree.node(nav.current()).members;
    const int picked = nav.same();
    EXPECT_NE(std::find(subtree.begin(), subtree.end(), picked), subtree.end());
    Navigator other(tree, 9);
    other.choose(1);
    EXPECT_EQ(other.same(), picked);
    EXPECT_THROW(other.choose(7), Error);
}

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
    research::ExpectedOracleResult one, two;
    {
        tbb::task_arena arena(1);
        arena.execute([&] { one = research::expectedErrorOracle(bank, {noisy}, clean.color()); });
    }
    {
        tbb::task_arena arena(2);
        arena.execute([&] { two = research::expectedErrorOracle(bank, {noisy}, clean.color()); });
    }
    ASSERT_EQ(one.ssim.size(), 4u);
    EXPECT_EQ(one.renders, 2);
    EXPECT_EQ(one.ssim[0], r.perPixel);
    for (std::size_t p = 0; p < r.choice.data().size(); ++p)
        ASSERT_EQ(one.choice.data()[p], r.choice.data()[p]) << p;
    EXPECT_EQ(one.ssim, two.ssim);
    // Another render: a different choice, still a per-pixel choice among the members.
    const research::ExpectedOracleResult other = research::expectedErrorOracle(
        bank, {testing::syntheticFrame(48, 40, 0.1f, 11)}, clean.color());
    EXPECT_NE(other.ssim[0], one.ssim[0]);
    EXPECT_GT(other.ssim[0], r.noisy);
    EXPECT_THROW(research::expectedErrorOracle(bank, {}, clean.color()), Error);
    try {
        research::expectedErrorOracle(bank, {noisy, testing::syntheticFrame(40, 40, 0.1f)},
                                      clean.color());
        FAIL() << "no error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("other render 2 is 40x40"), std::string::npos)
            << e.what();
    }
    research::ExpectedOracleOptions bad;
    bad.radii = {65};
    EXPECT_THROW(research::expectedErrorOracle(bank, {noisy}, clean.color(), bad), Error);
}

}  // namespace
}  // namespace glint::denoise

// The navigation tree (soft hierarchical clustering) and the navigator. The simulated user and the
// oracle are glint-lab's (tests/lab/oracle_test.cpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "glint/denoise/bank.h"
#include "glint/denoise/navigation.h"
#include "glint/image/error.h"
#include "navigation_images.h"

namespace glint::denoise {
namespace {

using glint::testing::pointers;
using glint::testing::syntheticResults;

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

}  // namespace
}  // namespace glint::denoise

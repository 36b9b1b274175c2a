// Image navigation: a design gallery over the bank organised by soft hierarchical clustering.
// At each node k centres are chosen among the node's members (k-means++ start, then k-medoids
// refinements); each child keeps the fraction p of the parent's members closest to its centre,
// so children overlap and one wrong choice can be undone further down; a node with at most k
// members is a leaf (docs/navigation.md).
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "glint/image/image.h"

namespace glint::denoise {

class FilterBank;

/// How two results are compared over the region of interest.
enum class ImageDistance {
    Mse,  ///< mean squared error of display values (exposure, clamp, sRGB)
    Ssim  ///< 1 − SSIM of display values
};

/// Parameters of the tree.
struct TreeOptions {
    int k = 4;       ///< children per node, >= 2
    double p = 0.5;  ///< fraction of a node's members each child keeps, in (0, 1); k·p >= 1
    ImageDistance distance = ImageDistance::Mse;
    float exposure = 0.0f;  ///< stops, for the display values
    /// Images are box-downsampled (linear values, then display) until their longer side is at
    /// most this (0: never), which keeps building the tree for 64 members fast; SSIM keeps at
    /// least 11 px per side.
    int maxSide = 128;
    int refinements = 4;     ///< k-medoids iterations after the k-means++ start
    std::uint64_t seed = 1;  ///< of k-means++
};

/// Throws glint::Error(InvalidArgument) naming the first bad option.
void validate(const TreeOptions& options);

/// The soft clustering tree over a set of images (e.g. a bank's results over a region).
class NavigationTree {
  public:
    /// One node: its members (indices into the images), the representative shown for it and
    /// its children (node indices; empty for a leaf).
    struct Node {
        std::vector<int> members;
        int representative = -1;
        std::vector<int> children;
        int parent = -1;
        int depth = 0;
    };

    /// Builds the tree over `images` (at least one, all of the same size and 3 channels).
    /// Child sizes are ⌈p·n⌉ (at most n − 1); every member is reachable from the root (members
    /// no child would keep replace a child's farthest member that another child also holds).
    NavigationTree(const std::vector<const Image*>& images, const TreeOptions& options);
    /// The tree over a bank's results, cropped to `region` (which must lie inside the bank's
    /// region; the whole bank region when empty).
    static NavigationTree fromBank(const FilterBank& bank, const TreeOptions& options,
                                   const std::optional<Rect>& region = std::nullopt);

    int root() const { return 0; }
    const Node& node(int index) const { return m_nodes[std::size_t(index)]; }
    std::size_t nodeCount() const { return m_nodes.size(); }
    std::size_t memberCount() const { return m_memberCount; }
    bool isLeaf(int index) const { return node(index).children.empty(); }
    /// Distance between members a and b (as TreeOptions::distance says).
    double distance(int a, int b) const {
        return m_distances[std::size_t(a) * m_memberCount + std::size_t(b)];
    }
    const TreeOptions& options() const { return m_options; }

  private:
    void split(int node);

    TreeOptions m_options;
    std::size_t m_memberCount = 0;
    std::vector<double> m_distances;  // memberCount²
    std::vector<Node> m_nodes;
};

/// A user's walk through a tree: what the studio's navigation stage shows and does.
class Navigator {
  public:
    /// One thing to show: a child node, or (at a leaf) a single member (node = -1).
    struct Option {
        int node = -1;
        int member = -1;  ///< the representative (or the member itself)
    };

    explicit Navigator(const NavigationTree& tree, std::uint64_t seed = 1);

    /// The node being looked at.
    int current() const { return m_path.back(); }
    /// The options at the current node: its children, or its members at a leaf.
    std::vector<Option> options() const;
    /// Descends into option i (a child), or at a leaf picks its member (done).
    void choose(int option);
    /// "They look the same": picks a random member of the current subtree (seeded) and
    /// returns it (done).
    int same();
    /// Back one level (and undoes a pick); nothing at the root.
    void back();
    /// Back to the root.
    void restart();
    /// The member picked, once done.
    std::optional<int> chosen() const { return m_chosen; }
    /// Choices made so far on the current path (a pick counts).
    int choices() const { return int(m_path.size()) - 1 + (m_chosen ? 1 : 0); }

  private:
    const NavigationTree* m_tree;
    std::vector<int> m_path;
    std::optional<int> m_chosen;
    std::uint64_t m_seed;
    std::uint64_t m_sameCount = 0;
};

}  // namespace glint::denoise

// The navigation tree: soft hierarchical clustering of a bank's results (k-means++ start,
// k-medoids refinement, overlapping children of the fraction p closest to each centre), the
// navigator a user walks.
#include "glint/denoise/navigation.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "glint/denoise/bank.h"
#include "glint/image/error.h"
#include "glint/image/io.h"
#include "glint/image/metrics.h"
#include "glint/image/random.h"

namespace glint::denoise {

void validate(const TreeOptions& o) {
    auto bad = [](const std::string& what, const char* option) {
        throw Error(ErrorKind::InvalidArgument, what, {}, option);
    };
    if (o.k < 2 || o.k > 64) bad("k = " + std::to_string(o.k) + " must be in [2, 64]", "--k");
    if (!(o.p > 0.0 && o.p < 1.0))
        bad("p = " + std::to_string(o.p) + " is not a number in (0, 1)", "--p");
    if (double(o.k) * o.p < 1.0)
        bad("k·p = " + std::to_string(double(o.k) * o.p) +
                " must be >= 1 so that every member stays reachable",
            "--p");
    if (!std::isfinite(o.exposure) || std::fabs(o.exposure) > 64.0f)
        bad("exposure must be finite, within ±64 stops", "--exposure");
    if (o.maxSide < 0) bad("maxSide must be >= 0", "--max-side");
    if (o.refinements < 0 || o.refinements > 100)
        bad("refinements must be in [0, 100]", "--refinements");
}

namespace {

// Display values (exposure, clamp, sRGB) of the image box-downsampled (in linear values, which
// keeps the sRGB work small) by an integer factor so that the longer side is at most maxSide
// (but never below minSide per side).
Image displaySmall(const Image& linear, float exposure, int maxSide, int minSide) {
    const int longer = std::max(linear.width(), linear.height());
    int f = maxSide > 0 ? (longer + maxSide - 1) / maxSide : 1;
    while (f > 1 && std::min(linear.width(), linear.height()) / f < minSide) --f;
    DisplayOptions d;
    d.exposure = exposure;
    if (f <= 1) return toDisplay(linear, d);
    const int w = linear.width() / f, h = linear.height() / f;
    Image small(w, h, 3);
    const float inv = 1.0f / float(f * f);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < 3; ++c) {
                float s = 0.0f;
                for (int dy = 0; dy < f; ++dy) {
                    const float* row = linear.row(y * f + dy) + std::size_t(x * f) * 3 + c;
                    for (int dx = 0; dx < f; ++dx) s += row[std::size_t(dx) * 3];
                }
                small(x, y, c) = s * inv;
            }
    return toDisplay(small, d);
}

double meanSquared(const Image& a, const Image& b) {
    double s = 0.0;
    const auto da = a.data(), db = b.data();
    for (std::size_t i = 0; i < da.size(); ++i) {
        const double d = double(da[i]) - db[i];
        s += d * d;
    }
    return da.empty() ? 0.0 : s / double(da.size());
}

}  // namespace

NavigationTree::NavigationTree(const std::vector<const Image*>& images, const TreeOptions& options)
    : m_options(options) {
    validate(options);
    if (images.empty())
        throw Error(ErrorKind::InvalidArgument, "navigation needs at least one image");
    for (const Image* im : images)
        if (!im || !im->sameShape(*images[0]) || im->channels() != 3)
            throw Error(ErrorKind::InvalidArgument,
                        "navigation images must all be 3-channel images of the same size");
    const bool ssim = options.distance == ImageDistance::Ssim;
    if (ssim && (images[0]->width() < 11 || images[0]->height() < 11))
        throw Error(ErrorKind::InvalidArgument,
                    "SSIM distance needs a region of at least 11x11 pixels", {}, "--distance");
    m_memberCount = images.size();
    const std::size_t n = m_memberCount;

    // Downsampled display copies, then every pairwise distance (in parallel).
    std::vector<Image> small(n);
    tbb::parallel_for(std::size_t(0), n, [&](std::size_t i) {
        small[i] = displaySmall(*images[i], options.exposure, options.maxSide, ssim ? 11 : 1);
    });
    m_distances.assign(n * n, 0.0);
    tbb::parallel_for(std::size_t(0), n, [&](std::size_t i) {
        for (std::size_t j = i + 1; j < n; ++j) {
            double d;
            if (ssim) {
                MetricOptions mo;
                mo.linear = true;  // already display values
                d = std::max(0.0, 1.0 - glint::ssim(small[i], small[j], mo).value);
            } else {
                d = meanSquared(small[i], small[j]);
            }
            m_distances[i * n + j] = m_distances[j * n + i] = d;
        }
    });

    // The root holds every member; its representative is their medoid.
    Node root;
    root.members.resize(n);
    std::iota(root.members.begin(), root.members.end(), 0);
    double best = std::numeric_limits<double>::infinity();
    for (int a : root.members) {
        double s = 0.0;
        for (int b : root.members) s += distance(a, b);
        if (s < best) best = s, root.representative = a;
    }
    m_nodes.push_back(std::move(root));
    split(0);
}

void NavigationTree::split(int index) {
    const std::vector<int> members = m_nodes[std::size_t(index)].members;
    const int n = int(members.size());
    const int k = m_options.k;
    if (n <= k) return;  // a leaf: its members are shown one by one

    // 1. k-means++ start (Arthur & Vassilvitskii 2007): the first centre at random, each next
    //    one with probability proportional to its distance to the nearest chosen centre.
    SplitMix64 rng(hash64(m_options.seed, std::uint64_t(index)));
    std::vector<int> centres{members[std::size_t(rng.below(std::uint64_t(n)))]};
    std::vector<double> nearest(std::size_t(n), std::numeric_limits<double>::infinity());
    while (int(centres.size()) < k) {
        double total = 0.0;
        for (int i = 0; i < n; ++i) {
            nearest[std::size_t(i)] = std::min(nearest[std::size_t(i)],
                                               distance(members[std::size_t(i)], centres.back()));
            const bool taken =
                std::find(centres.begin(), centres.end(), members[std::size_t(i)]) != centres.end();
            if (!taken) total += nearest[std::size_t(i)];
        }
        int pick = -1;
        if (total > 0.0) {
            double u = rng.uniformDouble() * total;
            for (int i = 0; i < n && pick < 0; ++i) {
                const int m = members[std::size_t(i)];
                if (std::find(centres.begin(), centres.end(), m) != centres.end()) continue;
                u -= nearest[std::size_t(i)];
                if (u < 0.0) pick = m;
            }
        }
        if (pick < 0)  // identical results (or rounding at the end): any member not yet a centre
            for (int i = 0; i < n && pick < 0; ++i)
                if (std::find(centres.begin(), centres.end(), members[std::size_t(i)]) ==
                    centres.end())
                    pick = members[std::size_t(i)];
        centres.push_back(pick);
    }

    // 2. k-medoids refinements (Voronoi iteration): assign, then move each centre to the member
    //    of its cluster with the smallest summed distance to the others.
    for (int it = 0; it < m_options.refinements; ++it) {
        std::vector<std::vector<int>> clusters(static_cast<std::size_t>(k));
        for (int m : members) {
            int c = 0;
            for (int j = 1; j < k; ++j)
                if (distance(m, centres[std::size_t(j)]) < distance(m, centres[std::size_t(c)]))
                    c = j;
            clusters[std::size_t(c)].push_back(m);
        }
        bool changed = false;
        for (int j = 0; j < k; ++j) {
            const std::vector<int>& cl = clusters[std::size_t(j)];
            if (cl.empty()) continue;
            int bestMember = centres[std::size_t(j)];
            double bestSum = std::numeric_limits<double>::infinity();
            for (int a : cl) {
                double s = 0.0;
                for (int b : cl) s += distance(a, b);
                if (s < bestSum - 1e-15) bestSum = s, bestMember = a;
            }
            if (bestMember != centres[std::size_t(j)] &&
                std::find(centres.begin(), centres.end(), bestMember) == centres.end()) {
                centres[std::size_t(j)] = bestMember;
                changed = true;
            }
        }
        if (!changed) break;
    }

    // 3. Children: the ⌈p·n⌉ members closest to each centre (at most n − 1, so the tree ends).
    const int size = std::min(int(std::ceil(m_options.p * double(n) - 1e-9)), n - 1);
    std::vector<std::vector<int>> kids(static_cast<std::size_t>(k));
    std::vector<int> cover(m_memberCount, 0);
    for (int j = 0; j < k; ++j) {
        std::vector<int> order = members;
        const int c = centres[std::size_t(j)];
        std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
            if (a == c || b == c) return a == c && b != c;
            return distance(a, c) < distance(b, c);
        });
        order.resize(std::size_t(size));
        for (int m : order) ++cover[std::size_t(m)];
        kids[std::size_t(j)] = std::move(order);
    }
    // 4. Reachability: a member no child keeps replaces, in the child of the nearest centre that
    //    can spare one, that child's farthest member also held by another child (k·⌈p·n⌉ >= n
    //    guarantees such a member exists somewhere).
    for (int u : members) {
        if (cover[std::size_t(u)] > 0) continue;
        std::vector<int> byDistance(static_cast<std::size_t>(k));
        std::iota(byDistance.begin(), byDistance.end(), 0);
        std::stable_sort(byDistance.begin(), byDistance.end(), [&](int a, int b) {
            return distance(u, centres[std::size_t(a)]) < distance(u, centres[std::size_t(b)]);
        });
        bool placed = false;
        for (int j : byDistance) {
            std::vector<int>& kid = kids[std::size_t(j)];
            const int c = centres[std::size_t(j)];
            int victim = -1;
            for (int slot = int(kid.size()) - 1; slot >= 0 && victim < 0; --slot)
                if (kid[std::size_t(slot)] != c && cover[std::size_t(kid[std::size_t(slot)])] > 1)
                    victim = slot;
            if (victim < 0) continue;
            --cover[std::size_t(kid[std::size_t(victim)])];
            kid[std::size_t(victim)] = u;
            ++cover[std::size_t(u)];
            placed = true;
            break;
        }
        GLINT_CHECK(placed, "navigation: a member could not be kept (k·p < 1?)");
    }

    const int depth = m_nodes[std::size_t(index)].depth;
    for (int j = 0; j < k; ++j) {
        Node child;
        child.members = std::move(kids[std::size_t(j)]);
        child.representative = centres[std::size_t(j)];
        child.parent = index;
        child.depth = depth + 1;
        const int childIndex = int(m_nodes.size());
        m_nodes.push_back(std::move(child));
        m_nodes[std::size_t(index)].children.push_back(childIndex);
    }
    for (int child : std::vector<int>(m_nodes[std::size_t(index)].children)) split(child);
}

NavigationTree NavigationTree::fromBank(const FilterBank& bank, const TreeOptions& options,
                                        const std::optional<Rect>& region) {
    const Rect r = region.value_or(bank.region());
    if (r.empty() || intersect(r, bank.region()) != r)
        throw Error(ErrorKind::InvalidArgument, "the region is empty or outside the bank's region",
                    {}, "--roi");
    std::vector<Image> crops;
    std::vector<const Image*> images;
    const Rect local{r.x0 - bank.region().x0, r.x1 - bank.region().x0, r.y0 - bank.region().y0,
                     r.y1 - bank.region().y0};
    if (r == bank.region()) {
        for (const Image& im : bank.results()) images.push_back(&im);
        return NavigationTree(images, options);
    }
    crops.reserve(bank.size());
    for (const Image& im : bank.results()) crops.push_back(im.crop(local));
    for (const Image& im : crops) images.push_back(&im);
    return NavigationTree(images, options);
}

Navigator::Navigator(const NavigationTree& tree, std::uint64_t seed)
    : m_tree(&tree), m_path{tree.root()}, m_seed(seed) {}

std::vector<Navigator::Option> Navigator::options() const {
    std::vector<Option> out;
    const NavigationTree::Node& node = m_tree->node(current());
    if (node.children.empty())
        for (int m : node.members) out.push_back({-1, m});
    else
        for (int c : node.children) out.push_back({c, m_tree->node(c).representative});
    return out;
}

void Navigator::choose(int option) {
    if (m_chosen)
        throw Error(ErrorKind::InvalidArgument, "a member is already chosen; go back first");
    const std::vector<Option> opts = options();
    if (option < 0 || option >= int(opts.size()))
        throw Error(ErrorKind::InvalidArgument, "option " + std::to_string(option) +
                                                    " does not exist (there are " +
                                                    std::to_string(opts.size()) + ")");
    const Option& o = opts[std::size_t(option)];
    if (o.node >= 0)
        m_path.push_back(o.node);
    else
        m_chosen = o.member;
}

int Navigator::same() {
    const std::vector<int>& members = m_tree->node(current()).members;
    SplitMix64 rng(hash64(m_seed, ++m_sameCount));
    m_chosen = members[std::size_t(rng.below(members.size()))];
    return *m_chosen;
}

void Navigator::back() {
    if (m_chosen)
        m_chosen.reset();
    else if (m_path.size() > 1)
        m_path.pop_back();
}

void Navigator::restart() {
    m_path.assign(1, m_tree->root());
    m_chosen.reset();
}

}  // namespace glint::denoise

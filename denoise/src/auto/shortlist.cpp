// The shortlist of the automatic selection (shortlist.h; docs/auto.md, "Shortlist").
#include "shortlist.h"

#include <algorithm>
#include <numeric>

#include "choice.h"
#include "glint/image/error.h"

namespace glint::denoise::detail {

std::vector<std::size_t> shortlistOf(const Choice& first, std::size_t size) {
    // By pixels won rather than by total weight, so that a member that wins one region outright
    // is not outranked by members with a little weight everywhere.
    std::vector<std::size_t> order(first.wins.size());
    std::iota(order.begin(), order.end(), std::size_t(0));
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
        const auto& wins = first.wins;
        const auto& totals = first.totals;
        return wins[a] != wins[b] ? wins[a] > wins[b] : totals[a] > totals[b];
    });
    order.resize(size);
    std::sort(order.begin(), order.end());
    return order;
}

}  // namespace glint::denoise::detail

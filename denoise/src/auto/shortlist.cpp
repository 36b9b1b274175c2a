// The shortlist of the automatic selection (shortlist.h; docs/auto.md, "Shortlist").
#include "shortlist.h"

#include <algorithm>
#include <numeric>

#include "choice.h"
#include "glint/denoise/progress.h"
#include "glint/image/error.h"
#include "halves_estimator.h"

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

void filterShortlistOnB(HalvesEstimator& halves, const std::vector<std::size_t>& shortlist,
                        bool keepResults, Estimates& estimates, WorkContext& work,
                        std::int64_t unitsPerMember) {
    if (keepResults)
        for (std::size_t m = 0; m < estimates.maps.size(); ++m)
            if (!std::binary_search(shortlist.begin(), shortlist.end(), m)) halves.dropResults(m);
    const ProgressFn going = [&](double) { return !work.cancelled(); };
    work.parallelFor(
        0, int(shortlist.size()),
        [&](int j) {
            const std::size_t m = shortlist[std::size_t(j)];
            MemberEstimate onB;
            try {
                onB = halves.estimateOnB(m, going);
            } catch (const Error& e) {
                if (e.kind() == ErrorKind::Cancelled) return;
                throw;
            }
            Image& raw = estimates.maps[m];
            const std::size_t pixels = raw.data().size();
            for (std::size_t p = 0; p < pixels; ++p)
                raw.data()[p] = float(0.5 * (double(raw.data()[p]) + double(onB.map.data()[p])));
            // The secant's: the mean of its unbiased form on both sides (A's from the
            // estimation).
            estimates.mapMean[m] = meanPerChannel(raw);
            estimates.estimatedMse[m] = onB.unbiasedMean
                                            ? 0.5 * (estimates.estimatedMse[m] + *onB.unbiasedMean)
                                            : estimates.mapMean[m];
        },
        unitsPerMember);
}

}  // namespace glint::denoise::detail

// The error estimation stage of the automatic selection (estimator.h).
#include "estimator.h"

#include "glint/image/error.h"

namespace glint::denoise::detail {

std::string pixelText(int x, int y) {
    return "pixel (" + std::to_string(x) + ", " + std::to_string(y) + ")";
}

double meanPerChannel(const Image& map) {
    double total = 0.0;
    for (int y = 0; y < map.height(); ++y) {
        double row = 0.0;
        for (int x = 0; x < map.width(); ++x) row += map(x, y, 0);
        total += row;
    }
    return total / double(map.pixelCount()) / 3.0;
}

Estimates estimateMembers(ErrorEstimator& estimator, std::size_t n, WorkContext& work,
                          std::int64_t unitsPerMember) {
    Estimates out;
    out.maps.resize(n);
    out.mapMean.assign(n, 0.0);
    out.estimatedMse.assign(n, 0.0);
    out.analytic.assign(n, 0);
    // Members in parallel, like the bank; a member's filters stop once the work is cancelled.
    const ProgressFn going = [&](double) { return !work.cancelled(); };
    work.parallelFor(
        0, int(n),
        [&](int i) {
            const auto m = std::size_t(i);
            MemberEstimate e;
            try {
                e = estimator.estimate(m, going);
            } catch (const Error& error) {
                if (error.kind() == ErrorKind::Cancelled) return;
                throw;
            }
            out.analytic[m] = e.analytic ? 1 : 0;
            out.mapMean[m] = meanPerChannel(e.map);
            out.estimatedMse[m] = e.unbiasedMean.value_or(out.mapMean[m]);
            out.maps[m] = std::move(e.map);
        },
        unitsPerMember);
    return out;
}

}  // namespace glint::denoise::detail

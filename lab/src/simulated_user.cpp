// The simulated user: walks the navigation tree by the SSIM of each option against the
// reference (glint/lab/simulated_user.h).
#include "glint/lab/simulated_user.h"

#include <cmath>
#include <limits>

#include "glint/image/error.h"
#include "glint/image/metrics.h"

namespace glint::lab {

using denoise::Navigator;

std::vector<SimulatedChoice> simulateUser(const denoise::NavigationTree& tree,
                                          const std::vector<const Image*>& images,
                                          const Image& reference, float exposure) {
    if (images.size() != tree.memberCount())
        throw Error(ErrorKind::InvalidArgument, "simulateUser: one image per tree member");
    MetricOptions mo;
    mo.exposure = exposure;
    std::vector<double> score(images.size(), std::numeric_limits<double>::quiet_NaN());
    auto ssimOf = [&](int m) {
        if (std::isnan(score[std::size_t(m)]))
            score[std::size_t(m)] = glint::ssim(*images[std::size_t(m)], reference, mo).value;
        return score[std::size_t(m)];
    };
    Navigator nav(tree);
    std::vector<SimulatedChoice> steps;
    while (!nav.chosen()) {
        const std::vector<Navigator::Option> opts = nav.options();
        int best = 0;
        for (int i = 1; i < int(opts.size()); ++i)
            if (ssimOf(opts[std::size_t(i)].member) > ssimOf(opts[std::size_t(best)].member))
                best = i;
        steps.push_back(
            {best, opts[std::size_t(best)].member, ssimOf(opts[std::size_t(best)].member)});
        nav.choose(best);
    }
    return steps;
}

}  // namespace glint::lab

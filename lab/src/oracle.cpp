// The oracle measures of a bank against a reference: noisy, best single member, best three with
// a per-pixel choice, per-pixel optimal choice (glint/lab/oracle.h; docs/navigation.md,
// "Research tools").
#include "glint/lab/oracle.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <limits>
#include <numeric>

#include "error_maps.h"
#include "glint/denoise/bank.h"
#include "glint/image/error.h"
#include "glint/image/io.h"
#include "glint/image/metrics.h"

namespace glint::lab {

using denoise::FilterBank;
using detail::errorMap;
using detail::pickComposite;

OracleResult oracle(const FilterBank& bank, const Image& noisy, const Image& reference,
                    float exposure) {
    if (bank.size() < 3)
        throw Error(ErrorKind::InvalidArgument, "the oracle needs a bank of at least 3 members");
    if (noisy.width() != bank.frameWidth() || noisy.height() != bank.frameHeight() ||
        !noisy.sameShape(reference) || noisy.channels() != 3)
        throw Error(
            ErrorKind::InvalidArgument,
            "the input and the reference must be 3-channel images of the bank's frame size (" +
                std::to_string(bank.frameWidth()) + "x" + std::to_string(bank.frameHeight()) + ")");
    const Rect& region = bank.region();
    if (region.width() < 11 || region.height() < 11)
        throw Error(ErrorKind::InvalidArgument,
                    "the bank covers " + std::to_string(region.width()) + "x" +
                        std::to_string(region.height()) +
                        " pixels; the oracle's SSIM needs at least 11x11");
    const Image ref = reference.crop(region);
    MetricOptions mo;
    mo.exposure = exposure;
    DisplayOptions dopt;
    dopt.exposure = exposure;
    const Image refDisplay = toDisplay(ref, dopt);

    OracleResult result;
    result.noisy = ssim(noisy.crop(region), ref, mo).value;

    // Every member's SSIM and error map.
    const std::size_t n = bank.size();
    std::vector<double> single(n), meanError(n);
    std::vector<std::vector<float>> errors(n);
    tbb::parallel_for(std::size_t(0), n, [&](std::size_t m) {
        single[m] = ssim(bank.result(m), ref, mo).value;
        errors[m] = errorMap(toDisplay(bank.result(m), dopt), refDisplay);
        double s = 0.0;
        for (float e : errors[m]) s += e;
        meanError[m] = s / double(errors[m].size());
    });
    result.bestMember = int(std::max_element(single.begin(), single.end()) - single.begin());
    result.bestSingle = single[std::size_t(result.bestMember)];

    // Per-pixel optimal choice over the whole bank.
    const std::size_t pixels = std::size_t(region.width()) * std::size_t(region.height());
    std::vector<int> pick(pixels, 0);
    for (std::size_t p = 0; p < pixels; ++p) {
        float best = std::numeric_limits<float>::infinity();
        for (std::size_t m = 0; m < n; ++m)
            if (errors[m][p] < best) best = errors[m][p], pick[p] = int(m);
    }
    result.perPixel = ssim(pickComposite(bank, pick), ref, mo).value;
    result.choice = Image(region.width(), region.height(), 1);
    for (std::size_t p = 0; p < pixels; ++p) result.choice.data()[p] = float(pick[p]);

    // Best three: exhaustive over triples of the 12 members with the smallest mean error.
    std::vector<int> order(n);
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
        return meanError[std::size_t(a)] < meanError[std::size_t(b)];
    });
    order.resize(std::min<std::size_t>(n, 12));
    std::vector<std::array<int, 3>> triples;
    for (std::size_t a = 0; a < order.size(); ++a)
        for (std::size_t b = a + 1; b < order.size(); ++b)
            for (std::size_t c = b + 1; c < order.size(); ++c)
                triples.push_back({order[a], order[b], order[c]});
    std::vector<double> total(triples.size());
    tbb::parallel_for(std::size_t(0), triples.size(), [&](std::size_t t) {
        const auto& e0 = errors[std::size_t(triples[t][0])];
        const auto& e1 = errors[std::size_t(triples[t][1])];
        const auto& e2 = errors[std::size_t(triples[t][2])];
        double s = 0.0;
        for (std::size_t p = 0; p < pixels; ++p) s += std::min(e0[p], std::min(e1[p], e2[p]));
        total[t] = s;
    });
    const std::size_t bestTriple =
        std::size_t(std::min_element(total.begin(), total.end()) - total.begin());
    result.best3Members = triples[bestTriple];
    for (std::size_t p = 0; p < pixels; ++p) {
        int m = result.best3Members[0];
        for (int j : result.best3Members)
            if (errors[std::size_t(j)][p] < errors[std::size_t(m)][p]) m = j;
        pick[p] = m;
    }
    result.best3 = ssim(pickComposite(bank, pick), ref, mo).value;
    return result;
}

}  // namespace glint::lab

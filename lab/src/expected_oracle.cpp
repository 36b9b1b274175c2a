// The expected-error oracle: the per-pixel choice by each member's error averaged over several
// renders (glint/lab/expected_oracle.h).
#include "glint/lab/expected_oracle.h"

#include <tbb/parallel_for.h>

#include <limits>

#include "error_maps.h"
#include "glint/denoise/prefilter.h"
#include "glint/denoise/registry.h"
#include "glint/image/error.h"
#include "glint/image/io.h"
#include "glint/image/metrics.h"

namespace glint::lab {

using denoise::BankMember;
using denoise::FilterBank;
using denoise::FilterOptions;
using detail::errorMap;
using detail::pickComposite;

ExpectedOracleResult expectedErrorOracle(const FilterBank& bank,
                                         const std::vector<FrameBuffers>& others,
                                         const Image& reference,
                                         const ExpectedOracleOptions& options) {
    if (others.empty())
        throw Error(ErrorKind::InvalidArgument,
                    "the expected-error oracle needs at least one other render of the scene");
    if (options.radii.empty())
        throw Error(ErrorKind::InvalidArgument, "the expected-error oracle needs a radius");
    for (int r : options.radii)
        if (r < 0 || r > 64)
            throw Error(ErrorKind::InvalidArgument,
                        "radius " + std::to_string(r) + " is outside 0 … 64");
    for (std::size_t i = 0; i < others.size(); ++i)
        if (others[i].width() != bank.frameWidth() || others[i].height() != bank.frameHeight())
            throw Error(ErrorKind::InvalidArgument, "other render " + std::to_string(i + 1) +
                                                        " is " + std::to_string(others[i].width()) +
                                                        "x" + std::to_string(others[i].height()) +
                                                        ", not the bank's " +
                                                        std::to_string(bank.frameWidth()) + "x" +
                                                        std::to_string(bank.frameHeight()));
    if (reference.width() != bank.frameWidth() || reference.height() != bank.frameHeight() ||
        reference.channels() != 3)
        throw Error(ErrorKind::InvalidArgument,
                    "the reference must be a 3-channel image of the bank's frame size");
    const Rect& region = bank.region();
    const Image ref = reference.crop(region);
    DisplayOptions dopt;
    dopt.exposure = options.exposure;
    const Image refDisplay = toDisplay(ref, dopt);
    const std::size_t n = bank.size();
    const std::size_t pixels = std::size_t(region.width()) * std::size_t(region.height());
    const double renders = double(others.size() + 1);

    // Each member's error map averaged over the renders (members in parallel: each owns its
    // accumulator, and the renders are added in order, so any thread count gives the same).
    std::vector<Image> expected(n);
    tbb::parallel_for(std::size_t(0), n, [&](std::size_t m) {
        Image sum(region.width(), region.height(), 1);
        auto add = [&](const Image& result) {
            const std::vector<float> e = errorMap(toDisplay(result, dopt), refDisplay);
            for (std::size_t p = 0; p < pixels; ++p) sum.data()[p] += float(e[p] / renders);
        };
        add(bank.result(m));
        const BankMember& member = bank.members()[m];
        const denoise::Filter& filter = denoise::findFilter(member.filter);
        FilterOptions fo;
        fo.region = region;
        for (const FrameBuffers& other : others) {
            const FrameBuffers input =
                options.prefilter ? denoise::prefilterFeatures(other, options.prefilterParams)
                                  : other;
            add(denoise::applyFilter(filter, input, member.params, fo));
        }
        expected[m] = std::move(sum);
    });

    ExpectedOracleResult result;
    result.radii = options.radii;
    result.renders = int(renders);
    MetricOptions mo;
    mo.exposure = options.exposure;
    std::vector<int> pick(pixels, 0);
    for (int radius : options.radii) {
        std::vector<Image> smoothed(n);
        tbb::parallel_for(std::size_t(0), n, [&](std::size_t m) {
            smoothed[m] = detail::boxSmooth(expected[m], radius);
        });
        for (std::size_t p = 0; p < pixels; ++p) {
            float best = std::numeric_limits<float>::infinity();
            for (std::size_t m = 0; m < n; ++m)
                if (smoothed[m].data()[p] < best) best = smoothed[m].data()[p], pick[p] = int(m);
        }
        result.ssim.push_back(ssim(pickComposite(bank, pick), ref, mo).value);
        if (result.choice.empty()) {
            result.choice = Image(region.width(), region.height(), 1);
            for (std::size_t p = 0; p < pixels; ++p) result.choice.data()[p] = float(pick[p]);
        }
    }
    return result;
}

}  // namespace glint::lab

// The oracle measures of a bank against a reference: noisy, best single member, best three with
// a per-pixel choice, per-pixel optimal choice (docs/navigation.md, "Research tools").
#include "glint/denoise/oracle.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <limits>
#include <numeric>

#include "../auto/choice.h"
#include "glint/denoise/auto.h"
#include "glint/denoise/bank.h"
#include "glint/denoise/prefilter.h"
#include "glint/denoise/registry.h"
#include "glint/denoise/research/expected_oracle.h"
#include "glint/image/error.h"
#include "glint/image/io.h"
#include "glint/image/metrics.h"

namespace glint::denoise {

namespace {

// Per-pixel squared display error summed over channels, box-averaged over 3×3 (truncated at
// the border), so the per-pixel choice is not driven by single-pixel noise.
std::vector<float> errorMap(const Image& display, const Image& referenceDisplay) {
    const int w = display.width(), h = display.height();
    std::vector<float> raw(std::size_t(w) * std::size_t(h));
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            float e = 0.0f;
            for (int c = 0; c < 3; ++c) {
                const float d = display(x, y, c) - referenceDisplay(x, y, c);
                e += d * d;
            }
            raw[std::size_t(y) * w + x] = e;
        }
    std::vector<float> out(raw.size());
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            float s = 0.0f;
            int count = 0;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const int xx = x + dx, yy = y + dy;
                    if (xx < 0 || yy < 0 || xx >= w || yy >= h) continue;
                    s += raw[std::size_t(yy) * w + xx];
                    ++count;
                }
            out[std::size_t(y) * w + x] = s / float(count);
        }
    return out;
}

// Composite taking each pixel from the member `pick` says.
Image pickComposite(const FilterBank& bank, const std::vector<int>& pick) {
    const Rect& r = bank.region();
    Image out(r.width(), r.height(), 3);
    for (int y = 0; y < r.height(); ++y)
        for (int x = 0; x < r.width(); ++x) {
            const int m = pick[std::size_t(y) * r.width() + x];
            for (int c = 0; c < 3; ++c) out(x, y, c) = bank.result(std::size_t(m))(x, y, c);
        }
    return out;
}

}  // namespace

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

namespace research {

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
        const Filter& filter = findFilter(member.filter);
        FilterOptions fo;
        fo.region = region;
        for (const FrameBuffers& other : others) {
            const FrameBuffers input =
                options.prefilter ? prefilterFeatures(other, options.prefilterParams) : other;
            add(applyFilter(filter, input, member.params, fo));
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

}  // namespace research

}  // namespace glint::denoise

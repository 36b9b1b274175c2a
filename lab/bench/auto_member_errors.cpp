// Each bank member's halves estimate against its true error, per tile (docs/lab/oidn-gap.md,
// section 4): whether the halves rank the members over a region as their results on all the
// samples rank against the reference.
//   build/bin/auto_member_errors IN.exr BANK REFERENCE.exr [--tile 32]
// IN has half buffers and BANK is its bank folder (glint-denoise bank). Per member and tile,
// display errors summed over RGB, means per pixel:
//   est   the halves estimator's map as the choice reads it (the secant's centred symmetric form,
//         every member filtered on both halves), relative to the median's own error;
//   half  the true error of the member's results on the halves, ½[(D f(A) − D x)² + (D f(B) − D
//   x)²]; full  the true error of its result on all the samples (the bank's), (D f − D x)².
// Prints, for the whole frame, the members by `full` with their rank by `half` and `est`, and for
// the tiles, how often each of the top members is the best by each measure and its advantage over
// the best other member.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "auto/choice.h"
#include "auto/display_weights.h"
#include "auto/halves_estimator.h"
#include "auto/median.h"
#include "auto/options.h"
#include "glint/denoise/auto.h"
#include "glint/denoise/bank.h"
#include "glint/denoise/registry.h"
#include "glint/image/error.h"
#include "glint/image/io.h"

using namespace glint;
using namespace glint::denoise;
namespace dd = glint::denoise::detail;

namespace {

// Per-tile sums of Σ_c (D(f) − D(x))², divided by the tile's pixel count.
std::vector<double> tileErrors(const Image& f, const Image& x, float exposure, int tile) {
    DisplayOptions o;
    o.exposure = exposure;
    const Image df = toDisplay(f, o), dx = toDisplay(x, o);
    const int tw = (f.width() + tile - 1) / tile, th = (f.height() + tile - 1) / tile;
    std::vector<double> sum(std::size_t(tw * th), 0.0), count(sum.size(), 0.0);
    for (int y = 0; y < f.height(); ++y)
        for (int x0 = 0; x0 < f.width(); ++x0) {
            double e = 0.0;
            for (int c = 0; c < 3; ++c) {
                const double d = double(df(x0, y, c)) - double(dx(x0, y, c));
                e += d * d;
            }
            const std::size_t t = std::size_t((y / tile) * tw + x0 / tile);
            sum[t] += e;
            count[t] += 1.0;
        }
    for (std::size_t t = 0; t < sum.size(); ++t) sum[t] /= count[t];
    return sum;
}

std::vector<double> tileMeans(const Image& map, int tile) {
    const int tw = (map.width() + tile - 1) / tile, th = (map.height() + tile - 1) / tile;
    std::vector<double> sum(std::size_t(tw * th), 0.0), count(sum.size(), 0.0);
    for (int y = 0; y < map.height(); ++y)
        for (int x = 0; x < map.width(); ++x) {
            const std::size_t t = std::size_t((y / tile) * tw + x / tile);
            sum[t] += map(x, y, 0);
            count[t] += 1.0;
        }
    for (std::size_t t = 0; t < sum.size(); ++t) sum[t] /= count[t];
    return sum;
}

double mean(const std::vector<double>& v) {
    double s = 0.0;
    for (double x : v) s += x;
    return s / double(v.size());
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 4) {
        std::fprintf(stderr, "usage: auto_member_errors IN.exr BANK REFERENCE.exr [--tile 32]\n");
        return 2;
    }
    int tile = 32;
    for (int i = 4; i + 1 < argc; i += 2)
        if (std::string(argv[i]) == "--tile") tile = std::atoi(argv[i + 1]);
    const FrameBuffers frame = readExr(argv[1]);
    const FilterBank bank = openBank(frame, argv[2]);
    const Image ref = readExr(argv[3]).color();
    AutoOptions options;
    options.estimator = AutoEstimator::Halves;
    options.tuning["shortlist"] = 0;
    options.tuning["stack"] = 0;
    const dd::AutoSettings settings = dd::resolveSettings(bank, frame, options);
    const Image median = dd::bankMedian(bank);
    const std::vector<double> displayMedian = dd::displayOf(median, settings.exposure);
    dd::HalvesEstimator halves(bank, frame, settings, true, &median, &displayMedian, nullptr);
    const Rect region = bank.region();
    GLINT_CHECK(region.x0 == 0 && region.y0 == 0 && region.width() == frame.width() &&
                region.height() == frame.height());
    const std::size_t n = bank.size();
    std::vector<std::vector<double>> est(n), half(n), full(n);
    std::vector<Image> maps(n);
    for (std::size_t m = 0; m < n; ++m) {
        const dd::MemberEstimate e = halves.estimate(m, [](double) { return true; });
        est[m] = tileMeans(e.map, tile);
        maps[m] = e.map;
        // The member's results on each half (the estimator keeps none).
        const BankMember& member = bank.members()[m];
        FilterOptions fo;
        fo.region = region;
        const Filter& filter = findFilter(member.filter);
        const Image onA = applyFilter(filter, halves.halfA(), member.params, fo);
        const Image onB = applyFilter(filter, halves.halfB(), member.params, fo);
        const std::vector<double> a = tileErrors(onA, ref, settings.exposure, tile);
        const std::vector<double> b = tileErrors(onB, ref, settings.exposure, tile);
        half[m].resize(a.size());
        for (std::size_t t = 0; t < a.size(); ++t) half[m][t] = 0.5 * (a[t] + b[t]);
        full[m] = tileErrors(bank.result(m), ref, settings.exposure, tile);
    }
    const auto name = [&](std::size_t m) {
        std::string s = bank.members()[m].filter;
        return s + "#" + std::to_string(m);
    };
    // Whole frame: the members by `full`, with their ranks by `half` and `est`.
    const auto rankBy = [&](const std::vector<std::vector<double>>& v) {
        std::vector<std::size_t> order(n);
        for (std::size_t m = 0; m < n; ++m) order[m] = m;
        std::stable_sort(order.begin(), order.end(),
                         [&](std::size_t i, std::size_t j) { return mean(v[i]) < mean(v[j]); });
        std::vector<std::size_t> rank(n);
        for (std::size_t r = 0; r < n; ++r) rank[order[r]] = r + 1;
        return std::make_pair(order, rank);
    };
    const auto [byFull, rankFull] = rankBy(full);
    const auto [byHalf, rankHalf] = rankBy(half);
    const auto [byEst, rankEst] = rankBy(est);
    std::printf(
        "whole frame (%zu members, tiles of %d): member | full | half | est | rank by "
        "full / half / est\n",
        n, tile);
    for (std::size_t r = 0; r < std::min<std::size_t>(8, n); ++r) {
        const std::size_t m = byFull[r];
        std::printf("  %-22s %.6f %.6f %+.6f  %zu / %zu / %zu\n", name(m).c_str(), mean(full[m]),
                    mean(half[m]), mean(est[m]), rankFull[m], rankHalf[m], rankEst[m]);
    }
    for (std::size_t m = 0; m < n; ++m)
        if (bank.members()[m].filter == "unet" && rankFull[m] > 8)
            std::printf("  %-22s %.6f %.6f %+.6f  %zu / %zu / %zu\n", name(m).c_str(),
                        mean(full[m]), mean(half[m]), mean(est[m]), rankFull[m], rankHalf[m],
                        rankEst[m]);
    // Tiles: how often each measure makes a member the best, and where the best by `full` is the
    // best by the others.
    const std::size_t tiles = full[0].size();
    std::vector<int> winsFull(n, 0), winsHalf(n, 0), winsEst(n, 0);
    int agreeHalf = 0, agreeEst = 0;
    for (std::size_t t = 0; t < tiles; ++t) {
        const auto best = [&](const std::vector<std::vector<double>>& v) {
            std::size_t b = 0;
            for (std::size_t m = 1; m < n; ++m)
                if (v[m][t] < v[b][t]) b = m;
            return b;
        };
        const std::size_t bf = best(full), bh = best(half), be = best(est);
        ++winsFull[bf];
        ++winsHalf[bh];
        ++winsEst[be];
        agreeHalf += bf == bh;
        agreeEst += bf == be;
    }
    std::printf("tiles: %zu; the best by full is the best by half in %d, by est in %d\n", tiles,
                agreeHalf, agreeEst);
    std::printf(
        "  member | tiles won by full / half / est | its mean advantage over the best "
        "other (full / half / est; < 0: better)\n");
    for (std::size_t m = 0; m < n; ++m) {
        if (winsFull[m] == 0 && winsHalf[m] == 0 && winsEst[m] == 0 &&
            bank.members()[m].filter != "unet")
            continue;
        const auto advantage = [&](const std::vector<std::vector<double>>& v) {
            double s = 0.0;
            for (std::size_t t = 0; t < tiles; ++t) {
                double other = 1e300;
                for (std::size_t j = 0; j < n; ++j)
                    if (j != m) other = std::min(other, v[j][t]);
                s += v[m][t] - other;
            }
            return s / double(tiles);
        };
        std::printf("  %-22s %3d / %3d / %3d   %+.6f / %+.6f / %+.6f\n", name(m).c_str(),
                    winsFull[m], winsHalf[m], winsEst[m], advantage(full), advantage(half),
                    advantage(est));
    }
    // The spatial correlation of the map differences the choice's confidence margin reads: for
    // unet against the best other members by `full`, d = map_j − map_unet less its box average
    // over 33² pixels, and the variance inflation b²·Var(mean of b×b blocks)/Var(d) (1 for
    // independent pixels: the margin's sqrt(var/count) is then the standard error).
    std::size_t unet = n;
    for (std::size_t m = 0; m < n; ++m)
        if (bank.members()[m].filter == "unet") unet = m;
    if (unet < n) {
        std::printf("variance inflation of d = map_j - map_unet at blocks 2 / 4 / 8 / 16:\n");
        int shown = 0;
        for (std::size_t r = 0; r < n && shown < 4; ++r) {
            const std::size_t j = byFull[r];
            if (j == unet) continue;
            ++shown;
            const int w = maps[j].width(), h = maps[j].height();
            Image d(w, h, 1);
            for (int y = 0; y < h; ++y)
                for (int x = 0; x < w; ++x) d(x, y, 0) = maps[j](x, y, 0) - maps[unet](x, y, 0);
            const Image trend = dd::boxSmooth(d, 16);
            for (std::size_t p = 0; p < d.data().size(); ++p) d.data()[p] -= trend.data()[p];
            double v = 0.0;
            for (float x : d.data()) v += double(x) * x;
            v /= double(d.data().size());
            std::printf("  %-22s", name(j).c_str());
            for (int b : {2, 4, 8, 16}) {
                double vb = 0.0;
                int blocks = 0;
                for (int y0 = 0; y0 + b <= h; y0 += b)
                    for (int x0 = 0; x0 + b <= w; x0 += b) {
                        double s = 0.0;
                        for (int y = y0; y < y0 + b; ++y)
                            for (int x = x0; x < x0 + b; ++x) s += d(x, y, 0);
                        s /= double(b * b);
                        vb += s * s;
                        ++blocks;
                    }
                vb /= double(blocks);
                std::printf(" %.2f", double(b * b) * vb / v);
            }
            std::printf("\n");
        }
    }
    return 0;
}

// The blend of the automatic selection (blend.h; docs/auto.md, "Blend").
#include "blend.h"

#include <algorithm>

#include "estimator.h"
#include "glint/denoise/bank.h"
#include "glint/denoise/progress.h"

namespace glint::denoise::detail {

std::vector<const Image*> bankResults(const FilterBank& bank) {
    std::vector<const Image*> out(bank.size());
    for (std::size_t m = 0; m < bank.size(); ++m) out[m] = &bank.result(m);
    return out;
}

void blendRow(const std::vector<Image>& planes, const std::vector<const Image*>& results, int y,
              std::vector<double>& sum, int resultsY0) {
    std::fill(sum.begin(), sum.end(), 0.0);
    for (std::size_t m = 0; m < planes.size(); ++m) {
        if (planes[m].empty() || !results[m]) continue;  // no result: weight 0 in these rows
        const float* w = planes[m].row(y);
        const float* value = results[m]->row(y - resultsY0);
        for (int x = 0; x < planes[m].width(); ++x) {
            if (w[x] == 0.0f) continue;
            for (std::size_t k = 0; k < 3; ++k)
                sum[std::size_t(x) * 3 + k] += double(w[x]) * double(value[std::size_t(x) * 3 + k]);
        }
    }
}

Blend blend(const std::vector<Image>& planes, const FilterBank& bank, WorkContext& work) {
    const std::size_t n = planes.size();
    const int width = bank.region().width(), height = bank.region().height();
    // Each member's weight summed over the region (after feathering; rows in order, scaled by
    // 1 / (3 · pixels), which keeps the order and which are 0).
    std::vector<double> totals(n, 0.0);
    for (std::size_t m = 0; m < n; ++m)
        if (!planes[m].empty()) totals[m] = meanPerChannel(planes[m]);
    // The composite (member order, as the weights) and the member of largest weight per pixel.
    Blend out;
    out.composite = Image(width, height, 3);
    out.choice = Image(width, height, 1);
    const std::vector<const Image*> results = bankResults(bank);
    work.parallelFor(0, height, [&](int y) {
        std::vector<double> c(std::size_t(width) * 3);
        blendRow(planes, results, y, c);
        std::vector<float> topWeight(std::size_t(width), 0.0f);
        std::vector<int> top(std::size_t(width), 0);
        for (std::size_t m = 0; m < n; ++m) {
            if (totals[m] == 0.0) continue;  // weight 0 everywhere: never the top
            const float* w = planes[m].row(y);
            for (int x = 0; x < width; ++x)
                if (w[x] > topWeight[std::size_t(x)])
                    topWeight[std::size_t(x)] = w[x], top[std::size_t(x)] = int(m);
        }
        float* row = out.composite.row(y);
        for (std::size_t i = 0; i < c.size(); ++i) row[i] = float(c[i]);
        for (int x = 0; x < width; ++x) out.choice(x, y, 0) = float(top[std::size_t(x)]);
    });
    // The layers: members with any weight, largest total first.
    for (std::size_t m = 0; m < n; ++m)
        if (totals[m] > 0.0) out.order.push_back(int(m));
    std::stable_sort(out.order.begin(), out.order.end(),
                     [&](int a, int b) { return totals[std::size_t(a)] > totals[std::size_t(b)]; });
    return out;
}

}  // namespace glint::denoise::detail

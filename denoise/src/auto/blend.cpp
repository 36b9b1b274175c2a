// The blend of the automatic selection (blend.h; docs/auto.md, "Blend").
#include "blend.h"

#include <algorithm>

#include "estimator.h"
#include "glint/denoise/bank.h"
#include "glint/denoise/progress.h"

namespace glint::denoise::detail {

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

void blendRows(const std::vector<Image>& planes, const std::vector<std::size_t>& used,
               const std::vector<const Image*>& results, int y0, int y1, Image& out, Image* choice,
               WorkContext& work) {
    const int width = out.width();
    work.parallelFor(y0, y1, [&](int y) {
        std::vector<double> c(std::size_t(width) * 3);
        blendRow(planes, results, y, c, y0);
        float* row = out.row(y);
        for (std::size_t i = 0; i < c.size(); ++i) row[i] = float(c[i]);
        if (!choice) return;
        // The member of largest weight (the first of equal ones).
        std::vector<float> topWeight(std::size_t(width), 0.0f);
        std::vector<int> top(std::size_t(width), 0);
        for (std::size_t m : used) {
            const float* w = planes[m].row(y);
            for (int x = 0; x < width; ++x)
                if (w[x] > topWeight[std::size_t(x)])
                    topWeight[std::size_t(x)] = w[x], top[std::size_t(x)] = int(m);
        }
        for (int x = 0; x < width; ++x) (*choice)(x, y, 0) = float(top[std::size_t(x)]);
    });
}

}  // namespace glint::denoise::detail

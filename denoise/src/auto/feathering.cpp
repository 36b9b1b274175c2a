// The feathering of the automatic selection (feathering.h; docs/auto.md, "Feathering").
#include "feathering.h"

#include <cmath>

#include "blend.h"
#include "choice.h"
#include "glint/denoise/bank.h"
#include "glint/denoise/progress.h"
#include "glint/image/display_curve.h"

namespace glint::denoise::detail {

void featherWeights(std::vector<Image>& planes, const FilterBank& bank, int radius, double gate,
                    float exposure, WorkContext& work) {
    std::vector<std::size_t> used;
    for (std::size_t m = 0; m < planes.size(); ++m)
        if (!planes[m].empty()) used.push_back(m);
    if (used.empty()) return;
    const int width = planes[used.front()].width(), height = planes[used.front()].height();
    const DisplayCurve display(std::exp2(double(exposure)));
    // The unfeathered composite in display values (blended as the blend stage blends the final
    // one).
    Image composite(width, height, 3);
    const std::vector<const Image*> results = bankResults(bank);
    work.parallelFor(0, height, [&](int y) {
        std::vector<double> sum(std::size_t(width) * 3);
        blendRow(planes, results, y, sum);
        float* out = composite.row(y);
        for (std::size_t i = 0; i < sum.size(); ++i) out[i] = float(display(sum[i]));
    });
    // Each plane feathered and gated (members in parallel).
    std::vector<Image> feathered(used.size());
    work.parallelFor(
        0, int(used.size()),
        [&](int index) {
            const auto j = std::size_t(index);
            const std::size_t m = used[j];
            Image f = boxSmooth(planes[m], radius);
            for (int y = 0; y < height; ++y) {
                float* w = f.row(y);
                const float* value = bank.result(m).row(y);
                const float* target = composite.row(y);
                for (int x = 0; x < width; ++x) {
                    if (w[x] == 0.0f) continue;
                    for (std::size_t k = 0; k < 3; ++k) {
                        const std::size_t i = std::size_t(x) * 3 + k;
                        if (std::fabs(display(double(value[i])) - double(target[i])) > gate) {
                            w[x] = 0.0f;
                            break;
                        }
                    }
                }
            }
            feathered[j] = std::move(f);
        },
        height);
    // Renormalised per pixel (the members in order).
    work.parallelFor(0, height, [&](int y) { renormaliseRow(planes, used, feathered, y); });
}

void renormaliseRow(std::vector<Image>& planes, const std::vector<std::size_t>& used,
                    const std::vector<Image>& feathered, int y) {
    const int width = planes[used.front()].width();
    for (int x = 0; x < width; ++x) {
        double sum = 0.0;
        for (const Image& f : feathered) sum += f(x, y, 0);
        if (!(sum > 0.0)) {
            // Every member is gated: the members blended here differ by more than the gate from
            // their blend, so the one with the largest weight is taken alone.
            std::size_t top = 0;
            for (std::size_t j = 1; j < used.size(); ++j)
                if (planes[used[j]](x, y, 0) > planes[used[top]](x, y, 0)) top = j;
            for (std::size_t j = 0; j < used.size(); ++j)
                planes[used[j]](x, y, 0) = j == top ? 1.0f : 0.0f;
            continue;
        }
        for (std::size_t j = 0; j < used.size(); ++j)
            planes[used[j]](x, y, 0) = float(double(feathered[j](x, y, 0)) / sum);
    }
}

}  // namespace glint::denoise::detail

// The feathering of the automatic selection (feathering.h; docs/auto.md, "Feathering").
#include "feathering.h"

#include <cmath>

#include "blend.h"
#include "glint/denoise/progress.h"
#include "glint/image/display_curve.h"

namespace glint::denoise::detail {

void featherRows(std::vector<Image>& planes, const std::vector<std::size_t>& used,
                 std::vector<Image>& feathered, const std::vector<const Image*>& results, int y0,
                 int y1, double gate, float exposure, WorkContext& work) {
    if (used.empty()) return;
    const int width = planes[used.front()].width();
    const DisplayCurve display(std::exp2(double(exposure)));
    // The unfeathered composite in display values (blended as the blend stage blends the final
    // one).
    Image target(width, y1 - y0, 3);
    work.parallelFor(y0, y1, [&](int y) {
        std::vector<double> sum(std::size_t(width) * 3);
        blendRow(planes, results, y, sum, y0);
        float* out = target.row(y - y0);
        for (std::size_t i = 0; i < sum.size(); ++i) out[i] = float(display(sum[i]));
    });
    // Each feathered plane gated, then all renormalised per pixel (the members in order).
    work.parallelFor(y0, y1, [&](int y) {
        for (std::size_t j = 0; j < used.size(); ++j) {
            if (!results[used[j]]) continue;  // weight 0 in all these rows
            float* w = feathered[j].row(y);
            const float* value = results[used[j]]->row(y - y0);
            const float* to = target.row(y - y0);
            for (int x = 0; x < width; ++x) {
                if (w[x] == 0.0f) continue;
                for (std::size_t k = 0; k < 3; ++k) {
                    const std::size_t i = std::size_t(x) * 3 + k;
                    if (std::fabs(display(double(value[i])) - double(to[i])) > gate) {
                        w[x] = 0.0f;
                        break;
                    }
                }
            }
        }
        renormaliseRow(planes, used, feathered, y);
    });
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

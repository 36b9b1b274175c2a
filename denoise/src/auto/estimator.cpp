// The error estimators' shared helpers (estimator.h).
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

}  // namespace glint::denoise::detail

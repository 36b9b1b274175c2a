// The soft round brush of the painting session (the thesis's Figure 5.4).
#include <algorithm>
#include <cmath>
#include <string>

#include "glint/denoise/paint.h"
#include "glint/image/error.h"

namespace glint::denoise {

void validate(const Brush& brush) {
    if (!(std::isfinite(brush.size) && brush.size > 0.0 && brush.size <= 1e5))
        throw Error(ErrorKind::InvalidArgument,
                    "brush size " + std::to_string(brush.size) + " must be in (0, 1e5] pixels", {},
                    "brush");
    if (!(brush.softness >= 0.0 && brush.softness <= 1.0))
        throw Error(ErrorKind::InvalidArgument,
                    "brush softness " + std::to_string(brush.softness) + " must be in [0, 1]", {},
                    "brush");
}

float brushWeight(double distance, const Brush& brush) {
    const double outer = 0.5 * brush.size;
    const double inner = brush.softness * outer;
    if (distance >= outer) return 0.0f;
    if (distance <= inner) return 1.0f;
    // Linear fall-off from 1 at the inner radius to 0 at the outer one.
    return float((outer - distance) / (outer - inner));
}

Rect dabRect(double x, double y, const Brush& brush, int width, int height) {
    const double r = 0.5 * brush.size;
    // Pixel i's centre is i + 0.5: the pixels whose centres lie within r of (x, y).
    const double ix0 = std::ceil(x - r - 0.5), ix1 = std::floor(x + r - 0.5) + 1.0;
    const double iy0 = std::ceil(y - r - 0.5), iy1 = std::floor(y + r - 0.5) + 1.0;
    auto clampTo = [](double v, int hi) { return int(std::clamp(v, 0.0, double(hi))); };
    return {clampTo(ix0, width), clampTo(ix1, width), clampTo(iy0, height), clampTo(iy1, height)};
}

}  // namespace glint::denoise

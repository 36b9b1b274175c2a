#include <cmath>

#include "scene/scene_data.h"

namespace glint::render::detail {

Vec3 Texture::lookup(Vec2 uv) const {
    const int w = image.width(), h = image.height();
    // Texel centres at half-integers; v flipped because image rows run top to bottom.
    // Repeat wrapping is applied to uv first, so huge or non-finite coordinates from a mesh never
    // reach the float → integer conversions below (which would be undefined behaviour).
    auto unit = [](float t) { return std::isfinite(t) ? t - std::floor(t) : 0.0f; };
    const float x = unit(uv.x) * float(w) - 0.5f;
    const float y = (1.0f - unit(uv.y)) * float(h) - 0.5f;
    const float fx = std::floor(x), fy = std::floor(y);
    const float tx = x - fx, ty = y - fy;
    auto wrap = [](long i, int n) { return int(((i % n) + n) % n); };
    const int x0 = wrap(long(fx), w), x1 = wrap(long(fx) + 1, w);
    const int y0 = wrap(long(fy), h), y1 = wrap(long(fy) + 1, h);
    auto texel = [&](int xi, int yi) {
        return Vec3{image(xi, yi, 0), image(xi, yi, 1), image(xi, yi, 2)};
    };
    return lerp(ty, lerp(tx, texel(x0, y0), texel(x1, y0)), lerp(tx, texel(x0, y1), texel(x1, y1)));
}

}  // namespace glint::render::detail

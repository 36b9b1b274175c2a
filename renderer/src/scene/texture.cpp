#include <algorithm>
#include <cmath>

#include "scene/scene_data.h"
#include "scene/texture_wrap.h"

namespace glint::render::detail {

namespace {

/// Bilinear lookup of `image` (3 or 4 channels; alpha 1 where it has none); uv origin at the
/// bottom-left.
Vec4 bilinear(const Image& image, Vec2 uv, TextureWrap wrapS, TextureWrap wrapT) {
    const int w = image.width(), h = image.height();
    // Texel centres at half-integers; v flipped because image rows run top to bottom.
    const float x = wrapCoordinate(uv.x, wrapS) * float(w) - 0.5f;
    const float y = (1.0f - wrapCoordinate(uv.y, wrapT)) * float(h) - 0.5f;
    const float fx = floorFast(x), fy = floorFast(y);
    const float tx = x - fx, ty = y - fy;
    const int x0 = wrapIndex(long(fx), w, wrapS), x1 = wrapIndex(long(fx) + 1, w, wrapS);
    const int y0 = wrapIndex(long(fy), h, wrapT), y1 = wrapIndex(long(fy) + 1, h, wrapT);
    const int n = image.channels();
    auto texel = [&](int xi, int yi) {
        const float* p = image.row(yi) + std::size_t(xi) * std::size_t(n);
        return n >= 4 ? Vec4{p[0], p[1], p[2], p[3]} : Vec4{p[0], p[1], p[2], 1.0f};
    };
    // a (1 − t) + b t, as lerp() computes it.
    auto mix = [](float t, const Vec4& a, const Vec4& b) {
        const float s = 1.0f - t;
        return Vec4{a.x * s + b.x * t, a.y * s + b.y * t, a.z * s + b.z * t, a.w * s + b.w * t};
    };
    return mix(ty, mix(tx, texel(x0, y0), texel(x1, y0)), mix(tx, texel(x0, y1), texel(x1, y1)));
}

/// Mean of the first three channels of `image`.
Vec3 meanOf(const Image& image) {
    double sum[3] = {0.0, 0.0, 0.0};
    const int n = image.channels();
    const float* data = image.data().data();
    for (std::size_t i = 0; i < image.pixelCount(); ++i)
        for (int c = 0; c < 3; ++c)
            sum[c] += data[i * std::size_t(n) + std::size_t(std::min(c, n - 1))];
    const double count = std::max<double>(1.0, double(image.pixelCount()));
    return {float(sum[0] / count), float(sum[1] / count), float(sum[2] / count)};
}
}  // namespace

Vec4 Texture::lookup(Vec2 uv, const TexFootprint& footprint) const {
    if (!store) return bilinear(image, uv, wrapS, wrapT);
    // OIIO's t runs down from the top; Glint's v up from the bottom (the filter wraps them, huge
    // and non-finite ones included).
    const float s = uv.x, t = 1.0f - uv.y;
    const TexFootprint st{{footprint.dx.x, -footprint.dx.y}, {footprint.dy.x, -footprint.dy.y}};
    return usableTextureValue(levels.lookup(*store, file, s, t, st, wrapS, wrapT), decodeSrgb);
}

// Flattened (as TextureLevels::lookupOneLevel is): in a unity build, which batches this file with
// texture_levels.cpp and texture_store.cpp, the whole lookup becomes one function.
[[gnu::flatten]] Vec4 Texture::lookupOneLevel(Vec2 uv, const TexFootprint& footprint,
                                              float u) const {
    if (!store) return bilinear(image, uv, wrapS, wrapT);
    const float s = uv.x, t = 1.0f - uv.y;
    const TexFootprint st{{footprint.dx.x, -footprint.dx.y}, {footprint.dy.x, -footprint.dy.y}};
    return usableTextureValue(levels.lookupOneLevel(*store, file, s, t, st, wrapS, wrapT, u),
                              decodeSrgb);
}

void Texture::readLevels() {
    levels = TextureLevels::read(*store, file);
}

Vec3 Texture::meanColour() const {
    if (!store) return meanOf(image);
    const Vec4 m = usableTextureValue(levels.mean(), decodeSrgb);
    return {m.x, m.y, m.z};
}

}  // namespace glint::render::detail

#include <algorithm>
#include <cmath>

#include "scene/scene_data.h"

namespace glint::render::detail {

namespace {
/// A texel index along an axis of n texels under `wrap` (i may be any integer).
int wrapIndex(long i, int n, TextureWrap wrap) {
    switch (wrap) {
        case TextureWrap::Clamp:
            return int(std::clamp<long>(i, 0, n - 1));
        case TextureWrap::Mirror: {
            const long period = 2L * n;
            long k = ((i % period) + period) % period;
            return int(k < n ? k : period - 1 - k);
        }
        case TextureWrap::Repeat:
            break;
    }
    return int(((i % n) + n) % n);
}

/// The coordinate in [0, 1) (repeat, mirror: one period of two) or [0, 1] (clamp) that wrapping
/// maps t to; non-finite coordinates become 0. Wrapping the coordinate before it becomes a
/// texel index keeps huge or non-finite uvs from a mesh out of the float → integer conversion
/// (which would be undefined behaviour).
float wrapCoordinate(float t, TextureWrap wrap) {
    if (!std::isfinite(t)) return 0.0f;
    switch (wrap) {
        case TextureWrap::Clamp:
            return std::clamp(t, -1.0f, 2.0f);
        case TextureWrap::Mirror:
            return t - 2.0f * std::floor(0.5f * t);
        case TextureWrap::Repeat:
            break;
    }
    return t - std::floor(t);
}

/// Bilinear lookup of `image` (3 or 4 channels; alpha 1 where it has none); uv origin at the
/// bottom-left.
Vec4 bilinear(const Image& image, Vec2 uv, TextureWrap wrapS, TextureWrap wrapT) {
    const int w = image.width(), h = image.height();
    // Texel centres at half-integers; v flipped because image rows run top to bottom.
    const float x = wrapCoordinate(uv.x, wrapS) * float(w) - 0.5f;
    const float y = (1.0f - wrapCoordinate(uv.y, wrapT)) * float(h) - 0.5f;
    const float fx = std::floor(x), fy = std::floor(y);
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
    // A footprint of a coarse texel or more: the prefiltered level in memory.
    const float reach = std::max(std::max(std::abs(footprint.dx.x), std::abs(footprint.dx.y)),
                                 std::max(std::abs(footprint.dy.x), std::abs(footprint.dy.y)));
    if (!coarse.empty() && reach * float(std::max(coarse.width(), coarse.height())) >= 1.0f)
        return bilinear(coarse, uv, wrapS, wrapT);
    // OIIO's t runs down from the top; Glint's v up from the bottom. The coordinates are
    // wrapped first so that huge ones stay clear of OIIO's float → integer texel indices.
    const float s = wrapCoordinate(uv.x, wrapS), t = 1.0f - wrapCoordinate(uv.y, wrapT);
    const TexFootprint st{{footprint.dx.x, -footprint.dx.y}, {footprint.dy.x, -footprint.dy.y}};
    return store->lookup(file, s, t, st, wrapS, wrapT, decodeSrgb);
}

void Texture::makeCoarse() {
    const TextureFileInfo& info = store->info(file);
    const int w = std::min(info.width, kCoarseTextureSize);
    const int h = std::min(info.height, kCoarseTextureSize);
    // Each coarse texel is the texture filtered over its square (OIIO picks the MIP level); a
    // texture no larger than the level keeps its own texels.
    const bool whole = w == info.width && h == info.height;
    const TexFootprint square =
        whole ? TexFootprint{} : TexFootprint{{1.0f / float(w), 0.0f}, {0.0f, 1.0f / float(h)}};
    Image level(w, h, 4);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const Vec4 v =
                store->lookup(file, (float(x) + 0.5f) / float(w), (float(y) + 0.5f) / float(h),
                              square, wrapS, wrapT, decodeSrgb);
            level(x, y, 0) = v.x, level(x, y, 1) = v.y, level(x, y, 2) = v.z, level(x, y, 3) = v.w;
        }
    coarse = std::move(level);
}

Vec3 Texture::meanColour() const {
    if (!store) return meanOf(image);
    if (!coarse.empty()) return meanOf(coarse);
    // A footprint of the whole texture: OIIO filters its coarsest MIP level.
    const Vec4 m = lookup({0.5f, 0.5f}, {{1.0f, 0.0f}, {0.0f, 1.0f}});
    return {m.x, m.y, m.z};
}

}  // namespace glint::render::detail

#include "scene/texture_levels.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>

#include <Imath/half.h>

#include "scene/half_float.h"
#include "scene/texture_wrap.h"

namespace glint::render::detail {

namespace {

/// The largest finite half float.
constexpr float kHalfMax = 65504.0f;

/// A footprint axis as the filter takes it: finite and not absurdly large (a grazing hit can
/// give a huge or infinite one; beyond a period the filter is the texture's mean anyway).
Vec2 saneAxis(Vec2 d) {
    auto sane = [](float v) { return std::isfinite(v) ? std::clamp(v, -4.0f, 4.0f) : 0.0f; };
    return {sane(d.x), sane(d.y)};
}

/// How a footprint is filtered: `taps` lookups spaced along `major`, each over a filter of
/// squared width `width2`. At most 8 taps along the long axis, as few as cover it at up to 1.25
/// times the short axis apart, each as wide as the short axis or as their spacing if that is
/// wider (so a footprint of up to 1.25:1 takes one tap as wide as its long axis, and one more
/// than 10 times longer than wide eight taps an eighth of its length wide). In squared lengths:
/// at most one square root (for the tap count), none for an isotropic footprint.
struct FilterPlan {
    Vec2 major;
    int taps = 1;
    float width2 = 0.0f;
};

/// log2(v) for a finite v > 0, within 1.1e-3: the float's exponent plus a cubic in its mantissa
/// m (log2 m ≈ x (a + b x + c x²), x = m − 1, a + b + c = 1 so that it is exact at powers of two
/// and continuous between them; fitted by least squares). It picks MIP levels and their weights,
/// which need no more, at a fraction of libm's log2f (a twentieth of the lookup's time).
float log2Fast(float v) {
    const std::uint32_t bits = std::bit_cast<std::uint32_t>(v);
    const float exponent = float(int(bits >> 23) - 127);
    const float x = std::bit_cast<float>((bits & 0x007fffffu) | 0x3f800000u) - 1.0f;
    constexpr float a = 1.4208645f, b = -0.5772507f, c = 1.0f - a - b;
    return exponent + x * (a + x * (b + x * c));
}

/// The most taps along a footprint's long axis.
constexpr int kMaxTaps = 8;
/// 1 / n² and 1 / n for n taps.
constexpr float kInverseSquares[kMaxTaps + 1] = {0.0f,         1.0f,         1.0f / 4.0f,
                                                 1.0f / 9.0f,  1.0f / 16.0f, 1.0f / 25.0f,
                                                 1.0f / 36.0f, 1.0f / 49.0f, 1.0f / 64.0f};
constexpr float kInverses[kMaxTaps + 1] = {0.0f,        1.0f,        1.0f / 2.0f,
                                           1.0f / 3.0f, 1.0f / 4.0f, 1.0f / 5.0f,
                                           1.0f / 6.0f, 1.0f / 7.0f, 1.0f / 8.0f};

FilterPlan plan(const TexFootprint& footprint) {
    const Vec2 dx = saneAxis(footprint.dx), dy = saneAxis(footprint.dy);
    const float lx2 = dx.x * dx.x + dx.y * dx.y, ly2 = dy.x * dy.x + dy.y * dy.y;
    const float longer2 = std::max(lx2, ly2), shorter2 = std::min(lx2, ly2);
    FilterPlan p;
    p.major = lx2 >= ly2 ? dx : dy;
    if (!(longer2 > 0.0f)) return p;
    // A tap may be up to kSlack times as wide as the short axis (a GPU's anisotropic filter
    // allows as much): a nearly round footprint takes one tap, not two.
    constexpr float kSlack2 = 1.25f * 1.25f;
    // The tap count, ceil(sqrt(ratio2 / kSlack2)) for the squared ratio ratio2 = longer2 /
    // shorter2, capped at kMaxTaps: one more tap for each n² the ratio exceeds, compared without a
    // division or a square root (they were the lookup's longest wait before its texels; a
    // needle-thin footprint, shorter2 = 0, takes them all).
    p.taps = 1;
    for (int n = 1; n < kMaxTaps; ++n) p.taps += longer2 > shorter2 * (kSlack2 * float(n * n));
    p.width2 = std::max(shorter2, longer2 * kInverseSquares[p.taps]);
    return p;
}

}  // namespace

TextureLevels TextureLevels::read(const TextureStore& store, int file) {
    TextureLevels levels;
    const std::vector<std::pair<int, int>> sizes = store.levelSizes(file);
    std::vector<float> rgba;
    levels.m_firstResident = int(sizes.size());
    for (std::size_t m = 0; m < sizes.size(); ++m) {
        Level level;
        level.width = sizes[m].first;
        level.height = sizes[m].second;
        if (std::max(level.width, level.height) <= kResidentTextureSize) {
            if (!store.readLevel(file, int(m), rgba)) return {};
            levels.m_firstResident = std::min(levels.m_firstResident, int(m));
            // Half floats: non-finite values 0 (as the store gives them), the rest within
            // half's range.
            level.texels.resize(rgba.size());
            for (std::size_t i = 0; i < rgba.size(); ++i)
                level.texels[i] =
                    Imath::half(std::isfinite(rgba[i]) ? std::clamp(rgba[i], -kHalfMax, kHalfMax)
                                                       : 0.0f)
                        .bits();
        }
        levels.m_levels.push_back(std::move(level));
    }
    return levels;
}

std::size_t TextureLevels::residentBytes() const {
    std::size_t n = 0;
    for (const Level& level : m_levels) n += level.texels.size() * sizeof(std::uint16_t);
    return n;
}

bool TextureLevels::resident(const TexFootprint& footprint) const {
    if (m_firstResident >= int(m_levels.size())) return false;
    const Level& finest = m_levels[std::size_t(m_firstResident)];
    const float size = float(std::max(finest.width, finest.height));
    return plan(footprint).width2 * (size * size) >= 1.0f;
}

Vec4 TextureLevels::bilinear(const TextureStore& store, int file, int index, float s, float t,
                             TextureWrap wrapS, TextureWrap wrapT, TilePin& pin) const {
    const Level& level = m_levels[std::size_t(index)];
    const int w = level.width, h = level.height;
    // Texel centres at half-integers. (s, t) lies within a few periods of [0, 1] (taps()), so
    // the texel indices are wrapped, not the coordinates.
    const float x = s * float(w) - 0.5f;
    const float y = t * float(h) - 0.5f;
    const float fx = floorFast(x), fy = floorFast(y);
    const float tx = x - fx, ty = y - fy;
    // Inside the level (most lookups) the indices need no wrapping, which divides.
    int x0 = int(fx), x1 = x0 + 1, y0 = int(fy), y1 = y0 + 1;
    if (x0 < 0 || x1 >= w)
        x0 = wrapIndex(long(fx), w, wrapS), x1 = wrapIndex(long(fx) + 1, w, wrapS);
    if (y0 < 0 || y1 >= h)
        y0 = wrapIndex(long(fy), h, wrapT), y1 = wrapIndex(long(fy) + 1, h, wrapT);
    auto mix = [](float u, const Vec4& a, const Vec4& b) {
        const float v = 1.0f - u;
        return Vec4{a.x * v + b.x * u, a.y * v + b.y * u, a.z * v + b.z * u, a.w * v + b.w * u};
    };
    Vec4 q[4];
    if (level.texels.empty()) {
        store.texelQuad(file, index, x0, x1, y0, y1, q, pin);
        return mix(ty, mix(tx, q[0], q[1]), mix(tx, q[2], q[3]));
    }
    const std::uint16_t* rows[2] = {level.texels.data() + std::size_t(y0) * std::size_t(w) * 4,
                                    level.texels.data() + std::size_t(y1) * std::size_t(w) * 4};
    const std::size_t cols[2] = {std::size_t(x0) * 4, std::size_t(x1) * 4};
#if defined(__SSE2__)
    // The same a (1 - t) + b t, four channels at once.
    const __m128 sx = _mm_set1_ps(tx), rx = _mm_set1_ps(1.0f - tx);
    const __m128 top = _mm_add_ps(_mm_mul_ps(halfToFloat4(rows[0] + cols[0]), rx),
                                  _mm_mul_ps(halfToFloat4(rows[0] + cols[1]), sx));
    const __m128 bottom = _mm_add_ps(_mm_mul_ps(halfToFloat4(rows[1] + cols[0]), rx),
                                     _mm_mul_ps(halfToFloat4(rows[1] + cols[1]), sx));
    alignas(16) float v[4];
    _mm_store_ps(v, _mm_add_ps(_mm_mul_ps(top, _mm_set1_ps(1.0f - ty)),
                               _mm_mul_ps(bottom, _mm_set1_ps(ty))));
    return {v[0], v[1], v[2], v[3]};
#else
    for (int k = 0; k < 4; ++k) {
        const std::uint16_t* p = rows[k / 2] + cols[k % 2];
        q[k] = {halfToFloat(p[0]), halfToFloat(p[1]), halfToFloat(p[2]), halfToFloat(p[3])};
    }
    return mix(ty, mix(tx, q[0], q[1]), mix(tx, q[2], q[3]));
#endif
}

TextureLevels::Filter TextureLevels::filterFor(const TexFootprint& footprint) const {
    const FilterPlan p = plan(footprint);
    const Level& finest = m_levels.front();
    // The level whose texel is as wide as the filter, between two levels when it falls there
    // (log2 of the width in texels, from its square); a filter narrower than a texel of the
    // finest level: the finest, bilinearly.
    const float size = float(std::max(finest.width, finest.height));
    const float texels2 = p.width2 * (size * size);
    const float lod = texels2 > 1.0f ? 0.5f * log2Fast(texels2) : 0.0f;
    const int last = int(m_levels.size()) - 1;
    Filter f;
    f.major = p.major;
    f.taps = p.taps;
    f.fine = std::min(int(lod), last);
    f.coarse = std::min(f.fine + 1, last);
    f.blend = f.fine == f.coarse ? 0.0f : std::min(lod - float(f.fine), 1.0f);
    return f;
}

Vec4 TextureLevels::taps(const TextureStore& store, int file, const Filter& f, int level, float s,
                         float t, TextureWrap wrapS, TextureWrap wrapT, TilePin& pin) const {
    // The coordinates wrapped once: the taps lie within a few periods of them (the axes are at
    // most 4 long), where bilinear() wraps the texel indices.
    s = wrapCoordinate(s, wrapS), t = wrapCoordinate(t, wrapT);
    const float inv = kInverses[f.taps];
    Vec4 sum;
    for (int k = 0; k < f.taps; ++k) {
        const float offset = (float(k) + 0.5f) * inv - 0.5f;
        const Vec4 v = bilinear(store, file, level, s + offset * f.major.x, t + offset * f.major.y,
                                wrapS, wrapT, pin);
        sum = {sum.x + v.x, sum.y + v.y, sum.z + v.z, sum.w + v.w};
    }
    return {sum.x * inv, sum.y * inv, sum.z * inv, sum.w * inv};
}

Vec4 TextureLevels::lookup(const TextureStore& store, int file, float s, float t,
                           const TexFootprint& footprint, TextureWrap wrapS,
                           TextureWrap wrapT) const {
    if (m_levels.empty()) return {0.0f, 0.0f, 0.0f, 1.0f};
    const Filter f = filterFor(footprint);
    TilePin pin;
    const Vec4 v = taps(store, file, f, f.fine, s, t, wrapS, wrapT, pin);
    if (!(f.blend > 0.0f)) {
        store.release(pin);
        return v;
    }
    // Trilinear: the taps at both levels, weighed (the same as blending each tap's two).
    const Vec4 c = taps(store, file, f, f.coarse, s, t, wrapS, wrapT, pin);
    store.release(pin);
    const float keep = 1.0f - f.blend;
    return {v.x * keep + c.x * f.blend, v.y * keep + c.y * f.blend, v.z * keep + c.z * f.blend,
            v.w * keep + c.w * f.blend};
}

// Flattened: the plan, the taps and their bilinear lookups inlined into the render's one lookup,
// which took a fifth off the texture path's samples (docs/lab/texture-speed.md, step 9).
[[gnu::flatten]] Vec4 TextureLevels::lookupOneLevel(const TextureStore& store, int file, float s,
                                                    float t, const TexFootprint& footprint,
                                                    TextureWrap wrapS, TextureWrap wrapT,
                                                    float u) const {
    if (m_levels.empty()) return {0.0f, 0.0f, 0.0f, 1.0f};
    const Filter f = filterFor(footprint);
    TilePin pin;
    const Vec4 v = taps(store, file, f, u < f.blend ? f.coarse : f.fine, s, t, wrapS, wrapT, pin);
    store.release(pin);
    return v;
}

Vec4 TextureLevels::mean() const {
    if (m_levels.empty() || m_levels.back().texels.empty()) return {};
    const Level& coarsest = m_levels.back();
    double sum[4] = {0.0, 0.0, 0.0, 0.0};
    const std::size_t texels = coarsest.texels.size() / 4;
    for (std::size_t i = 0; i < texels; ++i)
        for (int c = 0; c < 4; ++c)
            sum[c] += double(halfToFloat(coarsest.texels[i * 4 + std::size_t(c)]));
    const double n = std::max<double>(1.0, double(texels));
    return {float(sum[0] / n), float(sum[1] / n), float(sum[2] / n), float(sum[3] / n)};
}

}  // namespace glint::render::detail

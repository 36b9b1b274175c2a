#include "scene/texture_levels.h"

#include <algorithm>
#include <cmath>

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

/// How a footprint is filtered: `taps` lookups spaced along `major`, each over `width`.
struct FilterPlan {
    Vec2 major;
    int taps = 1;
    float width = 0.0f;
};

/// At most 8 taps along the long axis, each as wide as the short one; a footprint more than 8
/// times longer than wide is widened to an eighth of its length (so the taps still cover it).
FilterPlan plan(const TexFootprint& footprint) {
    const Vec2 dx = saneAxis(footprint.dx), dy = saneAxis(footprint.dy);
    const float lx = std::hypot(dx.x, dx.y), ly = std::hypot(dy.x, dy.y);
    const float longer = std::max(lx, ly), shorter = std::min(lx, ly);
    FilterPlan p;
    p.major = lx >= ly ? dx : dy;
    if (!(longer > 0.0f)) return p;
    constexpr int kMaxTaps = 8;
    const float ratio = shorter > 0.0f ? longer / shorter : float(kMaxTaps);
    p.taps = std::clamp(int(std::ceil(ratio)), 1, kMaxTaps);
    p.width = std::max(shorter, longer / float(kMaxTaps));
    return p;
}

}  // namespace

ResidentLevels ResidentLevels::read(const TextureStore& store, int file) {
    ResidentLevels resident;
    const std::vector<std::pair<int, int>> sizes = store.levelSizes(file);
    std::vector<float> rgba;
    for (std::size_t m = 0; m < sizes.size(); ++m) {
        const auto [w, h] = sizes[m];
        if (std::max(w, h) > kResidentTextureSize) continue;
        if (!store.readLevel(file, int(m), rgba)) return {};
        Level level;
        level.width = w;
        level.height = h;
        // Half floats: non-finite values 0 (as the store gives them), the rest within half's range.
        level.texels.resize(rgba.size());
        for (std::size_t i = 0; i < rgba.size(); ++i)
            level.texels[i] = Imath::half(
                std::isfinite(rgba[i]) ? std::clamp(rgba[i], -kHalfMax, kHalfMax) : 0.0f);
        resident.m_levels.push_back(std::move(level));
    }
    return resident;
}

std::size_t ResidentLevels::bytes() const {
    std::size_t n = 0;
    for (const Level& level : m_levels) n += level.texels.size() * sizeof(Imath::half);
    return n;
}

bool ResidentLevels::covers(const TexFootprint& footprint) const {
    if (m_levels.empty()) return false;
    const Level& finest = m_levels.front();
    return plan(footprint).width * float(std::max(finest.width, finest.height)) >= 1.0f;
}

Vec4 ResidentLevels::bilinear(const Level& level, float s, float t, TextureWrap wrapS,
                              TextureWrap wrapT) const {
    const int w = level.width, h = level.height;
    // Texel centres at half-integers.
    const float x = wrapCoordinate(s, wrapS) * float(w) - 0.5f;
    const float y = wrapCoordinate(t, wrapT) * float(h) - 0.5f;
    const float fx = std::floor(x), fy = std::floor(y);
    const float tx = x - fx, ty = y - fy;
    const int x0 = wrapIndex(long(fx), w, wrapS), x1 = wrapIndex(long(fx) + 1, w, wrapS);
    const int y0 = wrapIndex(long(fy), h, wrapT), y1 = wrapIndex(long(fy) + 1, h, wrapT);
    const Imath::half* texels = level.texels.data();
    auto texel = [&](int xi, int yi) {
        const Imath::half* p = texels + (std::size_t(yi) * std::size_t(w) + std::size_t(xi)) * 4;
        return Vec4{float(p[0]), float(p[1]), float(p[2]), float(p[3])};
    };
    auto mix = [](float u, const Vec4& a, const Vec4& b) {
        const float v = 1.0f - u;
        return Vec4{a.x * v + b.x * u, a.y * v + b.y * u, a.z * v + b.z * u, a.w * v + b.w * u};
    };
    return mix(ty, mix(tx, texel(x0, y0), texel(x1, y0)), mix(tx, texel(x0, y1), texel(x1, y1)));
}

Vec4 ResidentLevels::lookup(float s, float t, const TexFootprint& footprint, TextureWrap wrapS,
                            TextureWrap wrapT) const {
    const FilterPlan p = plan(footprint);
    const Level& finest = m_levels.front();
    // The level whose texel is as wide as the filter, between two levels when it falls there.
    const float lod =
        std::max(0.0f, std::log2(p.width * float(std::max(finest.width, finest.height))));
    const int last = int(m_levels.size()) - 1;
    const int fine = std::min(int(lod), last), coarse = std::min(fine + 1, last);
    const float blend = fine == coarse ? 0.0f : std::min(lod - float(fine), 1.0f);
    Vec4 sum;
    for (int k = 0; k < p.taps; ++k) {
        const float offset = (float(k) + 0.5f) / float(p.taps) - 0.5f;
        const float ks = s + offset * p.major.x, kt = t + offset * p.major.y;
        Vec4 v = bilinear(m_levels[std::size_t(fine)], ks, kt, wrapS, wrapT);
        if (blend > 0.0f) {
            const Vec4 c = bilinear(m_levels[std::size_t(coarse)], ks, kt, wrapS, wrapT);
            const float keep = 1.0f - blend;
            v = {v.x * keep + c.x * blend, v.y * keep + c.y * blend, v.z * keep + c.z * blend,
                 v.w * keep + c.w * blend};
        }
        sum = {sum.x + v.x, sum.y + v.y, sum.z + v.z, sum.w + v.w};
    }
    const float inv = 1.0f / float(p.taps);
    return {sum.x * inv, sum.y * inv, sum.z * inv, sum.w * inv};
}

Vec4 ResidentLevels::mean() const {
    if (m_levels.empty()) return {};
    const Level& coarsest = m_levels.back();
    double sum[4] = {0.0, 0.0, 0.0, 0.0};
    const std::size_t texels = coarsest.texels.size() / 4;
    for (std::size_t i = 0; i < texels; ++i)
        for (int c = 0; c < 4; ++c) sum[c] += double(coarsest.texels[i * 4 + std::size_t(c)]);
    const double n = std::max<double>(1.0, double(texels));
    return {float(sum[0] / n), float(sum[1] / n), float(sum[2] / n), float(sum[3] / n)};
}

}  // namespace glint::render::detail

#include "views/display.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "glint/image/io.h"

namespace glint::studio {

namespace {

constexpr int kLutSize = 4096;

// sRGB encoding of [0, 1] sampled finely enough that neighbouring 8-bit codes never merge.
const std::array<std::uint8_t, kLutSize + 1>& srgbLut() {
    static const auto lut = [] {
        std::array<std::uint8_t, kLutSize + 1> t{};
        for (int i = 0; i <= kLutSize; ++i)
            t[std::size_t(i)] = std::uint8_t(std::lround(255.0f * srgbEncode(float(i) / kLutSize)));
        return t;
    }();
    return lut;
}

inline std::uint8_t encode(float v, DisplayMode mode) {
    if (!(v > 0.0f)) return 0;  // also NaN
    if (v >= 1.0f) return 255;
    if (mode == DisplayMode::Linear) return std::uint8_t(std::lround(v * 255.0f));
    return srgbLut()[std::size_t(v * kLutSize + 0.5f)];
}

}  // namespace

QRgb falseColor(float t) {
    // Control points of a viridis-like ramp (dark blue, blue, teal, green, yellow).
    static constexpr std::array<std::array<float, 3>, 5> kStops{{{0.267f, 0.005f, 0.329f},
                                                                 {0.229f, 0.322f, 0.546f},
                                                                 {0.128f, 0.567f, 0.551f},
                                                                 {0.369f, 0.789f, 0.383f},
                                                                 {0.993f, 0.906f, 0.144f}}};
    if (!(t > 0.0f)) t = 0.0f;
    t = std::min(t, 1.0f);
    const float x = t * float(kStops.size() - 1);
    const int i = std::min(int(x), int(kStops.size()) - 2);
    const float f = x - float(i);
    auto channel = [&](int c) {
        const float v = kStops[std::size_t(i)][std::size_t(c)] * (1.0f - f) +
                        kStops[std::size_t(i + 1)][std::size_t(c)] * f;
        return int(std::lround(v * 255.0f));
    };
    return qRgb(channel(0), channel(1), channel(2));
}

void convertRect(QImage& target, const Image& image, const DisplaySettings& display,
                 const Rect& rect) {
    const Rect r = intersect(rect, image.bounds());
    const float scale = std::exp2(display.exposure);
    const int channels = image.channels();
    const float span =
        display.falseHi > display.falseLo ? 1.0f / (display.falseHi - display.falseLo) : 1.0f;
    for (int y = r.y0; y < r.y1; ++y) {
        const float* src = image.row(y);
        auto* dst = reinterpret_cast<QRgb*>(target.scanLine(y));
        for (int x = r.x0; x < r.x1; ++x) {
            const float* p = src + std::size_t(x) * channels;
            float v[3];
            for (int c = 0; c < 3; ++c)
                v[c] = p[channels == 1 ? 0 : std::min(c, channels - 1)] * scale + display.offset;
            if (display.mode == DisplayMode::FalseColor) {
                // Luminance (Rec. 709) of the exposed values, within the range.
                const float lum =
                    channels == 1 ? v[0] : 0.2126f * v[0] + 0.7152f * v[1] + 0.0722f * v[2];
                dst[x] = falseColor((lum - display.falseLo) * span);
            } else {
                dst[x] = qRgb(encode(v[0], display.mode), encode(v[1], display.mode),
                              encode(v[2], display.mode));
            }
        }
    }
}

std::pair<float, float> luminancePercentiles(const Image& image, const DisplaySettings& display,
                                             double lo, double hi) {
    // Gather the luminances (every pixel, or a grid of about 2^18 of them).
    const std::size_t pixels = std::size_t(image.width()) * std::size_t(image.height());
    const int step =
        pixels > (1u << 18) ? int(std::ceil(std::sqrt(double(pixels) / (1u << 18)))) : 1;
    const float scale = std::exp2(display.exposure);
    const int channels = image.channels();
    std::vector<float> values;
    values.reserve(pixels / std::size_t(step * step) + 1);
    for (int y = 0; y < image.height(); y += step)
        for (int x = 0; x < image.width(); x += step) {
            float v[3];
            for (int c = 0; c < 3; ++c)
                v[c] = image(x, y, channels == 1 ? 0 : std::min(c, channels - 1)) * scale +
                       display.offset;
            const float lum =
                channels == 1 ? v[0] : 0.2126f * v[0] + 0.7152f * v[1] + 0.0722f * v[2];
            if (std::isfinite(lum)) values.push_back(lum);
        }
    if (values.empty()) return {0.0f, 1.0f};
    // The value at fraction p of the sorted ranks, interpolated between neighbours.
    auto at = [&](double p) {
        const double rank = std::clamp(p, 0.0, 1.0) * double(values.size() - 1);
        const auto k = std::size_t(std::floor(rank));
        std::nth_element(values.begin(), values.begin() + std::ptrdiff_t(k), values.end());
        const float a = values[k];
        if (k + 1 >= values.size()) return a;
        const float b = *std::min_element(values.begin() + std::ptrdiff_t(k) + 1, values.end());
        return float(a + (rank - double(k)) * (b - a));
    };
    return {at(lo), at(hi)};
}

QImage toQImage(const Image& image, const DisplaySettings& display) {
    QImage out(image.width(), image.height(), QImage::Format_ARGB32);
    if (image.empty()) return out;
    convertRect(out, image, display, image.bounds());
    return out;
}

QImage maskOverlay(const Image& mask, const QColor& color) {
    QImage out(mask.width(), mask.height(), QImage::Format_ARGB32_Premultiplied);
    for (int y = 0; y < mask.height(); ++y) {
        auto* dst = reinterpret_cast<QRgb*>(out.scanLine(y));
        for (int x = 0; x < mask.width(); ++x) {
            const float m = std::clamp(mask(x, y, 0), 0.0f, 1.0f);
            const int a = int(std::lround(m * float(color.alpha())));
            dst[x] = qPremultiply(qRgba(color.red(), color.green(), color.blue(), a));
        }
    }
    return out;
}

QImage changeOverlay(const Image& change) {
    QImage out(change.width(), change.height(), QImage::Format_ARGB32_Premultiplied);
    for (int y = 0; y < change.height(); ++y) {
        auto* dst = reinterpret_cast<QRgb*>(out.scanLine(y));
        for (int x = 0; x < change.width(); ++x) {
            const float m = std::clamp(change(x, y, 0), 0.0f, 1.0f);
            const bool cyan = ((x / 4) + (y / 4)) % 2 == 0;
            const int a = int(std::lround(m * 220.0f));
            dst[x] = qPremultiply(cyan ? qRgba(0, 255, 255, a) : qRgba(255, 0, 255, a));
        }
    }
    return out;
}

QImage weightOverlay(const Image& weights) {
    QImage out(weights.width(), weights.height(), QImage::Format_ARGB32_Premultiplied);
    for (int y = 0; y < weights.height(); ++y) {
        auto* dst = reinterpret_cast<QRgb*>(out.scanLine(y));
        for (int x = 0; x < weights.width(); ++x) {
            const float w = std::clamp(weights(x, y, 0), 0.0f, 1.0f);
            dst[x] = qPremultiply(qRgba(10, 16, 48, int(std::lround((1.0f - w) * 170.0f))));
        }
    }
    return out;
}

QImage selectionOverlay(const Image& mask) {
    QImage out(mask.width(), mask.height(), QImage::Format_ARGB32_Premultiplied);
    auto in = [&](int x, int y) {
        return x >= 0 && y >= 0 && x < mask.width() && y < mask.height() && mask(x, y, 0) > 0.5f;
    };
    for (int y = 0; y < mask.height(); ++y) {
        auto* dst = reinterpret_cast<QRgb*>(out.scanLine(y));
        for (int x = 0; x < mask.width(); ++x) {
            if (!in(x, y)) {
                dst[x] = 0;
                continue;
            }
            // An edge pixel has a 4-neighbour outside: a dash of 4 black, 4 white.
            const bool edge = !in(x - 1, y) || !in(x + 1, y) || !in(x, y - 1) || !in(x, y + 1);
            dst[x] =
                edge ? (((x + y) / 4) % 2 == 0 ? qRgba(0, 0, 0, 255) : qRgba(255, 255, 255, 255))
                     : qPremultiply(qRgba(0, 220, 255, 70));
        }
    }
    return out;
}

QColor categoryColor(int i) {
    // Hues a golden-ratio turn apart never repeat and stay far apart for the first dozen.
    const double hue = std::fmod(0.13 + 0.618033988749895 * double(i), 1.0);
    return QColor::fromHsvF(float(hue), 0.85f, 0.95f);
}

float normalizeForDisplay(Image& image) {
    const float hi = luminancePercentiles(image, DisplaySettings{}, 0.99, 0.99).second;
    if (!(hi > 0.0f) || !std::isfinite(hi)) return 1.0f;
    for (float& v : image.data()) v /= hi;
    return hi;
}

}  // namespace glint::studio

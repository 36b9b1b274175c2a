// Turning linear images into display values: exposure, clamp, sRGB, false colour, PNG export.
#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <string>
#include <vector>

#include "glint/image/display_curve.h"
#include "glint/image/error.h"
#include "glint/image/io.h"
#include "image_files.h"
#include "other_formats.h"

namespace glint {

namespace {

/// A viridis-like ramp: five stops sampled from matplotlib's viridis at t = 0, 1/4, ..., 1
/// (already display-encoded colours).
constexpr std::array<std::array<float, 3>, 5> kRamp{{
    {0.267f, 0.005f, 0.329f},
    {0.229f, 0.322f, 0.545f},
    {0.128f, 0.567f, 0.551f},
    {0.369f, 0.789f, 0.383f},
    {0.993f, 0.906f, 0.144f},
}};

/// Colour of the ramp at t in [0, 1] by linear interpolation between stops.
std::array<float, 3> ramp(float t) {
    const float s = std::clamp(t, 0.0f, 1.0f) * float(kRamp.size() - 1);
    const int i = std::min(int(s), int(kRamp.size()) - 2);
    const float f = s - float(i);
    std::array<float, 3> out{};
    for (int c = 0; c < 3; ++c) out[c] = kRamp[i][c] + f * (kRamp[i + 1][c] - kRamp[i][c]);
    return out;
}

constexpr std::array<float, 3> kMagenta{1.0f, 0.0f, 1.0f};

}  // namespace

float srgbEncode(float linear) {
    // IEC 61966-2-1 transfer function.
    if (linear <= 0.0031308f) return 12.92f * linear;
    return 1.055f * std::pow(linear, 1.0f / 2.4f) - 0.055f;
}

const double* displayCurveTable() {
    static const std::vector<double> table = [] {
        std::vector<double> values(4097);
        for (std::size_t i = 0; i < values.size(); ++i) {
            const double x = double(i) / 4096.0;
            values[i] = x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1.0 / 2.4) - 0.055;
        }
        return values;
    }();
    return table.data();
}

float srgbDecode(float encoded) {
    // Inverse of IEC 61966-2-1.
    if (encoded <= 0.04045f) return encoded / 12.92f;
    return std::pow((encoded + 0.055f) / 1.055f, 2.4f);
}

bool srgbEncodedFile(const std::string& declaredColorSpace, bool eightBit) {
    const bool srgb =
        declaredColorSpace.size() == 4 &&
        std::equal(declaredColorSpace.begin(), declaredColorSpace.end(), "srgb",
                   [](char a, char b) { return std::tolower((unsigned char)a) == b; });
    return srgb || (declaredColorSpace.empty() && eightBit);
}

Image toDisplay(const Image& linear, const DisplayOptions& options) {
    if (linear.empty()) throw Error(ErrorKind::InvalidArgument, "cannot display an empty image");
    if (!(std::fabs(options.exposure) <= kMaxExposure))
        throw Error(
            ErrorKind::InvalidArgument,
            "exposure must be a number of stops in [-64, 64], got " + numberText(options.exposure));
    const int n = linear.channels();
    const bool falseColor = options.falseColorChannel >= 0;
    if (falseColor) {
        if (options.falseColorChannel >= n)
            throw Error(ErrorKind::InvalidArgument,
                        "false-colour channel " + std::to_string(options.falseColorChannel) +
                            " outside an image with " + std::to_string(n) + " channels");
        if (!(options.falseColorHi > options.falseColorLo))
            throw Error(ErrorKind::InvalidArgument, "false-colour range needs lo < hi, got lo " +
                                                        numberText(options.falseColorLo) + ", hi " +
                                                        numberText(options.falseColorHi));
        if (!std::isfinite(options.falseColorHi - options.falseColorLo))
            throw Error(ErrorKind::InvalidArgument,
                        "false-colour range hi - lo overflows float (at most 3.4e38)");
    }

    const float scale = std::exp2(options.exposure);
    Image out(linear.width(), linear.height(), 3);
    const float* src = linear.data().data();
    float* dst = out.data().data();
    for (std::size_t i = 0; i < linear.pixelCount(); ++i) {
        const float* p = src + i * n;
        std::array<float, 3> rgb{};
        if (falseColor) {
            // False colour: map [lo, hi] of one raw channel onto the ramp.
            const float v = p[options.falseColorChannel];
            rgb = std::isfinite(v) ? ramp((v - options.falseColorLo) /
                                          (options.falseColorHi - options.falseColorLo))
                                   : kMagenta;
        } else {
            // Grey for one channel, R,G,0 for two, the first three otherwise.
            for (int c = 0; c < 3; ++c) rgb[c] = n == 1 ? p[0] : (c < n ? p[c] : 0.0f);
            const bool finite =
                std::all_of(p, p + std::min(n, 3), [](float v) { return std::isfinite(v); });
            if (!finite) {
                rgb = kMagenta;
            } else {
                // Exposure in stops, clamp to [0, 1], then encode.
                for (float& v : rgb) {
                    v = std::clamp(v * scale, 0.0f, 1.0f);
                    if (options.srgb) v = srgbEncode(v);
                }
            }
        }
        std::copy(rgb.begin(), rgb.end(), dst + i * 3);
    }
    return out;
}

void writePng(const Image& linear, const std::filesystem::path& path,
              const DisplayOptions& options) {
    const Image display = toDisplay(linear, options);
    std::vector<unsigned char> bytes(display.data().size());
    const float* src = display.data().data();
    for (std::size_t i = 0; i < bytes.size(); ++i)
        bytes[i] = static_cast<unsigned char>(std::lround(std::clamp(src[i], 0.0f, 1.0f) * 255.0f));

    writeAtomically(path, [&](const std::filesystem::path& tmp) {
        detail::writeOtherFormat8(tmp, path, display.width(), display.height(), {"R", "G", "B"}, -1,
                                  options.srgb ? "sRGB" : "Linear", bytes.data());
    });
}

}  // namespace glint

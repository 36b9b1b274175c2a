// The display transform (exposure, clamp to [0, 1], sRGB) as the automatic selection of the
// denoise module weighs errors with it: in double, from a table with linear interpolation, and its
// slope. toDisplay and srgbEncode (io.h) are the exact curve in float for pictures; this one is
// within 2e-5 of it (1.6e-5 measured against srgbEncode) and costs a table lookup instead of a
// pow per value, which matters in maps evaluated for every member at every pixel and channel.
#pragma once

#include <cmath>
#include <cstddef>

namespace glint {

/// The sRGB encoding (IEC 61966-2-1) at x = i / 4096 for i = 0 … 4096, in double.
const double* displayCurveTable();

/// The display transform of linear values: exposure (a scale 2^stops), clamp to [0, 1], sRGB,
/// from displayCurveTable with linear interpolation.
class DisplayCurve {
  public:
    /// A curve for linear values scaled by `scale` (2^exposure).
    explicit DisplayCurve(double scale) : m_table(displayCurveTable()), m_scale(scale) {}
    /// D(v) in [0, 1].
    double operator()(double v) const {
        const double x = v * m_scale;
        if (!(x > 0.0)) return 0.0;
        if (x >= 1.0) return 1.0;
        const double f = x * 4096.0;
        const auto i = std::size_t(f);
        return m_table[i] + (f - double(i)) * (m_table[i + 1] - m_table[i]);
    }

  private:
    const double* m_table;
    double m_scale;
};

/// Slope of the display transform (exposure in stops, clamp to [0, 1], exact sRGB) at linear
/// value v; 0 where the value is clamped.
inline double displaySlope(double v, float exposure) {
    const double scale = std::exp2(double(exposure));
    const double x = v * scale;
    if (x <= 0.0 || x >= 1.0) return 0.0;
    // Derivative of the sRGB encoding (IEC 61966-2-1).
    const double d = x <= 0.0031308 ? 12.92 : 1.055 / 2.4 * std::pow(x, 1.0 / 2.4 - 1.0);
    return d * scale;
}

}  // namespace glint

// The table-driven display curve and its slope (glint/image/display_curve.h) against the exact
// sRGB encoding of toDisplay (srgbEncode).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "glint/image/display_curve.h"
#include "glint/image/io.h"

namespace glint {
namespace {

TEST(DisplayCurve, IsWithinTwoHundredThousandthsOfTheExactCurveAndClamps) {
    for (double exposure : {0.0, 1.0, -2.0}) {
        const double scale = std::exp2(exposure);
        const DisplayCurve display(scale);
        double worst = 0.0;
        for (int i = 0; i <= 100000; ++i) {
            const double v = 1.2 * double(i) / 100000.0 / scale;
            const double exact = std::clamp(v * scale, 0.0, 1.0);
            const double encoded =
                exact <= 0.0031308 ? 12.92 * exact : 1.055 * std::pow(exact, 1.0 / 2.4) - 0.055;
            worst = std::max(worst, std::abs(display(v) - encoded));
            // toDisplay's curve is the same one in float.
            EXPECT_NEAR(display(v), srgbEncode(float(exact)), 3e-5);
        }
        EXPECT_LT(worst, 2e-5) << "exposure " << exposure;
        EXPECT_EQ(display(-1.0), 0.0);
        EXPECT_EQ(display(std::nan("")), 0.0);
        EXPECT_EQ(display(2.0 / scale), 1.0);
    }
}

TEST(DisplayCurve, SlopeIsTheDerivativeAndZeroWhereClamped) {
    const DisplayCurve display(1.0);
    for (double v : {0.001, 0.01, 0.1, 0.5, 0.9}) {
        const double h = 1e-6;
        const double numeric = (display(v + h) - display(v - h)) / (2.0 * h);
        // The table interpolates linearly over 1/4096: its slope is the curve's within the
        // curvature over one interval.
        EXPECT_NEAR(displaySlope(v, 0.0f), numeric, 0.01 * numeric) << v;
    }
    EXPECT_EQ(displaySlope(-0.1, 0.0f), 0.0);
    EXPECT_EQ(displaySlope(1.5, 0.0f), 0.0);
    // One stop up doubles the slope where the value is not clamped.
    EXPECT_NEAR(displaySlope(0.1, 1.0f), 2.0 * displaySlope(0.2, 0.0f), 1e-12);
}

}  // namespace
}  // namespace glint

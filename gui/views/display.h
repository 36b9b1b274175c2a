// Turning linear images into screen pixels: exposure and offset, then sRGB, linear or false
// colour (tev's display pipeline). Conversions run on any part of an image so that a dab only
// converts the pixels it touched.
#pragma once

#include <QColor>
#include <QImage>

#include <utility>

#include "glint/image/image.h"

namespace glint::studio {

/// How values reach the screen.
enum class DisplayMode { Srgb, Linear, FalseColor };

struct DisplaySettings {
    float exposure = 0.0f;  ///< stops: values are multiplied by 2^exposure
    float offset = 0.0f;    ///< added after the exposure
    DisplayMode mode = DisplayMode::Srgb;
    /// False colour maps luminance (after exposure and offset) in [falseLo, falseHi] to the ramp.
    float falseLo = 0.0f, falseHi = 1.0f;
    /// The canvas sets [falseLo, falseHi] to the 1st–99th percentiles of the image it shows.
    bool autoRange = true;
    bool operator==(const DisplaySettings&) const = default;
};

/// Converts `image` (1 or 3 channels) to an ARGB32 image of its size.
QImage toQImage(const Image& image, const DisplaySettings& display);
/// Converts the pixels of `rect` of `image` into `target` (of the image's size).
void convertRect(QImage& target, const Image& image, const DisplaySettings& display,
                 const Rect& rect);
/// A 1-channel mask as a translucent overlay in `color` (alpha = mask · color.alpha).
QImage maskOverlay(const Image& mask, const QColor& color);
/// The change map's overlay: alpha = change · 220 in a 4-pixel checker of cyan and magenta, a
/// pair that stands out on any material (a red map vanished on a red wall).
QImage changeOverlay(const Image& change);
/// A layer's weights (1 channel in [0, 1]) as an overlay: where the layer does not show, the
/// image is dimmed in dark blue (alpha (1 − w) · 170); where it shows fully, it is untouched.
QImage weightOverlay(const Image& weights);
/// A selection (1 channel, > 0.5 selected): tinted cyan inside, and its edge pixels in a black
/// and white dash (marching ants, still) that shows on any background.
QImage selectionOverlay(const Image& mask);
/// A distinct colour for index `i` of a categorical map (golden-ratio hues, bright).
QColor categoryColor(int i);
/// Divides a statistics image (a variance, a count) by its 99th percentile of luminance so that
/// it reads at EV 0; returns the divisor (1 when the percentile is 0 or not finite).
float normalizeForDisplay(Image& image);
/// The luminance (Rec. 709, after exposure and offset, as false colour maps it) of `image` at
/// percentiles `lo` and `hi` in [0, 1], interpolated linearly between ranks (numpy's default).
/// Images over 2^18 pixels are sampled on a regular grid; non-finite values are skipped.
std::pair<float, float> luminancePercentiles(const Image& image, const DisplaySettings& display,
                                             double lo = 0.01, double hi = 0.99);
/// The false-colour map at t in [0, 1] (a perceptually ordered ramp, dark blue to yellow).
QRgb falseColor(float t);

}  // namespace glint::studio

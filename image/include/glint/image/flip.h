// FLIP, NVIDIA's perceptual difference evaluator (docs/metrics.md, "FLIP"): LDR-FLIP of
// Andersson et al., "FLIP: A Difference Evaluator for Alternating Images", HPG 2020, and HDR-FLIP
// of Andersson et al., "Visualizing Errors in Rendered High Dynamic Range Images", EG 2021.
#pragma once

#include <optional>

#include "glint/image/image.h"

namespace glint {

/// Pixels per degree of visual angle of the papers' default viewer: a 0.7 m wide, 3840-pixel
/// monitor seen from 0.7 m (0.7 * 3840 / 0.7 * pi / 180, about 67.02).
inline constexpr double kFlipDefaultPixelsPerDegree = 0.7 * 3840.0 / 0.7 * 3.14159265358979 / 180.0;

/// The tone mapper HDR-FLIP assumes the viewer would use.
enum class FlipToneMapper { Aces, Hable, Reinhard };

/// How FLIP looks at the images.
struct FlipOptions {
    /// false: LDR-FLIP of linear RGB values in [0, 1]; true: HDR-FLIP of linear radiance.
    bool hdr = false;
    /// Viewing condition; the filters' widths in pixels scale with it.
    double pixelsPerDegree = kFlipDefaultPixelsPerDegree;
    /// HDR only.
    FlipToneMapper toneMapper = FlipToneMapper::Aces;
    /// HDR only: exposure range in stops; unset ends come from the reference (HDR-FLIP, sec. 3).
    std::optional<double> startExposure;
    std::optional<double> stopExposure;
    /// HDR only: number of exposures; 0 means max(2, ceil(stop - start)) as the authors'.
    int exposures = 0;
    /// Restrict to this rectangle (it is then the whole image: filters clamp at its edges).
    std::optional<Rect> crop;
};

/// A FLIP evaluation.
struct FlipResult {
    double mean = 0.0;  ///< mean of `map` over its pixels
    Image map;          ///< per-pixel FLIP error in [0, 1], 1 channel, crop-sized
    /// HDR: the exposures used (first, last, count); LDR: 0, 0, 1.
    double startExposure = 0.0;
    double stopExposure = 0.0;
    int exposures = 1;
};

/// FLIP of `image` against `reference` (3-channel linear RGB, same shape). Throws
/// glint::Error(InvalidArgument) for a shape mismatch, a NaN/Inf value, LDR values outside
/// [0, 1] (HDR data: use options.hdr), a non-positive pixels-per-degree, an exposure range that
/// the reference cannot give (black reference) or start > stop.
FlipResult flip(const Image& image, const Image& reference, const FlipOptions& options = {});

/// The exposure range HDR-FLIP derives from a linear RGB reference (HDR-FLIP, sec. 3): start
/// maps the brightest luminance, stop the median luminance, to 0.85 after tone mapping.
struct FlipExposureRange {
    double start = 0.0;
    double stop = 0.0;
};
FlipExposureRange flipExposureRange(const Image& reference, FlipToneMapper toneMapper);

/// The papers' colour map for an error map: magma (matplotlib, van der Walt and Smith), as
/// linear RGB so that writePng shows the map's sRGB colours. `errors` has 1 channel in [0, 1].
Image flipColorMap(const Image& errors);

}  // namespace glint
